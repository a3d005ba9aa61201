#!/usr/bin/env bash
# Makes the Python virtual environment of vk-render's Python tests and benchmark, and installs the package
# from the working tree into it (python3 -m pip install ./python, as the README says), with pytest and
# Dask at pinned versions.
#
# The venv is made once, by default in target/python-venv (ignored by git), and its pins installed once;
# the package itself is built and installed again on every run (cargo rebuilds what changed). stdout is
# only the venv's python, for `python=$(scripts/python-env.sh)`.
#
# Usage: scripts/python-env.sh
# Environment: VK_RENDER_PYTHON_VENV (the venv's folder), PYTHON (the python3 that makes it).
set -euo pipefail

project=$(cd "$(dirname "$0")/.." && pwd)
venv=${VK_RENDER_PYTHON_VENV:-${CARGO_TARGET_DIR:-$project/target}/python-venv}
# Wheels for Debian 12's Python 3.11 and Debian 13's 3.13 alike (matplotlib for the README's examples). maturin builds the package; it is in the
# venv so that the package builds without fetching it again (--no-build-isolation).
pins=(numpy==2.4.6 pytest==9.2.0 dask==2026.8.0 distributed==2026.8.0 matplotlib==3.11.2 maturin==1.16.0)

# python3-venv: `python3 -m venv` with pip (stdout to stderr: this script's stdout is the python's path).
"$project/scripts/install-packages.sh" python3-venv >&2

"$project/scripts/make-venv.sh" "$venv" Python "${pins[@]}"
# The venv's bin first: maturin's build hooks run the maturin command.
(cd "$project" && PATH="$venv/bin:$PATH" "$venv/bin/python" -m pip install -q --disable-pip-version-check --no-build-isolation ./python) >&2 || {
    echo "pip could not build and install ./python into $venv" >&2
    exit 1
}
echo "$venv/bin/python"
