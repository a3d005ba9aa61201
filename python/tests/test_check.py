"""vk_render.check is `vk-render check`: the same verdict, mistakes and statistics."""

import re

import numpy as np

import vk_render
from conftest import FIG1, SCENES, cli


def test_the_exact_image_matches_and_a_mistake_is_named(renderer, tmp_path):
    exact = renderer.render(FIG1, width=200, height=130)
    report = vk_render.check(exact, "fig1-lambert", renderer=renderer)
    assert report["matches"] and report["verdict"] == "matches" and report["mistakes"] == []
    assert report["statistics"]["rms"] == 0.0
    assert np.array_equal(report["exact"], exact)

    gamma = renderer.render(FIG1, width=200, height=130, set={"image.encoding": "srgb"})
    vk_render._native.write_png(gamma, tmp_path / "gamma.png")
    report = vk_render.check(tmp_path / "gamma.png", "fig1-lambert", renderer=renderer)
    assert not report["matches"] and report["verdict"] == "mistake"
    assert [m["name"] for m in report["mistakes"]] == ["gamma-applied"]
    assert report["mistakes"][0]["should_be"] == "level = floor(255 clamp(L))"

    # The numbers `vk-render check` prints, to the digits it prints them.
    printed = cli("check", tmp_path / "gamma.png", "--scene", "fig1-lambert", check=False).stdout
    assert "diagnosis: gamma-applied" in printed
    rms, mean, p99 = re.search(r"root mean square ([\d.]+) levels, mean ([\d.]+), p99 ([\d.]+)", printed).groups()
    stats = report["statistics"]
    assert (f"{stats['rms']:.2f}", f"{stats['mean']:.2f}", f"{stats['p99']:.1f}") == (rms, mean, p99)
    regions = re.findall(r"^  (.+?) (lit body|unlit part|highlight|grazing band|open part): root mean square ([\d.]+)",
                         printed, re.MULTILINE)
    assert len(regions) == len(report["regions"])
    assert [f"{r['rms']:.2f}" for r in report["regions"]] == [r[2] for r in regions]


def test_a_wrong_parameter_is_named(renderer):
    """No mistake explains a sphere of the wrong sigma: check names the parameter, as `vk-render check`."""
    scene = SCENES / "fig2-oren-nayar-sigma-0.6.toml"
    mine = renderer.render(scene, width=300, height=200, set={"material.matte.sigma": 0.35})
    report = vk_render.check(mine, scene, renderer=renderer)
    assert report["verdict"] == "unexplained"
    [wrong] = report["wrong_parameters"]
    assert (wrong["object"], wrong["material"], wrong["model"]) == (0, "matte", "oren-nayar")
    # As the server's JSON says it: the scene's float32 0.6 as its shortest decimal.
    assert wrong["scene"] == {"sigma": [0.6]}
    assert abs(wrong["fitted"]["sigma"][0] - 0.35) < 0.02
    assert wrong["residual_levels"] < 1.0 < wrong["scene_levels"]
