"""Importance sampling from Python: vk_render.sample draws the exact mode's own sampler on the GPU, whose
samples follow their densities (a moment worked by hand), and vk_render.sampling_test gives `vk-render
sampling`'s verdicts and numbers, the same for the same seed."""

import csv

import numpy as np
import pytest

import vk_render
from conftest import ROOT, cli

LAMBERT = {"brdf": "lambert", "kd": 0.5}
GOLD = {"brdf": "cook-torrance", "kd": [1.0, 0.85, 0.57], "f0": [1.0, 0.85, 0.57], "roughness": 0.3, "metalness": 1.0}


def test_a_lambertian_surface_is_drawn_from_the_cosine(renderer):
    directions, pdf = renderer.sample(LAMBERT, [0.0, 0.0, 1.0], 200_000, seed=3)
    assert directions.shape == (200_000, 3) and directions.dtype == np.float32
    assert pdf.shape == (200_000,) and pdf.dtype == np.float32
    np.testing.assert_allclose(np.linalg.norm(directions, axis=1), 1.0, atol=1e-5)
    # The cosine's density cos(theta) / pi at each sample, and E[cos theta] = 2/3 under it (by hand:
    # integral of cos^2 / pi over the hemisphere), within 5 standard errors (sd of cos theta: sqrt(1/18)).
    np.testing.assert_allclose(pdf, directions[:, 2] / np.pi, rtol=1e-5)
    assert abs(directions[:, 2].mean() - 2 / 3) < 5 * np.sqrt(1 / 18 / 200_000)
    # The same seed draws the same samples; another, others.
    again, _ = vk_render.sample(LAMBERT, (0, 0, 1), 1000, seed=3, renderer=renderer)
    np.testing.assert_array_equal(again, directions[:1000])
    other, _ = vk_render.sample(LAMBERT, (0, 0, 1), 1000, seed=4, renderer=renderer)
    assert not np.array_equal(other, directions[:1000])


def test_a_metals_samples_weigh_nearly_fresnel_alone(renderer):
    # GGX's visible normals: f cos / pdf is F G2/G1, between 0 and 1 for gold, never the cosine's spikes.
    wo = [np.sin(np.radians(40)), 0.0, np.cos(np.radians(40))]
    directions, pdf = renderer.sample(GOLD, wo, 20_000)
    above = directions[:, 2] > 0
    f = renderer.brdf(GOLD, directions[above], np.tile(wo, (above.sum(), 1)))
    weight = f[:, 0] * directions[above, 2] / pdf[above]
    assert above.mean() > 0.95 and weight.max() <= 1.0 + 1e-4 and weight.min() >= 0.0


def test_the_sampling_test_is_the_commands(renderer, tmp_path):
    report = vk_render.sampling_test(GOLD, theta_o=[0, 60], samples=200_000, renderer=renderer)
    assert report["passed"] and len(report["views"]) == 2
    view = report["views"][1]
    assert view["histogram"].shape == (40, 160) and view["expected"].shape == (40, 160)
    assert view["histogram"].sum() + view["no_sample"] == 200_000
    assert {v["test"] for v in report["verdicts"]} >= {"chi-square", "estimator", "energy", "reciprocity"}
    # The command's numbers for the same material, views and seed.
    numbers = tmp_path / "views.csv"
    cli("sampling", "assets/analysis/course-materials.toml", "--material", "gold", "--theta-o", "0,60",
        "--samples", "200000", "--csv", numbers)
    rows = list(csv.DictReader(numbers.open()))
    for row, view in zip(rows, report["views"]):
        assert float(row["p_value"]) == pytest.approx(view["p_value"], rel=1e-9)
        assert float(row["estimate_r"]) == pytest.approx(view["estimate"][0], rel=1e-9)


def test_a_broken_sampler_fails_and_bad_arguments_are_named(renderer):
    # The course's Blinn-Phong at s = 0 reflects more than it receives: the energy test fails.
    plastic = {"brdf": "blinn-phong", "kd": 0.35, "ks": 0.15, "shininess": 0.0}
    report = vk_render.sampling_test(plastic, theta_o=[0], samples=100_000, renderer=renderer)
    assert not report["passed"]
    assert [v["test"] for v in report["verdicts"] if not v["passed"]] == ["energy"]
    with pytest.raises(ValueError, match="theta_o: 90"):
        vk_render.sampling_test(plastic, theta_o=[90], renderer=renderer)
    with pytest.raises(ValueError, match="wo"):
        vk_render.sample(plastic, [0, 0, -1], 10, renderer=renderer)
