"""docs/python-api.md is what scripts/python-api.py writes from the installed package's docstrings and its
stubs: the reference cannot drift from the package."""

import subprocess
import sys

from conftest import ROOT


def test_the_api_reference_is_current():
    done = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "python-api.py"), "--check"], capture_output=True, text=True
    )
    assert done.returncode == 0, done.stderr


def test_the_api_reference_names_every_public_name():
    import vk_render

    text = (ROOT / "docs" / "python-api.md").read_text()
    for name in vk_render.__all__:
        assert f"### `vk_render.{name}`" in text, name
