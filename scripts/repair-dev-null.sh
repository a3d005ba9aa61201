#!/usr/bin/env bash
# Makes /dev/null the null device again where it has become a regular file (a container whose /dev/null was
# removed and then written through by `> /dev/null`). A regular /dev/null hands every reader what others
# wrote there: cargo gives its `rustc -` probes /dev/null as their input, and a CI machine's build failed on
# a build script's probe error read back as Rust source. Silent where /dev/null is a character device.
set -euo pipefail

[ -c /dev/null ] && exit 0
echo "/dev/null is not the null device (it is a $(stat -c %F /dev/null)): making it one again (mknod c 1 3)" >&2
sudo=()
if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null 2>&1 || { echo "repairing /dev/null needs root or sudo" >&2; exit 1; }
    sudo=(sudo)
fi
# Made beside it and renamed over it, so that no moment is without a /dev/null.
"${sudo[@]}" mknod -m 666 /dev/null.vk-render c 1 3
"${sudo[@]}" mv -f /dev/null.vk-render /dev/null
[ -c /dev/null ] || { echo "/dev/null could not be made the null device" >&2; exit 1; }
