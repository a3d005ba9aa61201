#!/usr/bin/env bash
# The current-Debian test stage: runs a make target of vk-render (default: `make test`) inside a Debian 13
# (trixie) root made from Debian's own packages, so that the whole suite also runs on Mesa 25's lavapipe and
# validation layer 1.4, whose synchronisation validation sees hazards inside a render that Debian 12's
# layer (1.3.239) cannot.
#
# The root is made once with debootstrap and kept in a cache folder ($VK_RENDER_STAGE_CACHE, by default
# /var/cache/vk-render); later runs reuse it. Inside it the project is built with the README's own steps
# (`make test` installs what it needs with apt-get), into target/debian-13 so that the host's build is left
# alone. The project and the Rust toolchain are bound into the root at their own paths, in a private mount
# namespace: every mount goes away with this script, however it ends.
#
# Usage: scripts/stage-current.sh [MAKE-TARGET...]      (root, or sudo)
# Environment: VK_RENDER_STAGE_CACHE (cache folder), VK_RENDER_DEBIAN_MIRROR (a Debian mirror's URL, when
# this machine's apt sources name none).
set -euo pipefail

suite=trixie
stage=debian-13
project=$(cd "$(dirname "$0")/.." && pwd)
cache=${VK_RENDER_STAGE_CACHE:-/var/cache/vk-render}
root="$cache/$stage-root"
# What the root needs before the README's steps can run: make, and certificates for cargo's downloads.
base_packages=make,ca-certificates

if [ "$(id -u)" -ne 0 ]; then
    command -v sudo >/dev/null 2>&1 || { echo "the $stage stage needs root (debootstrap, chroot, mounts)" >&2; exit 1; }
    exec sudo --preserve-env=VK_RENDER_STAGE_CACHE,VK_RENDER_DEBIAN_MIRROR,CARGO_HOME,RUSTUP_HOME,HOME "$0" "$@"
fi

cargo_home=${CARGO_HOME:-$HOME/.cargo}
rustup_home=${RUSTUP_HOME:-$HOME/.rustup}
[ -x "$cargo_home/bin/cargo" ] || {
    echo "the $stage stage runs this machine's Rust toolchain inside the root, but $cargo_home/bin/cargo is missing" >&2
    exit 1
}

# The Debian archive that this machine's apt already uses (its release label is exactly "Debian").
debian_mirror() {
    if [ -n "${VK_RENDER_DEBIAN_MIRROR:-}" ]; then
        echo "$VK_RENDER_DEBIAN_MIRROR"
        return
    fi
    apt-cache policy 2>/dev/null | awk '/ release .*l=Debian,/ { print uri; exit } { uri = $2 }'
}

make_root() {
    "$project/scripts/install-packages.sh" debootstrap
    local mirror
    mirror=$(debian_mirror)
    if [ -z "$mirror" ]; then
        echo "no Debian mirror in this machine's apt sources: set VK_RENDER_DEBIAN_MIRROR to one" >&2
        exit 1
    fi
    echo "Making a Debian 13 ($suite) root in $root from $mirror (once; later runs reuse it)"
    rm -rf "$root.partial"
    mkdir -p "$cache"
    debootstrap --variant=minbase --include="$base_packages" "$suite" "$root.partial" "$mirror" \
        >"$cache/$stage-debootstrap.log" 2>&1 || {
        echo "debootstrap failed; its log: $cache/$stage-debootstrap.log" >&2
        tail -n 20 "$cache/$stage-debootstrap.log" >&2
        exit 1
    }
    # Named only once it is whole: an interrupted debootstrap is never taken for a root.
    mv "$root.partial" "$root"
}

[ -d "$root" ] || make_root

targets=("$@")
[ ${#targets[@]} -gt 0 ] || targets=(test)

# Inside a private mount namespace: bind what the build needs at the paths it has here, then run make.
exec unshare --mount --propagation private /bin/bash -euo pipefail -c '
    root=$1 project=$2 cargo_home=$3 rustup_home=$4 stage=$5
    shift 5
    bind() {
        mkdir -p "$root$1"
        mount --rbind "$1" "$root$1"
    }
    mount -t proc proc "$root/proc"
    bind /dev
    bind "$project"
    bind "$cargo_home"
    bind "$rustup_home"
    cp -L /etc/resolv.conf "$root/etc/resolv.conf"
    # debootstrap writes no /etc/hosts: without it "localhost" is not this machine inside, and chromedriver
    # (which reaches the browser at ws://localhost:PORT) cannot start a session.
    cp -L /etc/hosts "$root/etc/hosts"
    # pip inside (the pyrender benchmark) trusts what this machine trusts: a network may inspect TLS with
    # its own authority, which the root'"'"'s Debian bundle does not hold.
    cp -L /etc/ssl/certs/ca-certificates.crt "$root/etc/ssl/certs/host-ca-certificates.crt"
    mkdir -p "$root/run/user/0" && chmod 700 "$root/run/user/0"
    echo "== $stage stage: make $* in $project"
    exec chroot "$root" /usr/bin/env -i \
        HOME=/root PATH="$cargo_home/bin:/usr/sbin:/usr/bin:/sbin:/bin" \
        CARGO_HOME="$cargo_home" RUSTUP_HOME="$rustup_home" \
        CARGO_TARGET_DIR="$project/target/$stage" XDG_RUNTIME_DIR=/run/user/0 \
        CI="${CI:-}" TERM=dumb DEBIAN_FRONTEND=noninteractive PIP_CERT=/etc/ssl/certs/host-ca-certificates.crt \
        /bin/bash -c "cd \"\$1\" && shift && make \"\$@\"" make "$project" "$@"
' stage "$root" "$project" "$cargo_home" "$rustup_home" "$stage" "${targets[@]}"
