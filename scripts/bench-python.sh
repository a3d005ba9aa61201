#!/usr/bin/env bash
# The Python package against the command line, in one run (scripts/bench_python.py says what is measured
# and what each ratio is asked to be): builds vk-render, installs the package into its venv
# (scripts/python-env.sh), runs the benchmark there.
#
# Usage: scripts/bench-python.sh [--runs N] [--extra N]     (make bench-python)
set -euo pipefail
project=$(cd "$(dirname "$0")/.." && pwd)
cd "$project"
cargo build --release --locked >&2
python=$(scripts/python-env.sh)
"$python" scripts/bench_python.py "$@"
