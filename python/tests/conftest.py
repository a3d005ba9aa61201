"""What the Python tests share: the repository, the command-line binary they compare with, a renderer with
the validation layer on (any message it reports fails the call, so every test that renders checks it)."""

import os
import subprocess
from pathlib import Path

import numpy as np
import pytest

import vk_render

ROOT = Path(__file__).resolve().parents[2]
SCENES = ROOT / "assets" / "scenes"
FIG1 = SCENES / "fig1-lambert.toml"
BIN = Path(os.environ.get("VK_RENDER_BIN") or Path(os.environ.get("CARGO_TARGET_DIR") or ROOT / "target") / "release" / "vk-render")


def pytest_configure(config):
    config.addinivalue_line(
        "markers",
        "alone: make test runs these alone, after the other tests (scripts/run-tests.sh): they bound how long "
        "something takes, which tests beside them on 2 cores slow past the bound, or hang the device on purpose, "
        "which on a GPU ends in a reset that takes other processes' work with it",
    )


def cli(*args, check=True, **kwargs):
    """Runs `vk-render --validate ARGS` from the repository's root; its CompletedProcess."""
    done = subprocess.run(
        [str(BIN), "--validate", *map(str, args)], cwd=ROOT, capture_output=True, text=True, **kwargs
    )
    if check and done.returncode != 0:
        raise AssertionError(f"vk-render {' '.join(map(str, args))} failed ({done.returncode}):\n{done.stderr}")
    return done


@pytest.fixture(scope="session")
def renderer():
    """One renderer for the session, validating."""
    return vk_render.Renderer(validate=True)


@pytest.fixture(autouse=True)
def validating_default(monkeypatch):
    """The process-wide renderer validates too (made on first use, after this is set)."""
    monkeypatch.setenv("VK_RENDER_VALIDATE", "1")


@pytest.fixture
def in_root(monkeypatch):
    """Runs the test from the repository's root (relative scene paths, as the guide's examples)."""
    monkeypatch.chdir(ROOT)


def hemisphere(count, seed):
    """Random unit directions above the surface (z > 0.05)."""
    rng = np.random.default_rng(seed)
    v = rng.normal(size=(count * 3, 3))
    v /= np.linalg.norm(v, axis=1, keepdims=True)
    v[:, 2] = np.abs(v[:, 2])
    return v[v[:, 2] > 0.05][:count].astype(np.float32)
