//! The samplers tested as `vk-render sampling` tests them, on the GPU with the validation layer: every
//! built-in model's passes from sharp to rough at views up to 85°, and each mutant of the GLSL (a sampler,
//! a density or a BRDF broken on purpose) is caught by the test named for it. Then the command as a user
//! runs it: its exit status, report and numbers, and its errors.

mod common;

use glam::Vec3;

use common::{renderer, root, temp_dir, vk_render};
use vk_render::analysis::sampling::{
    test_sampler, views, SamplingOptions, SamplingReport, DEFAULT_LEVEL, DEFAULT_SAMPLES, DEFAULT_THETA_O,
};
use vk_render::brdf::{Analytic, Brdf, DiffuseModel, Measured, MeasuredTable, ParameterValue};
use vk_render::vulkan::ShaderSources;

/// Every default view (θo 0 to 85°, φo 0: the built-in models are isotropic), 10⁶ samples each.
fn options() -> SamplingOptions {
    SamplingOptions {
        views: DEFAULT_THETA_O.iter().map(|&t| (t, 0.0)).collect(),
        samples: DEFAULT_SAMPLES,
        seed: 1,
        level: DEFAULT_LEVEL,
    }
}

fn grey(value: f32) -> Vec3 {
    Vec3::splat(value)
}

fn gold(roughness: f32, metalness: f32) -> Brdf {
    let colour = Vec3::new(1.0, 0.85, 0.57);
    Brdf::CookTorrance { kd: colour, f0: colour, roughness, metalness, diffuse: DiffuseModel::OrenNayar }
}

fn plastic(shininess: f32) -> Brdf {
    Brdf::Phong { kd: grey(0.35), ks: grey(0.15), shininess }
}

fn blinn_plastic(shininess: f32) -> Brdf {
    Brdf::BlinnPhong { kd: grey(0.35), ks: grey(0.15), shininess }
}

/// The failed tests' names and details.
fn failures(report: &SamplingReport) -> Vec<String> {
    report.verdicts.iter().filter(|v| !v.passed).map(|v| format!("{} {:?}: {}", v.test, v.view, v.detail)).collect()
}

#[test]
fn every_built_in_sampler_passes_from_sharp_to_rough() {
    // Cook-Torrance from roughness 0.01 (GGX's α = 10⁻⁴) to 1, a metal and half a metal over Oren-Nayar;
    // Phong's and Blinn-Phong's lobes from s = 4 to 10⁵ (α about 0.006 as a Beckmann lobe: below s = 4 the
    // course's Blinn-Phong reflects more than it receives, which the energy test says); the diffuse models.
    let mut brdfs = vec![Brdf::Lambert { kd: grey(0.5) }, Brdf::OrenNayar { kd: grey(0.5), sigma: 0.6 }];
    for roughness in [0.01, 0.1, 0.3, 0.6, 1.0] {
        brdfs.push(gold(roughness, 1.0));
        brdfs.push(gold(roughness, 0.5));
    }
    for shininess in [4.0, 16.0, 1000.0, 1e5] {
        brdfs.push(plastic(shininess));
        brdfs.push(blinn_plastic(shininess));
    }
    let mut renderer = renderer();
    for brdf in &brdfs {
        let report = test_sampler(&mut renderer, brdf, &options(), || ()).unwrap();
        assert!(report.passed(), "{brdf:?}: {:#?}", failures(&report));
        // The views' p-values are spread, not all near 1 (a density counted twice would pass loosely).
        assert!(report.views.iter().any(|v| v.chi_square.p_value < 0.95), "{brdf:?}");
    }
}

/// A shipped `.brdf` model with `params` set.
fn shipped(file: &str, params: &[(&str, ParameterValue)]) -> Brdf {
    let material = params
        .iter()
        .try_fold(Analytic::defaults(common::shipped(file)), |m, (name, value)| m.with(name, *value))
        .unwrap();
    Brdf::Analytic(material)
}

#[test]
fn every_shipped_sampler_passes_from_sharp_to_rough() {
    // GGX's visible normals (Walter et al.'s model), Ward's half vectors (Walter 2005), Lafortune's cosine
    // lobes, Ashikhmin and Shirley's and the Disney BRDF's lobes, sharp to rough, over a diffuse base, isotropic and anisotropic both ways, at every view and,
    // where the model is anisotropic, every azimuth.
    let float = ParameterValue::Float;
    let grey = |v: f32| ParameterValue::Color(Vec3::splat(v));
    let mut brdfs = Vec::new();
    for alpha in [0.01, 0.1, 0.4, 1.0] {
        brdfs.push(shipped("walter_ggx.brdf", &[("alpha", float(alpha)), ("kd", grey(0.1)), ("f0", grey(0.5))]));
    }
    for (x, y) in [(0.01, 0.01), (0.2, 0.2), (1.0, 1.0), (0.05, 0.4)] {
        let params = [("alpha_x", float(x)), ("alpha_y", float(y)), ("rho_d", grey(0.3)), ("rho_s", grey(0.1))];
        brdfs.push(shipped("ward.brdf", &params));
    }
    for (nu, nv) in [(1.0, 1.0), (100.0, 100.0), (20.0, 800.0), (1e4, 1e4)] {
        let params = [("nu", float(nu)), ("nv", float(nv)), ("Rd", grey(0.3)), ("Rs", grey(0.3))];
        brdfs.push(shipped("ashikhmin_shirley.brdf", &params));
    }
    // Lafortune's generalized cosine lobe about its own axis: the sharpest modified Phong lobe, off-specular
    // towards grazing (Cxy -0.7), and about the normal (Cxy 0).
    for (cxy, n) in [(-1.0, 2000.0), (-0.7, 60.0), (0.0, 20.0)] {
        let params = [("Cxy", float(cxy)), ("n", float(n)), ("rho_d", grey(0.3)), ("rho_s", grey(0.3))];
        brdfs.push(shipped("lafortune.brdf", &params));
    }
    // The Disney BRDF by its lobes: its defaults, an anisotropic metal, a sharp clearcoat over a sharp lobe,
    // the roughest metal.
    let gold = ParameterValue::Color(Vec3::new(0.82, 0.67, 0.16));
    for params in [
        vec![],
        vec![("anisotropic", float(0.9)), ("metallic", float(1.0)), ("roughness", float(0.35))],
        vec![("clearcoat", float(1.0)), ("roughness", float(0.05))],
        // Rough, as a metal: over its diffuse base the model reflects more than it receives at 85° (Burley's
        // retro-reflection), which the energy test says of it.
        vec![("roughness", float(1.0)), ("metallic", float(1.0))],
    ] {
        brdfs.push(shipped("disney.brdf", &[&[("baseColor", gold)], &params[..]].concat()));
    }
    let mut renderer = renderer();
    for brdf in &brdfs {
        let options =
            SamplingOptions { views: views(&mut renderer, brdf, &DEFAULT_THETA_O, None).unwrap(), ..options() };
        let report = test_sampler(&mut renderer, brdf, &options, || ()).unwrap();
        assert!(report.passed(), "{}: {:#?}", vk_render::analysis::describe(brdf), failures(&report));
    }
}

/// `brdf` tabulated as a MERL table (each entry its value at the entry's centre), as `vk-render tabulate`
/// writes it.
fn measured(brdf: &Brdf) -> Brdf {
    Brdf::Measured(Measured::from_table(MeasuredTable::tabulate("tabulated.binary".into(), |wi, wo| {
        brdf.eval(Vec3::Z, wi, wo)
    })))
}

#[test]
fn every_measured_sampler_passes_from_sharp_to_rough() {
    // Tables of a sharp and a rough metal and of a diffuse model, each drawn from its own table's sampler.
    // The sharp metal's f0 below the gold's: the table's interpolation of so sharp a peak reflects a little
    // more than the model (an albedo of 1.02 seen head-on at f0 1), which the energy test would say.
    let sharp = Brdf::CookTorrance {
        kd: grey(0.5),
        f0: Vec3::new(0.9, 0.75, 0.5),
        roughness: 0.1,
        metalness: 1.0,
        diffuse: DiffuseModel::Lambert,
    };
    let mut renderer = renderer();
    for brdf in [sharp, gold(0.5, 0.5), Brdf::OrenNayar { kd: grey(0.5), sigma: 0.6 }] {
        let report = test_sampler(&mut renderer, &measured(&brdf), &options(), || ()).unwrap();
        assert!(report.passed(), "{brdf:?} as measured: {:#?}", failures(&report));
        assert!(report.views.iter().any(|v| v.chi_square.p_value < 0.95), "{brdf:?}");
    }
}

/// A mutant: one edit of the GLSL, the material it shows on, and the test that must catch it.
struct Mutant {
    name: &'static str,
    file: &'static str,
    from: &'static str,
    to: &'static str,
    brdf: Brdf,
    caught_by: &'static str,
}

fn mutants() -> Vec<Mutant> {
    vec![
        Mutant {
            name: "the half vector's Jacobian 1 / (4 wo.h) dropped",
            file: "common/sampling.glsl",
            from: "return cosine_power_pdf(n, m.shininess, h) / (4.0 * WoH);",
            to: "return cosine_power_pdf(n, m.shininess, h);",
            brdf: blinn_plastic(16.0),
            caught_by: "chi-square",
        },
        Mutant {
            name: "GGX's D (n.h) where the visible normals' density belongs",
            file: "common/sampling.glsl",
            from: "ggx_g1(NoV, alpha) * d_ggx(n, h, alpha) / (4.0 * NoV)",
            to: "d_ggx(n, h, alpha) * dot(n, h) / (4.0 * WoH)",
            brdf: gold(0.3, 1.0),
            caught_by: "chi-square",
        },
        Mutant {
            name: "a Phong exponent off by one in the sampler",
            file: "common/sampling.glsl",
            from: "float log_u = log(u.x) / (s + 1.0);",
            to: "float log_u = log(u.x) / (s + 2.0);",
            brdf: plastic(16.0),
            caught_by: "chi-square",
        },
        Mutant {
            name: "a measured table's half vector Jacobian 1 / (4 wo.h) dropped",
            file: "brdf/measured_sampler.glsl",
            from: "return density / (4.0 * max(dot(wo, h), 1e-12));",
            to: "return density;",
            brdf: measured(&gold(0.3, 1.0)),
            caught_by: "chi-square",
        },
        Mutant {
            name: "directions below the surface with a nonzero density",
            file: "common/sampling.glsl",
            from: "    if (dot(n, wi) <= 0.0) {\n        return 0.0;\n    }\n    float share",
            to: "    float share",
            brdf: plastic(16.0),
            caught_by: "density below the surface",
        },
        Mutant {
            name: "a sampler agreeing with its density but missing the BRDF's diffuse part",
            file: "common/sampling.glsl",
            from: "return lobe + diffuse > 0.0 ? lobe / (lobe + diffuse) : 1.0;",
            to: "return 1.0;",
            brdf: plastic(16.0),
            caught_by: "estimator",
        },
        Mutant {
            name: "a BRDF made non-reciprocal (Fresnel at the view's angle, not the half vector's)",
            file: "brdf/cook_torrance.glsl",
            from: "f_schlick(VoH, f0);",
            to: "f_schlick(NoV, f0);",
            brdf: Brdf::CookTorrance {
                kd: grey(0.5),
                f0: grey(0.04),
                roughness: 0.5,
                metalness: 1.0,
                diffuse: DiffuseModel::Lambert,
            },
            caught_by: "reciprocity",
        },
        Mutant {
            name: "a BRDF reflecting more than it receives (Lambert without its 1/π)",
            file: "brdf/lambert.glsl",
            from: "return kd * INV_PI;",
            to: "return kd;",
            brdf: Brdf::Lambert { kd: grey(0.5) },
            caught_by: "energy",
        },
    ]
}

#[test]
fn each_mutant_is_caught_by_its_test() {
    let mut renderer = renderer();
    let mut missed = Vec::new();
    for mutant in mutants() {
        let sources = ShaderSources::default().with_replaced(mutant.file, mutant.from, mutant.to).unwrap();
        renderer.set_shaders(sources).unwrap();
        let report = test_sampler(&mut renderer, &mutant.brdf, &options(), || ());
        renderer.set_shaders(ShaderSources::default()).unwrap();
        let report = report.unwrap();
        if !report.verdicts.iter().any(|v| v.test == mutant.caught_by && !v.passed) {
            missed.push(format!("{} (not caught by {}): {:#?}", mutant.name, mutant.caught_by, failures(&report)));
        }
    }
    // A .brdf file's sampler broken on purpose: Ward's density without the reflection's 1 / (4 V.H).
    let ward = common::shipped("ward.brdf");
    let text = ward.source().replace("NdotH * NdotH * NdotH * 4.0 * VdotH)", "NdotH * NdotH * NdotH)");
    assert_ne!(text, ward.source());
    let broken = vk_render::brdf::AnalyticModel::from_text(&ward.path, text).unwrap();
    let report = test_sampler(&mut renderer, &Brdf::Analytic(Analytic::defaults(broken.into())), &options(), || ());
    let report = report.unwrap();
    if !report.verdicts.iter().any(|v| v.test == "chi-square" && !v.passed) {
        missed.push(format!("ward.brdf's density without 1 / (4 V.H): {:#?}", failures(&report)));
    }
    assert!(missed.is_empty(), "{missed:#?}");
    // And the shaders put back pass again.
    assert!(test_sampler(&mut renderer, &plastic(16.0), &options(), || ()).unwrap().passed());
}

fn course_materials() -> String {
    root().join("assets/analysis/course-materials.toml").to_str().unwrap().to_string()
}

#[test]
fn the_command_passes_fails_and_refuses_as_documented() {
    let folder = temp_dir();
    let (report, csv) = (folder.path().join("report.png"), folder.path().join("views.csv"));
    let materials = course_materials();
    let passing = vk_render(&[
        "sampling",
        &materials,
        "--material",
        "gold",
        "--theta-o",
        "0,60",
        "--samples",
        "200000",
        "-o",
        report.to_str().unwrap(),
        "--csv",
        csv.to_str().unwrap(),
    ]);
    let stdout = String::from_utf8_lossy(&passing.stdout);
    assert_eq!(passing.status.code(), Some(0), "{stdout}{}", String::from_utf8_lossy(&passing.stderr));
    assert!(stdout.contains("sampling: every test passed"), "{stdout}");
    assert_eq!(image::open(&report).unwrap().width(), 1500);
    let text = std::fs::read_to_string(&csv).unwrap();
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("theta_o,phi_o,samples,chi_square,degrees_of_freedom,p_value"), "{}", lines[0]);
    assert_eq!(lines.len(), 3, "{text}");
    assert!(lines[2].starts_with("60,0,200000,") && lines[2].ends_with(",true"), "{}", lines[2]);

    // The course's Blinn-Phong at s = 0 reflects 1.29 of what it receives: exit 1, the test named.
    let failing = vk_render(&[
        "sampling",
        &materials,
        "--material",
        "blinn-phong",
        "--set",
        "material.blinn-phong.shininess=0",
        "--theta-o",
        "0",
        "--samples",
        "100000",
    ]);
    let stdout = String::from_utf8_lossy(&failing.stdout);
    assert_eq!(failing.status.code(), Some(1), "{stdout}");
    assert!(stdout.contains("sampling: FAILED: energy at θo 0° φo 0°"), "{stdout}");

    // Bad input: one line naming what is wrong, exit 2, no file.
    let written = folder.path().join("never.png");
    for (args, message) in [
        (vec!["--material", "chrome"], "chrome"),
        (vec!["--material", "gold", "--theta-o", "90"], "--theta-o 90"),
        (vec!["--material", "gold", "--samples", "10"], "--samples 10"),
        (vec!["--material", "gold", "--level", "1.5"], "--level 1.5"),
        (vec!["--material", "gold", "--csv", "numbers.txt"], "numbers.txt"),
    ] {
        let mut all = vec!["sampling", materials.as_str(), "-o", written.to_str().unwrap()];
        all.extend(args);
        let output = vk_render(&all);
        let stderr = String::from_utf8_lossy(&output.stderr);
        assert_eq!(output.status.code(), Some(2), "{all:?}: {stderr}");
        assert!(stderr.lines().count() == 1 && stderr.contains(message), "{all:?}: {stderr}");
        assert!(!written.exists());
    }
}
