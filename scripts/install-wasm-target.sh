#!/usr/bin/env bash
# The Rust target the pages' WebAssembly is built for (build.rs builds crates/web/ for it: the library's `.brdf`
# reader, which the explore page's editor runs). Added with rustup when it is missing; quiet when present.
set -euo pipefail
target=wasm32-unknown-unknown
sysroot=$(rustc --print sysroot)
[ -d "$sysroot/lib/rustlib/$target" ] && exit 0
if ! command -v rustup >/dev/null; then
    echo "the Rust target $target is missing, and there is no rustup to add it: install Rust from https://rustup.rs" >&2
    exit 1
fi
echo "Adding the Rust target $target (the pages' WebAssembly)"
rustup target add "$target"
