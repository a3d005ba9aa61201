"""Analytic BRDFs (BRDF Explorer's .brdf files) from Python: a material dict naming a file, on the GPU against
the shipped model's Rust mirror, renders and sweeps over a file's parameters as the command line makes them,
bad values as SceneError, a model's invalid values as a SceneWarning, a BRDF that outlasts the timeout as
DeviceError."""

import subprocess
import sys

import numpy as np
import pytest

import vk_render
from conftest import ROOT, cli, hemisphere

WARD = {
    "brdf": "analytic",
    "file": str(ROOT / "assets" / "brdfs" / "ward.brdf"),
    "params": {"rho_d": [0.2, 0.1, 0.05], "rho_s": 0.5, "alpha_x": 0.08, "alpha_y": 0.4},
}

SPHERE = """[image]
width = 64
height = 48
samples = 1
[[light]]
position = [2.0, 2.0, -1.0]
power = 40.0
[material.m]
brdf = "analytic"
file = "{file}"
[[object]]
shape = "sphere"
center = [0.0, 0.0, 3.0]
radius = 1.0
material = "m"
"""


def test_a_files_brdf_on_the_gpu_is_its_rust_mirror(renderer):
    wi, wo = hemisphere(400, 3), hemisphere(400, 4)
    gpu = renderer.brdf(WARD, wi, wo)
    mirror = vk_render._native.brdf_mirror(WARD, wi, wo)
    assert gpu.shape == (400, 3) and gpu.max() > 0
    np.testing.assert_allclose(gpu, mirror, rtol=2e-4, atol=1e-6)
    # Mirrored at 30 degrees (H = N): rho_d / pi + rho_s / (4 pi alpha_x alpha_y cos 30).
    s, c = 0.5, 3 ** 0.5 / 2
    f = renderer.brdf(WARD, [s, 0.0, c], [-s, 0.0, c])
    expected = np.array([0.2, 0.1, 0.05]) / np.pi + 0.5 / (4 * np.pi * 0.08 * 0.4 * c)
    np.testing.assert_allclose(f[0], expected, rtol=1e-4)


def test_a_file_without_a_mirror_is_refused_by_the_mirror(renderer, tmp_path):
    copy = tmp_path / "ward.brdf"
    copy.write_text((ROOT / "assets" / "brdfs" / "ward.brdf").read_text() + "\n# an edited copy\n")
    material = {**WARD, "file": str(copy)}
    assert renderer.brdf(material, [0.0, 0.0, 1.0], [0.0, 0.0, 1.0]).shape == (1, 3)
    with pytest.raises(ValueError, match="no Rust mirror"):
        vk_render._native.brdf_mirror(material, np.array([[0, 0, 1]], np.float32), np.array([[0, 0, 1]], np.float32))


def scene_file(tmp_path, brdf):
    (tmp_path / "m.brdf").write_text(brdf)
    path = tmp_path / "scene.toml"
    path.write_text(SPHERE.format(file="m.brdf"))
    return path


def test_render_and_set_take_a_files_parameters_as_the_command_line(renderer, tmp_path):
    scene = tmp_path / "scene.toml"
    scene.write_text(SPHERE.format(file=WARD["file"]))
    image = renderer.render(scene, set={"material.m.params.alpha_y": 0.2})
    cli("render", scene, "--set", "material.m.params.alpha_y=0.2", "-o", tmp_path / "cli.png")
    assert np.array_equal(image, vk_render._native.read_image(tmp_path / "cli.png"))
    assert not np.array_equal(image, renderer.render(scene))
    with pytest.raises(vk_render.SceneError, match=r"material.m.params.alpha_y = 2.*outside \[0.01, 1\]"):
        renderer.render(scene, set={"material.m.params.alpha_y": 2.0})
    records = vk_render.sweep(scene, {"material.m.params.alpha_x": [0.05, 0.3]}, renderer=renderer)
    for record in records:
        assert np.array_equal(record["image"], renderer.render(scene, set=record["params"]))


def test_a_negative_brdf_is_a_scene_warning(renderer, tmp_path):
    negative = """analytic
::begin shader
vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return dot(V, X) < 0.0 ? vec3(-1.0) : vec3(0.2); }
::end shader
"""
    scene = scene_file(tmp_path, negative)
    with pytest.warns(vk_render.SceneWarning, match="its BRDF gave NaN, an infinity or a negative value"):
        renderer.render(scene)


@pytest.mark.alone
def test_a_brdf_that_outlasts_the_timeout_is_a_device_error(tmp_path):
    slow = """analytic
::begin parameters
float limit 0 1e12 1e9
::end parameters
::begin shader
vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)
{
    float x = 0.0;
    for (float i = 0.0; i < limit; i += 1.0)
        for (float j = 0.0; j < limit; j += 1.0)
            x += sin(i + j * dot(L, V));
    return vec3(abs(x));
}
::end shader
"""
    scene = scene_file(tmp_path, slow)
    scene.write_text(scene.read_text().replace("width = 64", "width = 600").replace("height = 48", "height = 400"))
    # In a process of its own: the device is given up with the work still running, which only the process's
    # end stops.
    program = (
        "import os, sys, vk_render\n"
        "r = vk_render.Renderer(timeout=1.0)\n"
        "try:\n"
        f"    r.render({str(scene)!r})\n"
        "except vk_render.DeviceError as e:\n"
        "    print(e); sys.stdout.flush(); os._exit(3)\n"
        "os._exit(0)\n"
    )
    done = subprocess.run([sys.executable, "-c", program], capture_output=True, text=True, timeout=120)
    assert done.returncode == 3, done.stdout + done.stderr
    assert "did not finish its work within 1 s" in done.stdout and "m.brdf may never end" in done.stdout
