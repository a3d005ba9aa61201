"""Every example of the guide's page "Python" (docs/python.md) runs as written, in order, from a folder that
holds the repository's assets (its files land there), and prints what its comments say; so does the Python
example of the README's tour."""

import contextlib
import io
import os
import re
import shutil
import subprocess

import pytest

from conftest import BIN, ROOT

SLURM = "# On a Slurm cluster (not run here)."


def section():
    text = (ROOT / "docs" / "python.md").read_text()
    assert text.startswith("# Python\n")
    return text


def blocks(language, text=None):
    return re.findall(rf"```{language}\n(.*?)```", section() if text is None else text, re.DOTALL)


def test_the_guides_python_examples_run_as_written(tmp_path, monkeypatch):
    pytest.importorskip("matplotlib")
    pytest.importorskip("dask.distributed")
    (tmp_path / "assets").symlink_to(ROOT / "assets")
    monkeypatch.chdir(tmp_path)
    namespace = {}
    examples = [code for code in blocks("python") if not code.startswith(SLURM)]
    assert len(examples) >= 7
    printed = io.StringIO()
    for code in examples:
        with contextlib.redirect_stdout(printed):
            exec(compile(code, "docs/python.md", "exec"), namespace)
    # What the page's comments say each print shows.
    for said in [
        "(400, 600, 3) uint8 [152 152 152]",
        "[0.5968",
        "600 400 ['matte', 'red']",
        "mistake ['gamma-applied']",
        "material.grey.kd = [1.5, 1.5, 1.5]: every component must be in [0, 1]",
        "6 {'material.matte.sigma': 0.0, 'light.0.power': 60} (100, 150, 3)",
        "True grid-tiles/grid-sigma=0.0-power=30.png",
        "brushed (357, 3) float32",
    ]:
        assert said in printed.getvalue(), (said, printed.getvalue())
    assert " True\n" in printed.getvalue()  # the albedo's bound
    assert "oren-nayar" in (tmp_path / "rough.toml").read_text()
    for picture in ("fig1-python.png", "gold-lobe.png"):
        assert (tmp_path / picture).stat().st_size > 10_000
    # The shell example after the Dask one makes the sheet from the tiles the workers wrote.
    sheet = [code for code in blocks("sh") if "vk-render sheet" in code]
    assert len(sheet) == 1
    command = sheet[0].replace("\\\n", " ").replace("vk-render", str(BIN), 1)
    subprocess.run(command, shell=True, check=True, capture_output=True)
    assert (tmp_path / "grid-tiles" / "grid.png").stat().st_size > 10_000
    # The install lines are what `make test` does: the wheel of `make wheel`, installed by pip
    # (scripts/python-env.sh).
    install = blocks("sh")[0]
    assert "make wheel" in install and "python3 -m pip install target/wheels/vk_render-*.whl" in install


def test_the_slurm_example_is_said_not_to_have_run():
    slurm = [code for code in blocks("python") if code.startswith(SLURM)]
    assert len(slurm) == 1 and "SLURMCluster" in slurm[0]
    assert "This was not run here" in section()


def test_the_readmes_tour_runs_as_written(tmp_path, monkeypatch):
    (tmp_path / "assets").symlink_to(ROOT / "assets")
    monkeypatch.chdir(tmp_path)
    examples = blocks("python", (ROOT / "README.md").read_text())
    assert len(examples) == 1
    printed = io.StringIO()
    with contextlib.redirect_stdout(printed):
        exec(compile(examples[0], "README.md", "exec"), {})
    assert "(400, 600, 3) uint8 [152 152 152]" in printed.getvalue(), printed.getvalue()
