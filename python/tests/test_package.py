"""The package as an editor and help() see it, and as pip builds it where something is missing."""

import importlib.util
import os
import subprocess
import sys
from pathlib import Path

import vk_render
from conftest import ROOT

PACKAGE = Path(vk_render.__file__).parent


def test_every_public_name_has_a_docstring_and_a_stub():
    stubs = (PACKAGE / "__init__.pyi").read_text() + (PACKAGE / "_native.pyi").read_text()
    assert (PACKAGE / "py.typed").exists()
    for name in vk_render.__all__:
        thing = getattr(vk_render, name)
        assert thing.__doc__ and len(thing.__doc__.strip()) > 20, name
        assert f" {name}" in stubs or f"{name} as {name}" in stubs, name
    for method in ("render", "brdf", "albedo", "check"):
        assert getattr(vk_render.Renderer, method).__doc__, method
    for method in ("load", "from_toml", "with_set", "to_toml"):
        assert getattr(vk_render.Scene, method).__doc__, method


def test_pip_says_what_is_missing_before_it_builds(tmp_path):
    # The build backend (python/build_backend.py) with no cargo on PATH, then no pkg-config.
    (tmp_path / "bin").mkdir()
    probe = (
        "import sys; sys.path.insert(0, sys.argv[1]); import build_backend; "
        "print(build_backend._missing())"
    )
    no_cargo = subprocess.run(
        [sys.executable, "-c", probe, str(ROOT / "python")],
        env={**os.environ, "PATH": str(tmp_path / "bin"), "CARGO": "cargo"}, capture_output=True, text=True,
    )
    assert "cargo is missing" in no_cargo.stdout and "https://rustup.rs" in no_cargo.stdout, no_cargo
    # The backend looks for cargo on PATH and runs nothing: any executable of that name (the tests run
    # without Rust on PATH, scripts/test-python.sh).
    (tmp_path / "bin" / "cargo").write_text("#!/bin/sh\nexit 0\n")
    (tmp_path / "bin" / "cargo").chmod(0o755)
    no_packages = subprocess.run(
        [sys.executable, "-c", probe, str(ROOT / "python")],
        env={**os.environ, "PATH": str(tmp_path / "bin")}, capture_output=True, text=True,
    )
    assert "make setup" in no_packages.stdout and "libshaderc-dev" in no_packages.stdout, no_packages
    # With the packages of `make setup` (pkg-config, c++ and shaderc's libraries on this machine's PATH).
    everything = subprocess.run(
        [sys.executable, "-c", probe, str(ROOT / "python")],
        env={**os.environ, "PATH": f"{tmp_path / 'bin'}:{os.environ['PATH']}"}, capture_output=True, text=True,
    )
    assert everything.stdout.strip() == "None", everything
    assert importlib.util.find_spec("maturin") is not None
