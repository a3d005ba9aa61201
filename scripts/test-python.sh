#!/usr/bin/env bash
# The Python package's tests (make test-python): the package installed from its wheel into the tests' venv
# (scripts/python-env.sh), then pytest with no cargo on PATH, as on a user's machine without Rust. The tests
# compare with the command line's binary already built (python/tests/conftest.py).
#
# Usage: scripts/test-python.sh [PYTEST-ARGUMENTS...]
# Environment: as scripts/python-env.sh (VK_RENDER_WHEEL: the wheel to test instead of building one);
# VK_RENDER_PYTHON: the python of a venv python-env.sh has already made (scripts/run-tests.sh sets it).
set -euo pipefail

project=$(cd "$(dirname "$0")/.." && pwd)
python=${VK_RENDER_PYTHON:-$("$project/scripts/python-env.sh")}

# PATH without any folder that holds cargo.
IFS=: read -ra folders <<<"$PATH"
path=
for folder in "${folders[@]}"; do
    [ -x "$folder/cargo" ] || path=${path:+$path:}$folder
done

cd "$project/python/tests"
# The package the tests import is the installed wheel's, not the source tree's.
PATH=$path "$python" -c '
import sys, sysconfig, vk_render
site = sysconfig.get_paths()["platlib"]
if not vk_render.__file__.startswith(site):
    sys.exit(f"the tests would import vk_render from {vk_render.__file__}, not the wheel in {site}")
print(f"vk_render from {vk_render.__file__}", file=sys.stderr)
'
exec env PATH="$path" "$python" -m pytest -q -p no:cacheprovider "$@"
