"""Renders through Python are the command line's images: the PNG's bytes, the EXR's values, `set` as
`--set`, and a Scene as its file."""

import pickle

import numpy as np
import pytest

import vk_render
from conftest import FIG1, ROOT, SCENES, cli


def cli_image(tmp_path, scene, *args, suffix="png"):
    out = tmp_path / f"cli.{suffix}"
    cli("render", scene, "-o", out, *args)
    return vk_render._native.read_image(out), out


@pytest.mark.parametrize(
    "scene, args, kwargs",
    [
        (FIG1, [], {}),
        (SCENES / "fig3-plastic-s-16.toml", ["--width", "160", "--height", "100", "--samples", "1"],
         {"width": 160, "height": 100, "samples": 1}),
        (SCENES / "fig4-gold-metalness-0.5.toml", ["--width", "120", "--height", "80", "--view", "brdf"],
         {"width": 120, "height": 80, "view": "brdf"}),
    ],
)
def test_an_array_is_the_png_the_command_line_writes(renderer, tmp_path, scene, args, kwargs):
    expected, png = cli_image(tmp_path, scene, *args)
    image = renderer.render(scene, **kwargs)
    assert image.dtype == np.uint8 and image.shape == expected.shape
    assert np.array_equal(image, expected)
    # And written as a PNG, the very bytes.
    vk_render._native.write_png(image, tmp_path / "python.png")
    assert (tmp_path / "python.png").read_bytes() == png.read_bytes()


def test_hdr_is_the_exr_the_command_line_writes(renderer, tmp_path):
    expected, _ = cli_image(tmp_path, SCENES / "fig4-gold-metalness-1.0.toml", "--width", "150", "--height", "100",
                            "--set", "image.exposure=2", suffix="exr")
    image = renderer.render(SCENES / "fig4-gold-metalness-1.0.toml", width=150, height=100,
                            set={"image.exposure": 2}, hdr=True)
    assert image.dtype == np.float32 and image.shape == (100, 150, 3)
    assert np.array_equal(image, expected)
    assert image.max() > 1.0 or image.min() >= 0.0


def test_set_means_what_dash_dash_set_means(renderer, tmp_path):
    sets = {
        "material.grey.brdf": "oren-nayar",
        "material.grey.sigma": 0.4,
        "material.red.kd": [0.2, 0.6, 0.3],
        "light.0.power": 45,
        "image": {"width": 200, "height": 120},
        "camera.position": (0.0, 0.3, -0.5),
    }
    expected, _ = cli_image(
        tmp_path, FIG1, "--set", "material.grey.brdf=oren-nayar", "--set", "material.grey.sigma=0.4",
        "--set", "material.red.kd=[0.2, 0.6, 0.3]", "--set", "light.0.power=45",
        "--set", "image={width = 200, height = 120}", "--set", "camera.position=[0.0, 0.3, -0.5]",
    )
    assert np.array_equal(renderer.render(FIG1, set=sets), expected)
    # numpy values are their Python equivalents.
    numpy_sets = dict(sets, **{"material.red.kd": np.array([0.2, 0.6, 0.3]), "light.0.power": np.int64(45)})
    assert np.array_equal(renderer.render(FIG1, set=numpy_sets), expected)


def test_a_scene_renders_as_its_file_and_with_set_as_set(renderer):
    scene = vk_render.Scene.load(FIG1)
    assert (scene.width, scene.height, scene.samples, scene.view) == (600, 400, 4, "radiance")
    assert scene.materials == ["grey", "red"]
    assert [o["shape"] for o in scene.objects] == ["sphere", "plane"]
    assert scene.lights[0]["power"] == 60.0
    small = scene.with_set({"image.width": 90, "image.height": 60})
    assert (scene.width, small.width, small.height) == (600, 90, 60)
    from_file = renderer.render(FIG1, width=90, height=60)
    assert np.array_equal(renderer.render(small), from_file)
    # Its text is a scene that renders the same; so is a pickled copy (what Dask sends its workers).
    again = vk_render.Scene.from_toml(small.to_toml(), base_dir=ROOT)
    assert np.array_equal(renderer.render(again), from_file)
    assert pickle.loads(pickle.dumps(small)) == small
    assert np.array_equal(renderer.render(small, set={"material.grey.kd": 0.9}),
                          renderer.render(FIG1, width=90, height=60, set={"material.grey.kd": 0.9}))


def test_a_mesh_is_found_beside_the_toml_text(renderer, tmp_path):
    (tmp_path / "tri.obj").write_text("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
    text = """
[image]
width = 64
height = 48
[[light]]
type = "point"
position = [0.0, 0.0, -2.0]
color = [1.0, 1.0, 1.0]
power = 20.0
[material.white]
brdf = "lambert"
kd = [0.8, 0.8, 0.8]
[[object]]
shape = "mesh"
path = "tri.obj"
translate = [0.0, 0.0, 2.0]
material = "white"
"""
    image = renderer.render(vk_render.Scene.from_toml(text, base_dir=tmp_path))
    assert image.shape == (48, 64, 3) and image.max() > 0
    elsewhere = vk_render.Scene.from_toml(text, base_dir=ROOT)
    with pytest.raises(vk_render.SceneError, match="tri.obj"):
        renderer.render(elsewhere)


def test_the_process_wide_renderer_is_made_once(in_root):
    first = vk_render.render("assets/scenes/fig1-lambert.toml", width=60, height=40)
    assert vk_render.default_renderer() is vk_render.default_renderer()
    assert np.array_equal(first, vk_render.default_renderer().render(FIG1, width=60, height=40))


def test_the_reference_is_the_ray_tracer_of_the_command_line(tmp_path):
    out = tmp_path / "ref.png"
    cli("reference", FIG1, "-o", out, "--width", "120", "--height", "80")
    traced = vk_render.reference(FIG1, width=120, height=80)
    assert np.array_equal(traced, vk_render._native.read_image(out))
    rendered = vk_render.render(FIG1, width=120, height=80)
    assert np.abs(traced.astype(int) - rendered.astype(int)).mean() < 1.0


def test_a_scenes_warnings_are_python_warnings(renderer, tmp_path):
    dark = """
[material.grey]
brdf = "lambert"
kd = [0.5, 0.5, 0.5]
[[object]]
shape = "sphere"
center = [0.0, 0.0, 3.0]
radius = 1.0
material = "grey"
"""
    scene = vk_render.Scene.from_toml(dark)
    assert scene.warnings and "no [[light]]" in scene.warnings[0]
    assert scene.lights == []
    with pytest.warns(vk_render.SceneWarning, match=r"the scene has no \[\[light\]\]: every object is black"):
        image = renderer.render(scene, width=40, height=30)
    assert image[15, 20].tolist() == [0, 0, 0]


def test_the_exact_modes_accuracy_is_what_render_prints(renderer, tmp_path):
    sky = {"environment.builtin": "sky", "environment.mode": "exact"}
    renderer.render(FIG1, width=48, height=32, set=sky)
    accuracy = renderer.accuracy
    printed = cli("render", FIG1, "-o", tmp_path / "sky.png", "--width", "48", "--height", "32",
                  "--set", 'environment.builtin="sky"', "--set", 'environment.mode="exact"').stdout
    assert printed.startswith(
        f"environment (exact): {accuracy['samples']} samples a pixel in {accuracy['passes']} passes: "
        f"standard error at most {accuracy['p99_levels']:.2f} of an 8-bit level"
    ), (printed, accuracy)
    renderer.render(FIG1, width=48, height=32)
    assert renderer.accuracy is None
