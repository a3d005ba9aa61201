#!/usr/bin/env bash
# Makes the Python virtual environment of vk-render's Python tests and benchmark, with pytest and Dask at
# pinned versions, and installs the package into it from its wheel, as a user does (docs/python.md: pip
# install the wheel of `make wheel`): the wheel scripts/build-wheel.sh builds, or the one $VK_RENDER_WHEEL
# names (the Debian 13 stage installs the wheel built on Debian 12 so).
#
# The venv is made once, by default in target/python-venv (ignored by git), and its pins installed once;
# the package is installed again on every run. stdout is only the venv's python, for
# `python=$(scripts/python-env.sh)`.
#
# Usage: scripts/python-env.sh
# Environment: VK_RENDER_PYTHON_VENV (the venv's folder), PYTHON (the python3 that makes it), VK_RENDER_WHEEL.
set -euo pipefail

project=$(cd "$(dirname "$0")/.." && pwd)
venv=${VK_RENDER_PYTHON_VENV:-${CARGO_TARGET_DIR:-$project/target}/python-venv}
# Wheels for Debian 12's Python 3.11 and Debian 13's 3.13 alike (matplotlib for the examples of
# docs/python.md; maturin for the test of python/build_backend.py, which builds from source; the export
# formats' own readers for python/tests/test_export.py: pygltflib, MaterialX, Mitsuba 3 and its Dr.Jit).
pins=(numpy==2.4.6 pytest==9.2.0 dask==2026.8.0 distributed==2026.8.0 matplotlib==3.11.2 maturin==1.16.0
    pygltflib==1.16.5 materialx==1.39.5 mitsuba==3.9.1 drjit==1.5.0)

# python3-venv: `python3 -m venv` with pip (stdout to stderr: this script's stdout is the python's path).
"$project/scripts/install-packages.sh" python3-venv >&2

"$project/scripts/make-venv.sh" "$venv" Python "${pins[@]}"
wheel=${VK_RENDER_WHEEL:-$("$project/scripts/build-wheel.sh")}
"$venv/bin/python" -m pip install -q --disable-pip-version-check --force-reinstall --no-deps "$wheel" >&2 || {
    echo "pip could not install $wheel into $venv" >&2
    exit 1
}
echo "$venv/bin/python"
