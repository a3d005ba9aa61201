"""The build backend of vk_render: maturin's, after checking what it cannot say plainly itself.

`python3 -m pip install ./python` builds the Rust library and its binding with cargo, which needs the Rust
toolchain and, for the shader compiler (shaderc), the Debian packages that `make setup` installs. Without
them maturin or the linker fails pages later; this says which is missing and how to get it, first.
"""

import os
import shutil
import subprocess

import maturin
from maturin import *  # noqa: F401,F403 (the PEP 517 and PEP 660 hooks, re-exported)

# What shaderc's build links (pkg-config names) and the packages of `make setup` that bring them.
_SHADER_LIBRARIES = ["shaderc", "glslang", "SPIRV-Tools"]
_SETUP_PACKAGES = "libshaderc-dev glslang-dev spirv-tools glslc g++ pkg-config"


def _missing():
    if shutil.which(os.environ.get("CARGO", "cargo")) is None:
        return (
            "vk_render is built from Rust source: cargo is missing. Install the Rust toolchain "
            "(https://rustup.rs), then run pip again."
        )
    if shutil.which("pkg-config") is None or shutil.which("c++") is None:
        return (
            "vk_render needs a C++ compiler and pkg-config to build its shader compiler: run `make setup` in "
            f"the vk-render repository (Debian/Ubuntu packages: {_SETUP_PACKAGES}), then run pip again."
        )
    for library in _SHADER_LIBRARIES:
        found = subprocess.run(["pkg-config", "--exists", library], check=False).returncode == 0
        if not found:
            return (
                f"vk_render needs the shader compiler's libraries ({library} not found by pkg-config): run "
                f"`make setup` in the vk-render repository (Debian/Ubuntu packages: {_SETUP_PACKAGES}), then "
                "run pip again."
            )
    return None


def _checked(hook):
    def build(*args, **kwargs):
        problem = _missing()
        if problem is not None:
            raise SystemExit(f"error: {problem}")
        return hook(*args, **kwargs)

    build.__name__ = hook.__name__
    build.__doc__ = hook.__doc__
    return build


build_wheel = _checked(maturin.build_wheel)
build_editable = _checked(maturin.build_editable)
prepare_metadata_for_build_wheel = _checked(maturin.prepare_metadata_for_build_wheel)
prepare_metadata_for_build_editable = _checked(maturin.prepare_metadata_for_build_editable)
