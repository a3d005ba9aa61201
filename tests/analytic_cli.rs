//! `.brdf` files from the command line: every bad file and bad value is one line naming the file and its
//! line (or the scene's key, value and range), exit status 1 and no image; warnings for what loads but will
//! not do what the file may mean; a BRDF's invalid values counted and shown; overrides and sweeps of a
//! file's parameters.

mod common;

use std::path::{Path, PathBuf};
use std::process::Output;

use common::{root, temp_dir, vk_render};

/// A lit sphere of material `m`, the analytic model of `brdf.brdf` beside the scene, with `params`.
const SCENE: &str = "[image]\nwidth = 96\nheight = 64\n[[light]]\nposition = [0.0, 0.0, -2.0]\npower = 60.0\n\
                     [material.m]\nbrdf = \"analytic\"\nfile = \"brdf.brdf\"\nPARAMS\n[[object]]\nshape = \"sphere\"\n\
                     center = [0.0, 0.0, 3.0]\nradius = 1.0\nmaterial = \"m\"\n";

/// A well-formed file, which the cases break line by line.
const GOOD: &str = "analytic\n# a comment\n::begin parameters\nfloat alpha 0.01 1 0.3\nbool useF 0\ncolor kd 0.5 0.5 0.5\n\
                    ::end parameters\n::begin shader\nconst float PI = 3.14159265358979323846;\n\
                    vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{\n    return kd / PI * (useF ? 1.0 : alpha + 0.7);\n}\n\
                    ::end shader\n";

/// GOOD with an importance sampler after its shader, from line 15.
fn with_sampler() -> String {
    format!(
        "{GOOD}::begin isFunc\nvec3 sampleBRDF(vec3 V, vec3 N, vec3 X, vec3 Y, vec2 u)\n{{\n    return N;\n}}\n\
         float pdfBRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{{\n    return 1.0;\n}}\n::end isFunc\n"
    )
}

/// The scene and its `.brdf` file written into `folder`.
fn write(folder: &Path, brdf: &str, params: &str) -> PathBuf {
    std::fs::write(folder.join("brdf.brdf"), brdf).unwrap();
    let scene = folder.join("scene.toml");
    std::fs::write(&scene, SCENE.replace("PARAMS", params)).unwrap();
    scene
}

fn render(scene: &Path, extra: &[&str]) -> (Output, PathBuf) {
    let out = scene.parent().unwrap().join("out.png");
    let mut args = vec!["render", scene.to_str().unwrap(), "-o", out.to_str().unwrap()];
    args.extend_from_slice(extra);
    (vk_render(&args), out)
}

/// Renders the scene of `brdf` and `params`, which must fail with one line holding every needle, status 1,
/// and no image.
fn fails(brdf: &str, params: &str, needles: &[&str]) {
    let folder = temp_dir();
    let scene = write(folder.path(), brdf, params);
    let (output, out) = render(&scene, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr).to_string();
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "more than one line:\n{stderr}");
    for needle in needles {
        assert!(stderr.contains(needle), "stderr lacks {needle:?}:\n{stderr}");
    }
    assert!(!out.exists(), "an image was written: {stderr}");
}

/// GOOD with one line replaced.
fn edited(from: &str, to: &str) -> String {
    assert!(GOOD.contains(from), "{from}");
    GOOD.replace(from, to)
}

#[test]
fn a_good_file_renders_and_its_parameters_take_their_defaults() {
    let folder = temp_dir();
    let scene = write(folder.path(), GOOD, "");
    let (output, out) = render(&scene, &[]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    assert!(out.exists());
    assert!(output.stderr.is_empty(), "{}", String::from_utf8_lossy(&output.stderr));
}

#[test]
fn every_malformed_file_is_one_line_naming_its_line() {
    let prefix = "scene.toml: material.m.file = \"brdf.brdf\": ";
    let cases: Vec<(String, &str)> = vec![
        (GOOD.replacen("analytic", "bparam", 1), "brdf.brdf:1: the file starts with `bparam`, not `analytic`"),
        (edited("float alpha 0.01 1 0.3", "int alpha 0 1 0"), "brdf.brdf:4: unknown parameter type `int`"),
        (
            edited("float alpha 0.01 1 0.3", "float alpha 1 0.01 0.3"),
            "brdf.brdf:4: float alpha: MIN 1 is above MAX 0.01",
        ),
        (
            edited("float alpha 0.01 1 0.3", "float alpha 0.01 1 3"),
            "brdf.brdf:4: float alpha: DEFAULT 3 is outside [0.01, 1]",
        ),
        (edited("::end shader\n", ""), "brdf.brdf:8: the section `shader` begun here is never ended (`::end shader`)"),
        (edited("vec3 BRDF(", "vec3 brdf("), "brdf.brdf: the shader section defines no function `vec3 BRDF(vec3 L"),
        (
            edited("vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)", "float BRDF(vec3 L, vec3 V, vec3 N)"),
            "brdf.brdf:10: the shader section defines `float BRDF(vec3, vec3, vec3)`: vk-render calls `vec3 BRDF(",
        ),
        (edited("return kd / PI", "return kd / PI +"), "brdf.brdf:12: GLSL: "),
        (edited("return kd / PI * (useF ? 1.0 : alpha + 0.7);", "return alpha;"), "brdf.brdf:12: GLSL: "),
        (edited("return kd / PI", "return kd / Pi"), "brdf.brdf:12: GLSL: 'Pi' : undeclared identifier"),
        (
            edited("color kd 0.5 0.5 0.5", "color in 0.5 0.5 0.5"),
            "brdf.brdf:6: the parameter name `in` is a GLSL keyword",
        ),
    ];
    for (text, expected) in cases {
        fails(&text, "", &[prefix, expected]);
    }
    // An isFunc section's functions, missing, mistyped or wrong, are named at the file's own lines.
    let sampler = with_sampler();
    let sampler_cases = [
        (
            sampler.replace("float pdfBRDF(", "float pdf("),
            "brdf.brdf: the isFunc section defines no function `float pdfBRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)`",
        ),
        (
            sampler
                .replace("vec3 sampleBRDF(vec3 V, vec3 N, vec3 X, vec3 Y, vec2 u)", "vec3 sampleBRDF(vec3 V, vec2 u)"),
            "brdf.brdf:16: the isFunc section defines `vec3 sampleBRDF(vec3, vec2)`: vk-render calls `vec3 sampleBRDF(",
        ),
        (sampler.replace("    return N;", "    return N +;"), "brdf.brdf:18: GLSL: "),
    ];
    for (text, expected) in sampler_cases {
        fails(&text, "", &[prefix, expected]);
    }
    let folder = temp_dir();
    let (output, out) = render(&write(folder.path(), &sampler, ""), &[]);
    assert!(output.status.success() && out.exists(), "{}", String::from_utf8_lossy(&output.stderr));
}

#[test]
fn a_missing_file_and_a_folder_are_named() {
    let folder = temp_dir();
    let scene = write(folder.path(), GOOD, "");
    std::fs::remove_file(folder.path().join("brdf.brdf")).unwrap();
    let (output, out) = render(&scene, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1));
    assert!(stderr.contains("material.m.file = \"brdf.brdf\": cannot read the BRDF file"), "{stderr}");
    assert!(!out.exists());
    std::fs::create_dir(folder.path().join("brdf.brdf")).unwrap();
    let (output, _) = render(&scene, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("is a folder, not a regular file"), "{stderr}");
}

#[test]
fn a_bad_value_names_the_key_the_value_and_the_range() {
    let prefix = "scene.toml: material.m.params.";
    fails(
        GOOD,
        "params = { alpha = 1.5 }",
        &[prefix, "alpha = 1.5: outside [0.01, 1], the range brdf.brdf (line 4) gives alpha"],
    );
    fails(
        GOOD,
        "params = { beta = 1 }",
        &["material.m.params.beta = 1: brdf.brdf has no parameter `beta` (it has alpha, useF, kd)"],
    );
    fails(
        GOOD,
        "params = { alpha = \"x\" }",
        &["alpha = \"x\": alpha is a float parameter of brdf.brdf (line 4): it takes a number"],
    );
    fails(
        GOOD,
        "params = { useF = 2 }",
        &["useF = 2: useF is a bool parameter of brdf.brdf (line 5): it takes true or false"],
    );
    fails(
        GOOD,
        "params = { kd = [1, 2] }",
        &["kd = [1, 2]: kd is a color parameter of brdf.brdf (line 6): it takes a colour"],
    );
    fails(GOOD, "kd = 0.5", &["material.m.kd: not a parameter of brdf \"analytic\" (it takes file, params)"]);
}

#[test]
fn set_overrides_a_files_parameter_even_without_a_params_table() {
    let folder = temp_dir();
    let scene = write(folder.path(), GOOD, "");
    let (output, out) = render(&scene, &["--set", "material.m.params.alpha=0.9"]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let brighter = image::open(&out).unwrap().to_rgb8();
    let (output, out) = render(&scene, &[]);
    assert!(output.status.success());
    let default = image::open(&out).unwrap().to_rgb8();
    // kd / pi (alpha + 0.7) at the sphere's centre: 0.9 + 0.7 against 0.3 + 0.7 of the same light.
    let centre = |image: &image::RgbImage| f32::from(image.get_pixel(48, 32)[0]);
    let ratio = centre(&brighter) / centre(&default);
    assert!((ratio - 1.6).abs() < 0.02, "the override changed the centre by {ratio}");
    let (output, _) = render(&scene, &["--set", "material.m.params.alpha=2"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(stderr.contains("material.m.params.alpha = 2: outside [0.01, 1]"), "{stderr}");
}

#[test]
fn a_sweep_steps_a_files_parameter() {
    let folder = temp_dir();
    let scene = write(folder.path(), GOOD, "");
    let sheet = folder.path().join("sheet.png");
    let output = vk_render(&[
        "sweep",
        scene.to_str().unwrap(),
        "--param",
        "material.m.params.alpha",
        "--values",
        "0.1,0.5,1",
        "-o",
        sheet.to_str().unwrap(),
    ]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    let centres: Vec<u8> = ["0.1", "0.5", "1"]
        .iter()
        .map(|v| image::open(folder.path().join(format!("sheet-{v}.png"))).unwrap().to_rgb8().get_pixel(48, 32)[0])
        .collect();
    assert!(centres[0] < centres[1] && centres[1] < centres[2], "{centres:?}");
}

#[test]
fn a_dropped_define_and_an_unknown_section_are_warned_of() {
    let folder = temp_dir();
    let brdf = edited("const float PI", "#define TWO 2.0\nconst float PI").replace(
        "::end parameters\n",
        "::end parameters\n::begin notes\nvec3 sampleBRDF() { return vec3(0); }\n::end notes\n",
    );
    let scene = write(folder.path(), &brdf, "");
    let (output, out) = render(&scene, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(out.exists());
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 2, "{stderr}");
    assert!(
        lines.iter().any(|l| l.starts_with("warning: ") && l.contains("brdf.brdf: line 8: the section `notes`")),
        "{stderr}"
    );
    assert!(lines.iter().any(|l| l.contains("brdf.brdf: line 12: `#define TWO 2.0` is dropped")), "{stderr}");
}

/// A BRDF negative over half the hemisphere of V (where V . X < 0), and valid elsewhere.
const NEGATIVE: &str = "analytic\n::begin parameters\ncolor kd 0.5 0.5 0.5\n::end parameters\n::begin shader\n\
                        vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{\n    return dot(V, X) < 0.0 ? -kd : kd;\n}\n\
                        ::end shader\n";

#[test]
fn invalid_values_are_counted_once_with_a_direction_pair_and_the_image_is_written() {
    let folder = temp_dir();
    let scene = write(folder.path(), NEGATIVE, "");
    // The sphere's X is +y x N: on one half of the sphere the camera's direction has V . X < 0.
    let (output, out) = render(&scene, &[]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(out.exists());
    let warnings: Vec<&str> = stderr.lines().filter(|l| l.starts_with("warning: ")).collect();
    assert_eq!(warnings.len(), 1, "{stderr}");
    let warning = warnings[0];
    assert!(warning.contains("brdf.brdf: its BRDF gave NaN, an infinity or a negative value"), "{warning}");
    let count: u64 =
        warning.split("value ").nth(1).and_then(|r| r.split(' ').next()).and_then(|n| n.parse().ok()).unwrap();
    assert!(count > 100, "{warning}");
    assert!(warning.contains("f = [-0.5, -0.5, -0.5] at L (theta"), "{warning}");
    // The image counts them as 0: the negative half of the sphere is black.
    let image = image::open(&out).unwrap().to_rgb8();
    assert!(image.pixels().any(|p| p.0 == [0, 0, 0]));
    // The probe commands report them as well.
    let lobes = folder.path().join("lobes.csv");
    let output =
        vk_render(&["plot", "lobe", scene.to_str().unwrap(), "--theta-i", "30", "-o", lobes.to_str().unwrap()]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert!(output.status.success(), "{stderr}");
    assert!(
        stderr.contains("warning: ") && stderr.contains("its BRDF gave NaN, an infinity or a negative value"),
        "{stderr}"
    );
}

#[test]
fn the_shipped_models_load_without_warnings() {
    for entry in std::fs::read_dir(root().join("assets/brdfs")).unwrap() {
        let path = entry.unwrap().path();
        let model = vk_render::brdf::AnalyticModel::load(&path).unwrap_or_else(|e| panic!("{e}"));
        assert!(model.warnings.is_empty(), "{:?}", model.warnings);
    }
}

/// A BRDF whose loops run about 10^18 times (lavapipe stops each GLSL loop after 65535 iterations, so even
/// this ends there, after some seconds for a 600 x 400 image; on a GPU it would not).
const ENDLESS: &str = "analytic\n::begin parameters\nfloat limit 0 1e12 1e9\n::end parameters\n::begin shader\n\
                       vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y)\n{\n    float x = 0.0;\n    for (float i = \
                       0.0; i < limit; i += 1.0)\n        for (float j = 0.0; j < limit; j += 1.0)\n            x += \
                       sin(i + j * dot(L, V));\n    return vec3(abs(x));\n}\n::end shader\n";

#[test]
fn a_brdf_that_never_ends_is_given_up_at_the_timeout_naming_its_file() {
    let folder = temp_dir();
    let scene = write(folder.path(), ENDLESS, "");
    let text = std::fs::read_to_string(&scene)
        .unwrap()
        .replace("width = 96", "width = 600")
        .replace("height = 64", "height = 400");
    std::fs::write(&scene, text).unwrap();
    let started = std::time::Instant::now();
    let (output, out) = render(&scene, &["--timeout", "1"]);
    let stderr = String::from_utf8_lossy(&output.stderr);
    assert_eq!(output.status.code(), Some(1), "{stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "{stderr}");
    assert!(stderr.contains("the device did not finish its work within 1 s (--timeout)"), "{stderr}");
    assert!(stderr.contains("brdf.brdf may never end"), "{stderr}");
    assert!(!out.exists());
    // Given up at the timeout, not when the work ended.
    assert!(started.elapsed() < std::time::Duration::from_secs(20), "{:?}", started.elapsed());
}

#[test]
fn tabulate_writes_a_files_brdf_as_a_merl_table_from_its_own_glsl() {
    let folder = temp_dir();
    let scene = folder.path().join("scene.toml");
    let lambert = root().join("assets/brdfs/lambert.brdf");
    let text = format!(
        "[material.m]\nbrdf = \"analytic\"\nfile = {:?}\nparams = {{ kd = [0.5, 0.25, 0.125] }}\n",
        lambert.display().to_string()
    );
    std::fs::write(&scene, text).unwrap();
    let table = folder.path().join("m.binary");
    let output = vk_render(&["tabulate", scene.to_str().unwrap(), "--material", "m", "-o", table.to_str().unwrap()]);
    assert!(output.status.success(), "{}", String::from_utf8_lossy(&output.stderr));
    // Every entry is the built-in Lambert's, tabulated by its Rust mirror: kd / pi where both directions are
    // above the horizon, 0 where an entry's are not (past theta_d + theta_h of 90 degrees).
    let read = vk_render::brdf::MeasuredTable::read(&table).unwrap();
    let kd = glam::Vec3::new(0.5, 0.25, 0.125);
    let mirror = vk_render::brdf::Brdf::Lambert { kd };
    let expected = vk_render::brdf::MeasuredTable::tabulate(table.clone(), |wi, wo| mirror.eval(glam::Vec3::Z, wi, wo));
    let mut lit = 0;
    for (entry, want) in read.rgb.chunks_exact(3).zip(expected.rgb.chunks_exact(3)) {
        for (value, want) in entry.iter().zip(want) {
            assert!((value - want).abs() <= 1e-6 * want, "{entry:?} against {want}");
        }
        lit += usize::from(entry[0] > 0.0);
    }
    assert!(lit > read.rgb.len() / 3 / 2, "{lit} entries lit");
}

#[test]
fn the_guides_analytic_examples_run_as_written() {
    // The shell blocks of the guide's page on .brdf files (docs/analytic-brdfs.md), each command run from a
    // folder holding the repository's assets (its files land there); the output the fits' block shows is the
    // second fit's. tests/docs.rs leaves these blocks to this test.
    let section = std::fs::read_to_string(root().join("docs/analytic-brdfs.md")).unwrap();
    assert!(section.starts_with("# Analytic BRDFs"), "the page");
    let blocks: Vec<&str> = section.split("```sh\n").skip(1).filter_map(|b| b.split("```").next()).collect();
    let folder = temp_dir();
    std::os::unix::fs::symlink(root().join("assets"), folder.path().join("assets")).unwrap();
    let mut outputs = Vec::new();
    for block in &blocks {
        let commands = block.replace("\\\n", " ");
        for line in commands.lines().map(|l| l.split(" # ").next().unwrap_or(l).trim()).filter(|l| !l.is_empty()) {
            let words: Vec<&str> = line.split_whitespace().collect();
            assert_eq!(words[0], "vk-render", "{line}");
            let output = std::process::Command::new(env!("CARGO_BIN_EXE_vk-render"))
                .arg("--validate")
                .args(&words[1..])
                .current_dir(folder.path())
                .output()
                .unwrap();
            assert!(output.status.success(), "{line}: {}", String::from_utf8_lossy(&output.stderr));
            outputs.push(String::from_utf8_lossy(&output.stdout).into_owned());
        }
    }
    assert_eq!(outputs.len(), 8);
    for file in ["brushed.png", "sweep.png", "lobes.png", "furnace.csv", "brushed.binary"] {
        assert!(folder.path().join(file).exists(), "{file}");
    }
    let shown = section.split("```\nblinn-phong (").nth(1).and_then(|b| b.split("```").next()).expect("the output");
    assert_eq!(outputs[6], format!("blinn-phong ({shown}"));
}
