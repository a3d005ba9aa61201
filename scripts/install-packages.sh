#!/usr/bin/env bash
# Installs the Debian packages named as arguments that are not installed yet.
# Idempotent and silent when everything is present; says what to do where apt-get is unavailable.
set -euo pipefail

missing=()
for package in "$@"; do
    if ! dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "install ok installed"; then
        missing+=("$package")
    fi
done
[ ${#missing[@]} -eq 0 ] && exit 0

if ! command -v apt-get >/dev/null 2>&1; then
    echo "vk-render needs these Debian/Ubuntu packages, which are not installed: ${missing[*]}" >&2
    echo "apt-get is not available here: install their equivalents with this system's package manager." >&2
    exit 1
fi
sudo=()
if [ "$(id -u)" -ne 0 ]; then
    if command -v sudo >/dev/null 2>&1; then
        sudo=(sudo)
    else
        echo "vk-render needs these packages: ${missing[*]}; run as root or install sudo." >&2
        exit 1
    fi
fi
echo "Installing missing Debian packages: ${missing[*]}"
"${sudo[@]}" apt-get update -qq
DEBIAN_FRONTEND=noninteractive "${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
