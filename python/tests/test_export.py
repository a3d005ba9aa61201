"""`vk-render export` and `fit --export`: each format's file read back by the format's own parser and its lobe,
evaluated by the format's own definition (formats.py), against ours on the GPU (Renderer.brdf).

Two checks per export. With the course's G and Schlick's Fresnel put in place of the format's, the file's
parameters give our lobe to float precision wherever the format's structure is ours: this is where a mapping
error would show (alpha written for a roughness, pbrt's remapped roughness, a colour in the wrong lobe).
With the format's own G and Fresnel, the difference is the models' own, bounded here and tabled in
docs/export.md (BOUNDS)."""

import math
import re

import numpy as np
import pytest

import formats
from conftest import cli, hemisphere

MATERIALS = {
    # Figure 4's gold: the GGX lobe alone.
    "gold": {"brdf": "cook-torrance", "kd": [1.0, 0.85, 0.57], "f0": [1.0, 0.85, 0.57], "roughness": 0.3,
             "metalness": 1.0},
    # Both lobes, one colour: every format holds its structure.
    "copper": {"brdf": "cook-torrance", "kd": [0.95, 0.64, 0.54], "f0": [0.95, 0.64, 0.54], "roughness": 0.5,
               "metalness": 0.6, "diffuse": "lambert"},
    # Both lobes, two colours: glTF as a dielectric with a specular layer, Mitsuba and pbrt as a mix;
    # Standard Surface and OpenPBR refuse it.
    "lacquer": {"brdf": "cook-torrance", "kd": [0.5, 0.25, 0.125], "f0": [0.9, 0.6, 0.3], "roughness": 0.4,
                "metalness": 0.25, "diffuse": "lambert"},
    "matte": {"brdf": "lambert", "kd": [0.5, 0.25, 0.125]},
    # Figure 2's Oren-Nayar: Standard Surface's own; glTF, Mitsuba and pbrt write Lambert's.
    "rough-matte": {"brdf": "oren-nayar", "kd": [0.5, 0.5, 0.5], "sigma": 0.6},
}

FORMATS = {"gltf": "gltf", "materialx": "mtlx", "openpbr": "mtlx", "mitsuba": "xml", "pbrt": "pbrt"}

# The models' own differences: relative root mean square of f_r cos(theta_o) - ours over directions up to 70
# degrees from the normal, the largest of red, green and blue; None where the export is refused. Measured
# (docs/export.md has the table): glTF and OpenPBR differ from ours by their G alone (Smith's height-correlated
# G against the course's Smith-Schlick with Karis's k, lower at grazing angles: gold 0.369, copper 0.245), the
# others by their Fresnel too; Oren-Nayar's sigma 0.6 written as Lambert 0.278, as OpenPBR's EON 0.231.
BOUNDS = {
    ("gold", "gltf"): 0.39, ("gold", "materialx"): 0.40, ("gold", "openpbr"): 0.39, ("gold", "mitsuba"): 0.40,
    ("gold", "pbrt"): 0.40,
    ("copper", "gltf"): 0.26, ("copper", "materialx"): 0.27, ("copper", "openpbr"): 0.26,
    ("copper", "mitsuba"): 0.27, ("copper", "pbrt"): 0.27,
    ("lacquer", "gltf"): 0.30, ("lacquer", "materialx"): None, ("lacquer", "openpbr"): None,
    ("lacquer", "mitsuba"): 0.35, ("lacquer", "pbrt"): 0.35,
    ("matte", "gltf"): 1e-4, ("matte", "materialx"): 1e-4, ("matte", "openpbr"): 1e-4, ("matte", "mitsuba"): 1e-4,
    ("matte", "pbrt"): 1e-4,
    ("rough-matte", "gltf"): 0.29, ("rough-matte", "materialx"): 1e-4, ("rough-matte", "openpbr"): 0.25,
    ("rough-matte", "mitsuba"): 0.29, ("rough-matte", "pbrt"): 0.29,
}


def directions(count=400):
    """Light and view directions up to 70 degrees from the normal, as pairs."""
    wi, wo = hemisphere(count * 3, 11), hemisphere(count * 3, 12)
    keep = (wi[:, 2] > math.cos(math.radians(70))) & (wo[:, 2] > math.cos(math.radians(70)))
    return wi[keep][:count].astype(float), wo[keep][:count].astype(float)


def scene_of(tmp_path):
    text = []
    for name, material in MATERIALS.items():
        text.append(f"[material.{name}]")
        for key, value in material.items():
            text.append(f"{key} = {value!r}".replace("'", '"'))
        text.append("")
    path = tmp_path / "materials.toml"
    path.write_text("\n".join(text))
    return path


def by_definition(format, path, wi, wo, course_g):
    if format == "gltf":
        return formats.gltf(path, wi, wo, course_g)
    if format in ("materialx", "openpbr"):
        return formats.materialx(path, wi, wo, course_g)
    if format == "mitsuba":
        return formats.mitsuba_by_definition(path, wi, wo, course_g)
    return formats.pbrt(path, wi, wo, course_g)


def difference(theirs, ours, wo):
    """The relative root mean square of the difference of f_r cos(theta_o), the largest channel's."""
    cos = wo[:, 2:3]
    return float(np.max(np.sqrt(np.mean(((theirs - ours) * cos) ** 2, axis=0) / np.mean((ours * cos) ** 2, axis=0))))


@pytest.fixture(scope="module")
def exports(tmp_path_factory):
    """Every material exported in every format: {(material, format): (path or None, stdout or stderr)}."""
    folder = tmp_path_factory.mktemp("exports")
    scene = scene_of(folder)
    done = {}
    for name in MATERIALS:
        for format, extension in FORMATS.items():
            path = folder / f"{name}.{format}.{extension}"
            run = cli("export", scene, "--material", name, "--format", format, "-o", path, check=False)
            done[(name, format)] = (path if run.returncode == 0 else None, run.stdout + run.stderr)
    return done


def refused(material, format):
    return BOUNDS[(material, format)] is None


@pytest.mark.parametrize("material,format", [key for key in BOUNDS])
def test_each_export_read_back_by_its_own_tools_is_our_lobe(renderer, exports, material, format):
    path, said = exports[(material, format)]
    if refused(material, format):
        assert path is None and not (said and "written as" in said)
        assert "one base colour" in said and "glTF" in said and f"--material {material}" in said, said
        return
    assert path is not None, said
    assert f"{material} (" in said and "written as" in said, said
    wi, wo = directions()
    ours = renderer.brdf(MATERIALS[material], wi.astype(np.float32), wo.astype(np.float32)).astype(float)
    # The mapping: the file's parameters with the course's G and Schlick's Fresnel are our lobe. Oren-Nayar
    # written as Lambert's (glTF, Mitsuba, pbrt) or as OpenPBR's EON is another lobe: the bound below has it.
    if not (material == "rough-matte" and format != "materialx"):
        # Standard Surface's artistic_ior clamps gold's red F0 of 1 to 0.99; pbrt's and our conductor's k, to
        # 0.9999.
        exact = 1.1e-2 if (material, format) == ("gold", "materialx") else 2e-4
        assert difference(by_definition(format, path, wi, wo, True), ours, wo) < exact
    # The models' own difference, stated in docs/export.md.
    own = difference(by_definition(format, path, wi, wo, False), ours, wo)
    assert own <= BOUNDS[(material, format)], f"{own:.4f}"


def test_mitsuba_itself_evaluates_each_export_as_its_definition_and_renders_it(exports, tmp_path):
    import mitsuba as mi

    wi, wo = directions(100)
    for material in MATERIALS:
        path, said = exports[(material, "mitsuba")]
        theirs, definition = formats.mitsuba(path, wi, wo), formats.mitsuba_by_definition(path, wi, wo)
        np.testing.assert_allclose(theirs, definition, rtol=5e-4, atol=1e-7, err_msg=material)
    # A sphere of the gold under a point light, rendered by Mitsuba: lit where it faces the light.
    gold, _ = exports[("gold", "mitsuba")]
    scene = mi.load_string(f"""<scene version="3.0.0">
        <include filename="{gold}"/>
        <integrator type="direct"/>
        <sensor type="perspective"><float name="fov" value="30"/>
            <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
            <film type="hdrfilm"><integer name="width" value="32"/><integer name="height" value="32"/></film>
            <sampler type="independent"><integer name="sample_count" value="4"/></sampler>
        </sensor>
        <shape type="sphere"><ref id="gold"/></shape>
        <emitter type="point"><point name="position" value="0, 0, 5"/><rgb name="intensity" value="20"/></emitter>
    </scene>""")
    image = np.array(mi.render(scene))
    assert image.shape == (32, 32, 3) and np.all(np.isfinite(image))
    centre, corner = image[14:18, 14:18].mean(axis=(0, 1)), image[:3, :3].mean(axis=(0, 1))
    assert np.all(corner == 0) and centre[0] > centre[2] > 0, (centre, corner)


def test_fit_exports_the_best_fit_a_format_holds(tmp_path):
    from conftest import ROOT

    analysis = ROOT / "assets/analysis/course-materials.toml"
    out = tmp_path / "plastic.gltf"
    # Phong ranks first against itself; the export is the best of the others that glTF holds.
    done = cli("fit", analysis, "--material", "phong", "--to", "all", "--export", "gltf", "--export-to", out)
    assert "exporting the cook-torrance fit" in done.stdout, done.stdout
    assert "phong (cook-torrance kd" in done.stdout and out.exists(), done.stdout
    # The file holds the fitted parameters printed in the ranking.
    import pygltflib

    (material,) = pygltflib.GLTF2().load(str(out)).materials
    ranked = [line for line in done.stdout.splitlines() if "cook-torrance" in line and "residual" in line][0]
    assert f"roughness = {material.pbrMetallicRoughness.roughnessFactor}," in ranked, ranked
    # Only models no format holds: refused before fitting.
    refused = cli("fit", analysis, "--material", "phong", "--to", "phong", "--export", "gltf", "--export-to", out,
                  check=False)
    assert refused.returncode == 1 and "--export" in refused.stderr and "cook-torrance" in refused.stderr


def written(stdout):
    """The material the `written as` line describes (`NAME (cook-torrance kd (r, g, b), f0 (r, g, b), roughness R,
    metalness M, lambert diffuse) written as`), as a material of the scene format."""
    line = next(line for line in stdout.splitlines() if " written as " in line)
    found = re.search(r"kd \(([^)]*)\), f0 \(([^)]*)\), roughness ([-0-9.e]+), metalness ([-0-9.e]+), lambert", line)
    assert found, line
    kd, f0 = ([float(v) for v in colour.split(",")] for colour in found.groups()[:2])
    return {"brdf": "cook-torrance", "kd": kd, "f0": f0, "roughness": float(found.group(3)),
            "metalness": float(found.group(4)), "diffuse": "lambert"}


@pytest.mark.parametrize("format", FORMATS)
def test_a_two_colour_fit_exports_to_every_format_as_the_model_fitted(renderer, tmp_path, format):
    # The lacquer's own Cook-Torrance (two colours) is its fit; Standard Surface and OpenPBR, with one base
    # colour, take the metallic-roughness fit made for them (4.9% from the lacquer).
    out = tmp_path / f"fit.{FORMATS[format]}"
    done = cli("fit", scene_of(tmp_path), "--material", "lacquer", "--to", "cook-torrance", "--export", format,
               "--export-to", out)
    material = written(done.stdout)
    if format in ("materialx", "openpbr"):
        assert "one base colour for both lobes: fitting metallic-roughness too" in done.stdout, done.stdout
        assert "exporting the metallic-roughness fit" in done.stdout, done.stdout
        assert material["kd"] == material["f0"] and 0 < material["metalness"] < 1, material
        ranked = next(line for line in done.stdout.splitlines() if ". metallic-roughness " in line)
        assert f"metalness = {material['metalness']}" in ranked, ranked
    else:
        assert material == MATERIALS["lacquer"], material
    # The file, read back by its own tools and evaluated by its format's definition (the course's G and
    # Schlick's Fresnel put in), is the fitted model.
    wi, wo = directions()
    ours = renderer.brdf(material, wi.astype(np.float32), wo.astype(np.float32)).astype(float)
    assert difference(by_definition(format, out, wi, wo, True), ours, wo) < 2e-4


def test_what_cannot_be_exported_is_refused_in_one_line_and_nothing_is_written(tmp_path):
    from conftest import ROOT

    analysis = ROOT / "assets/analysis/course-materials.toml"
    out = tmp_path / "out.gltf"
    for arguments, words in [
        (["--material", "phong", "--format", "gltf"], ["--material phong", "fit it first"]),
        (["--material", "nothing", "--format", "gltf"], ["nothing"]),
        (["--material", "gold", "--format", "usd"], ["usd"]),
    ]:
        done = cli("export", analysis, *arguments, "-o", out, check=False)
        assert done.returncode != 0 and all(w in done.stderr for w in words), done.stderr
        assert not out.exists()
    missing = cli("export", analysis, "--material", "gold", "--format", "gltf", "-o", tmp_path / "no" / "x.gltf",
                  check=False)
    assert missing.returncode == 1 and "no/x.gltf" in missing.stderr, missing.stderr
