#!/usr/bin/env bash
# Makes the Python virtual environment in which scripts/bench_pyrender.py runs pyrender 0.1.45, the OpenGL
# peer of vk-render's benchmark, headless through EGL on Mesa's llvmpipe (PYOPENGL_PLATFORM=egl).
#
# Every package is pinned, so that Debian 12 (Python 3.11) and Debian 13 (Python 3.13) run the same code:
# each pin has wheels for both but PyOpenGL, which is built from its source (pure Python). PyOpenGL stays at
# pyrender's own pin, 3.1.0: its EGL platform works for pyrender's surfaceless EGL context (3.1.0's known
# failures are with OSMesa), and 3.1.10 renders as fast but conflicts with pyrender's requirement. numpy is 2.x
# (1.x has no wheels for Python 3.13); pyrender 0.1.45 uses numpy 1's np.infty only in Mesh.bounds, which
# shadows and the viewer read and the benchmark does not.
#
# The venv is made once, by default in target/pyrender-venv (ignored by git); a later run that finds it made
# with these pins, and pyrender importable, does nothing. stdout is only the venv's python, for
# `python=$(scripts/bench-pyrender-env.sh)`; sourced, the script sets VK_RENDER_PYRENDER_PYTHON instead.
#
# Usage: scripts/bench-pyrender-env.sh      (or: source scripts/bench-pyrender-env.sh)
# Environment: VK_RENDER_PYRENDER_VENV (the venv's folder), PYTHON (the python3 that makes it).

if [[ "${BASH_SOURCE[0]}" != "$0" ]]; then
    # Sourced: run as a child, so that its `set -e` and `exit` stay out of the caller's shell.
    VK_RENDER_PYRENDER_PYTHON=$(bash "${BASH_SOURCE[0]}") || return 1
    export VK_RENDER_PYRENDER_PYTHON
    return 0
fi
set -euo pipefail

project=$(cd "$(dirname "$0")/.." && pwd)
venv=${VK_RENDER_PYRENDER_VENV:-$project/target/pyrender-venv}
pins=(pyrender==0.1.45 PyOpenGL==3.1.0 numpy==2.4.6 scipy==1.17.1 trimesh==5.2.0 pyglet==2.1.19
    pillow==13.0.0 networkx==3.6.1 imageio==2.38.1 freetype-py==2.5.1 six==1.17.0)

# python3-venv: `python3 -m venv` with pip. libegl1: the EGL loader, with Mesa's EGL (libegl-mesa0).
# libgl1: libGL.so.1, the library PyOpenGL 3.1.0 resolves GL functions from (it also pulls libX11, which
# pyglet loads when pyrender imports its viewer). libgl1-mesa-dri: llvmpipe itself.
# (stdout to stderr: this script's stdout is the python's path only.)
"$project/scripts/install-packages.sh" python3-venv libegl1 libgl1 libgl1-mesa-dri >&2

ready() {
    [ -x "$venv/bin/python" ] && [ "$(cat "$venv/vk-render-pins" 2>/dev/null)" = "${pins[*]}" ] &&
        PYOPENGL_PLATFORM=egl "$venv/bin/python" -c 'import pyrender' >/dev/null 2>&1
}

if ! ready; then
    # A venv whose pins are right but whose pyrender does not import is made anew.
    rm -f "$venv/vk-render-pins"
    "$project/scripts/make-venv.sh" "$venv" pyrender "${pins[@]}"
    ready || {
        echo "pyrender does not import in $venv; see: PYOPENGL_PLATFORM=egl $venv/bin/python -c 'import pyrender'" >&2
        exit 1
    }
fi
echo "$venv/bin/python"
