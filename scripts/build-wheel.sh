#!/usr/bin/env bash
# Builds the Python package's wheel, target/wheels/vk_render-VERSION-cp39-abi3-manylinux_2_N_x86_64.whl: one
# wheel for every CPython from 3.9 on (abi3), which pip installs where there is neither Rust nor a build
# package. The shader compiler (shaderc) is linked in statically and Vulkan is loaded at run time, so what
# the extension needs of the system is glibc, libstdc++ and libgcc_s: maturin gives the wheel the oldest
# manylinux tag those symbol versions allow and refuses to build one that breaks it (--auditwheel check),
# and auditwheel's own reading of the wheel must agree with the tag.
#
# The build tools (maturin, auditwheel) live in a venv made once, target/wheel-tools-venv. stdout is only
# the wheel's path, for `wheel=$(scripts/build-wheel.sh)`; everything else goes to stderr.
#
# Usage: scripts/build-wheel.sh
set -euo pipefail

project=$(cd "$(dirname "$0")/.." && pwd)
target=${CARGO_TARGET_DIR:-$project/target}
venv=$target/wheel-tools-venv
out=$target/wheels

"$project/scripts/install-packages.sh" python3-venv >&2
"$project/scripts/make-venv.sh" "$venv" "wheel tools" maturin==1.16.0 auditwheel==6.8.2

# Only this build's wheel in the folder, so that target/wheels/vk_render-*.whl names one file.
rm -f "$out"/vk_render-*.whl
(cd "$project/python" && "$venv/bin/maturin" build --release --locked --auditwheel check --out "$out") >&2 || {
    echo "maturin could not build the wheel" >&2
    exit 1
}
wheels=("$out"/vk_render-*.whl)
[ ${#wheels[@]} -eq 1 ] && [ -f "${wheels[0]}" ] || {
    echo "expected one wheel in $out, found: ${wheels[*]}" >&2
    exit 1
}
wheel=${wheels[0]}

# The tag maturin gave (the last field of the name) against the one auditwheel finds the wheel consistent
# with: auditwheel names the most compatible tag, so its glibc version must be at most the wheel's.
tag=$(basename "$wheel" .whl)
tag=${tag##*-}
shown=$("$venv/bin/auditwheel" show "$wheel" 2>&1 | tr '\n' ' ')
consistent=$(grep -oE 'platform tag: +"manylinux_[0-9]+_[0-9]+_x86_64"' <<<"$shown" | grep -oE 'manylinux_[0-9]+_[0-9]+_x86_64' || true)
glibc() { sed -E 's/^manylinux_([0-9]+)_([0-9]+)_.*/\1 \2/' <<<"$1"; }
if [[ $tag != manylinux_*_x86_64 ]] || [ -z "$consistent" ]; then
    echo "the wheel's tag is $tag and auditwheel finds it consistent with ${consistent:-no manylinux tag}: $shown" >&2
    exit 1
fi
read -r tag_major tag_minor <<<"$(glibc "$tag")"
read -r needs_major needs_minor <<<"$(glibc "$consistent")"
if (( needs_major > tag_major || (needs_major == tag_major && needs_minor > tag_minor) )); then
    echo "the wheel is tagged $tag but needs $consistent (auditwheel): $shown" >&2
    exit 1
fi
echo "wheel: $wheel ($tag; auditwheel: consistent with $consistent)" >&2
echo "$wheel"
