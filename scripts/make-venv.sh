#!/usr/bin/env bash
# Makes a Python virtual environment with pinned packages, once: `scripts/make-venv.sh VENV WHAT PIN...`
# does nothing when VENV was made with exactly these pins (recorded in VENV/vk-render-pins), else makes it
# anew with `${PYTHON:-python3} -m venv` (Debian's python3-venv) and installs them. WHAT names it in
# messages. Everything it prints goes to stderr. Used by the pyrender benchmark's and the Python tests' venvs.
set -euo pipefail
venv=$1 what=$2
shift 2
pins=("$@")
if [ -x "$venv/bin/python" ] && [ "$(cat "$venv/vk-render-pins" 2>/dev/null)" = "${pins[*]}" ]; then
    exit 0
fi
echo "Making the $what venv in $venv (once; later runs reuse it)" >&2
rm -rf "$venv"
"${PYTHON:-python3}" -m venv "$venv" >&2 || {
    echo "${PYTHON:-python3} -m venv failed: is python3-venv installed?" >&2
    exit 1
}
"$venv/bin/python" -m pip install -q --disable-pip-version-check "${pins[@]}" >&2 || {
    echo "pip could not install ${pins[*]} into $venv" >&2
    exit 1
}
echo "${pins[*]}" >"$venv/vk-render-pins"
