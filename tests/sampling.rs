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
    options_at(&DEFAULT_THETA_O)
}

/// The views at `theta_o` (degrees, φo 0), 10⁶ samples each.
fn options_at(theta_o: &[f64]) -> SamplingOptions {
    SamplingOptions {
        views: theta_o.iter().map(|&t| (t, 0.0)).collect(),
        samples: DEFAULT_SAMPLES,
        seed: 1,
        level: DEFAULT_LEVEL,
    }
}

/// Three views of θo (degrees): head-on, where a sharp peak sits on the pole, halfway and grazing.
const THREE_VIEWS: [f64; 3] = [0.0, 40.0, 85.0];

/// How much of each model's range a test of the samplers covers. `make test` takes the two ends of each
/// family's list (its sharpest lobe first; its roughest, or its most anisotropic, last) at
/// [`THREE_VIEWS`]. `make test-long` takes the whole list at every default view (one to three minutes a
/// test on 2 cores).
#[derive(Clone, Copy)]
enum Range {
    Ends,
    Whole,
}

impl Range {
    /// `values` (one family's list, its sharpest first) as this range takes them.
    fn of<T: Clone>(self, values: &[T]) -> Vec<T> {
        match self {
            Range::Whole => values.to_vec(),
            Range::Ends => vec![values[0].clone(), values[values.len() - 1].clone()],
        }
    }

    /// The views of θo (degrees) a model is tested at, and the samples drawn at each: the command's 10⁶ over
    /// the whole range, 2¹⁸ at the ends (χ² at 10⁶ samples is `make test-long`'s; the mutants, each caught
    /// at the ends' views, are drawn at 10⁶).
    fn options(self) -> SamplingOptions {
        match self {
            Range::Whole => options_at(&DEFAULT_THETA_O),
            Range::Ends => SamplingOptions { samples: 1 << 18, ..options_at(&THREE_VIEWS) },
        }
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
fn the_built_in_samplers_pass_at_both_ends_of_their_range() {
    let brdfs = [&diffuse()[..], &cook_torrance(Range::Ends), &phong_and_blinn_phong(Range::Ends)].concat();
    built_in_samplers_pass(&brdfs, Range::Ends);
}

// The whole ranges in two tests, which run side by side.
#[test]
#[ignore = "long: make test-long"]
fn every_cook_torrance_sampler_passes_from_sharp_to_rough() {
    built_in_samplers_pass(&cook_torrance(Range::Whole), Range::Whole);
}

#[test]
#[ignore = "long: make test-long"]
fn every_phong_and_diffuse_sampler_passes_from_sharp_to_rough() {
    built_in_samplers_pass(&[&diffuse()[..], &phong_and_blinn_phong(Range::Whole)].concat(), Range::Whole);
}

/// The diffuse models.
fn diffuse() -> [Brdf; 2] {
    [Brdf::Lambert { kd: grey(0.5) }, Brdf::OrenNayar { kd: grey(0.5), sigma: 0.6 }]
}

/// Cook-Torrance from roughness 0.01 (GGX's α = 10⁻⁴) to 1, a metal and half a metal over Oren-Nayar.
fn cook_torrance(range: Range) -> Vec<Brdf> {
    range.of(&[0.01, 0.1, 0.3, 0.6, 1.0]).into_iter().flat_map(|r| [gold(r, 1.0), gold(r, 0.5)]).collect()
}

/// Phong's and Blinn-Phong's lobes from s = 4 to 10⁵ (α about 0.006 as a Beckmann lobe: below s = 4 the
/// course's Blinn-Phong reflects more than it receives, which the energy test says).
fn phong_and_blinn_phong(range: Range) -> Vec<Brdf> {
    range.of(&[4.0, 16.0, 1000.0, 1e5]).into_iter().flat_map(|s| [plastic(s), blinn_plastic(s)]).collect()
}

/// Each of `brdfs` passes every test at `range`'s views.
fn built_in_samplers_pass(brdfs: &[Brdf], range: Range) {
    let mut renderer = renderer();
    for brdf in brdfs {
        let report = test_sampler(&mut renderer, brdf, &range.options(), || ()).unwrap();
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
fn the_shipped_samplers_pass_at_both_ends_of_their_range() {
    shipped_samplers_pass(Range::Ends);
}

#[test]
#[ignore = "long: make test-long"]
fn every_shipped_sampler_passes_from_sharp_to_rough() {
    shipped_samplers_pass(Range::Whole);
}

fn shipped_samplers_pass(range: Range) {
    // GGX's visible normals (Walter et al.'s model), Ward's half vectors (Walter 2005), Lafortune's cosine
    // lobes, Ashikhmin and Shirley's and the Disney BRDF's lobes, sharp to rough, over a diffuse base, isotropic and anisotropic both ways, at every view and,
    // where the model is anisotropic, every azimuth.
    let float = ParameterValue::Float;
    let grey = |v: f32| ParameterValue::Color(Vec3::splat(v));
    let mut brdfs = Vec::new();
    for alpha in range.of(&[0.01, 0.1, 0.4, 1.0]) {
        brdfs.push(shipped("walter_ggx.brdf", &[("alpha", float(alpha)), ("kd", grey(0.1)), ("f0", grey(0.5))]));
    }
    for (x, y) in range.of(&[(0.01, 0.01), (0.2, 0.2), (1.0, 1.0), (0.05, 0.4)]) {
        let params = [("alpha_x", float(x)), ("alpha_y", float(y)), ("rho_d", grey(0.3)), ("rho_s", grey(0.1))];
        brdfs.push(shipped("ward.brdf", &params));
    }
    for (nu, nv) in range.of(&[(1e4, 1e4), (100.0, 100.0), (1.0, 1.0), (20.0, 800.0)]) {
        let params = [("nu", float(nu)), ("nv", float(nv)), ("Rd", grey(0.3)), ("Rs", grey(0.3))];
        brdfs.push(shipped("ashikhmin_shirley.brdf", &params));
    }
    // Lafortune's generalized cosine lobe about its own axis: the sharpest modified Phong lobe, off-specular
    // towards grazing (Cxy -0.7), and about the normal (Cxy 0).
    for (cxy, n) in range.of(&[(-1.0, 2000.0), (-0.7, 60.0), (0.0, 20.0)]) {
        let params = [("Cxy", float(cxy)), ("n", float(n)), ("rho_d", grey(0.3)), ("rho_s", grey(0.3))];
        brdfs.push(shipped("lafortune.brdf", &params));
    }
    // The Disney BRDF by its lobes: a sharp clearcoat over a sharp lobe, its defaults, the roughest metal,
    // an anisotropic metal.
    let gold = ParameterValue::Color(Vec3::new(0.82, 0.67, 0.16));
    for params in range.of(&[
        &[("clearcoat", float(1.0)), ("roughness", float(0.05))][..],
        &[],
        // Rough, as a metal: over its diffuse base the model reflects more than it receives at 85° (Burley's
        // retro-reflection), which the energy test says of it.
        &[("roughness", float(1.0)), ("metallic", float(1.0))],
        &[("anisotropic", float(0.9)), ("metallic", float(1.0)), ("roughness", float(0.35))],
    ]) {
        brdfs.push(shipped("disney.brdf", &[&[("baseColor", gold)], params].concat()));
    }
    let mut renderer = renderer();
    for brdf in &brdfs {
        let options = range.options();
        let theta_o: Vec<f64> = options.views.iter().map(|view| view.0).collect();
        let options = SamplingOptions { views: views(&mut renderer, brdf, &theta_o, None).unwrap(), ..options };
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
fn the_measured_samplers_pass_at_both_ends_of_their_range() {
    measured_samplers_pass(Range::Ends);
}

#[test]
#[ignore = "long: make test-long"]
fn every_measured_sampler_passes_from_sharp_to_rough() {
    measured_samplers_pass(Range::Whole);
}

fn measured_samplers_pass(range: Range) {
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
    for brdf in range.of(&[sharp, gold(0.5, 0.5), Brdf::OrenNayar { kd: grey(0.5), sigma: 0.6 }]) {
        let report = test_sampler(&mut renderer, &measured(&brdf), &range.options(), || ()).unwrap();
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
            file: "brdf/blinn_phong.glsl",
            from: "return cosine_power_pdf(n, shininess, h) / (4.0 * WoH);",
            to: "return cosine_power_pdf(n, shininess, h);",
            brdf: blinn_plastic(16.0),
            caught_by: "chi-square",
        },
        Mutant {
            name: "GGX's D (n.h) where the visible normals' density belongs",
            file: "brdf/cook_torrance.glsl",
            from: "ggx_g1(NoV, alpha) * d_ggx(n, h, alpha) / (4.0 * NoV)",
            to: "d_ggx(n, h, alpha) * dot(n, h) / (4.0 * WoH)",
            brdf: gold(0.3, 1.0),
            caught_by: "chi-square",
        },
        Mutant {
            name: "a Phong exponent off by one in the sampler",
            file: "common/warp.glsl",
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
        let report = test_sampler(&mut renderer, &mutant.brdf, &options_at(&THREE_VIEWS), || ()).unwrap();
        if !report.verdicts.iter().any(|v| v.test == mutant.caught_by && !v.passed) {
            missed.push(format!("{} (not caught by {}): {:#?}", mutant.name, mutant.caught_by, failures(&report)));
        }
    }
    renderer.set_shaders(ShaderSources::default()).unwrap();
    // A .brdf file's sampler broken on purpose: Ward's density without the reflection's 1 / (4 V.H).
    let ward = common::shipped("ward.brdf");
    let text = ward.source().replace("NdotH * NdotH * NdotH * 4.0 * VdotH)", "NdotH * NdotH * NdotH)");
    assert_ne!(text, ward.source());
    let broken = vk_render::brdf::AnalyticModel::from_text(&ward.path, text).unwrap();
    let report = test_sampler(
        &mut renderer,
        &Brdf::Analytic(Analytic::defaults(broken.into())),
        &options_at(&THREE_VIEWS),
        || (),
    );
    let report = report.unwrap();
    if !report.verdicts.iter().any(|v| v.test == "chi-square" && !v.passed) {
        missed.push(format!("ward.brdf's density without 1 / (4 V.H): {:#?}", failures(&report)));
    }
    assert!(missed.is_empty(), "{missed:#?}");
    // And the shaders put back pass again.
    assert!(test_sampler(&mut renderer, &plastic(16.0), &options_at(&THREE_VIEWS), || ()).unwrap().passed());
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

/// `tests/sampling/burley_ggx.brdf` at `roughness`, base 0.25 and F0 0.3 (base 0.3 and F0 0.5 reflect more
/// than they receive at 85°, Burley's retro-reflection, which the energy test says).
fn burley_ggx(roughness: f32) -> Brdf {
    let model = vk_render::brdf::AnalyticModel::load(&root().join("tests/sampling/burley_ggx.brdf")).unwrap();
    let material = [("roughness", roughness), ("base", 0.25), ("f0", 0.3)]
        .into_iter()
        .try_fold(Analytic::defaults(model), |m, (name, value)| m.with(name, ParameterValue::Float(value)))
        .unwrap();
    Brdf::Analytic(material)
}

/// The density and f_r cos θi of `burley_ggx.brdf` seen head-on, at θi, per unit solid angle, in double
/// precision: a mirror written for this test, the parameters as the GPU holds them (float32).
fn burley_ggx_head_on(roughness: f32, theta_i: f64) -> (f64, f64) {
    use std::f64::consts::PI;
    let (r, base, f0, share) = (f64::from(roughness), f64::from(0.25f32), f64::from(0.3f32), 0.5);
    let a2 = r.powi(4);
    let ggx = |c: f64| a2 / (PI * (c * c * (a2 - 1.0) + 1.0).powi(2));
    let g1 = |c: f64| 2.0 * c / (c + (a2 + (1.0 - a2) * c * c).sqrt());
    // Seen head-on the half vector is θi / 2 from the normal, and from both directions.
    let (n_l, n_h) = (theta_i.cos(), (theta_i / 2.0).cos());
    let pdf = share * ggx(n_h) / 4.0 + (1.0 - share) * n_l / PI;
    let fd90 = 0.5 + 2.0 * r * n_h * n_h;
    let diffuse = base / PI * (1.0 + (fd90 - 1.0) * (1.0 - n_l).powi(5));
    let fresnel = f0 + (1.0 - f0) * (1.0 - n_h).powi(5);
    let specular = fresnel * ggx(n_h) * g1(n_l) * g1(1.0) / (4.0 * n_l);
    (pdf, (diffuse + specular) * n_l)
}

/// The integral over the hemisphere of a function of θi alone, 2π ∫ g(θ) sin θ dθ: composite Simpson on
/// panels that double in width from 1e-7 rad at the pole, where the lobe is, to π/2, 2000 intervals each.
fn head_on_integral(g: impl Fn(f64) -> f64) -> f64 {
    let mut edges = vec![0.0, 1e-7];
    while *edges.last().unwrap() < std::f64::consts::FRAC_PI_2 {
        let next = (edges.last().unwrap() * 2.0).min(std::f64::consts::FRAC_PI_2);
        edges.push(next);
    }
    let mut total = 0.0;
    for pair in edges.windows(2) {
        let (a, b) = (pair[0], pair[1]);
        let n = 2000;
        let h = (b - a) / n as f64;
        let f = |t: f64| g(t) * t.sin();
        let mut sum = f(a) + f(b);
        for k in 1..n {
            sum += f(a + k as f64 * h) * if k % 2 == 1 { 4.0 } else { 2.0 };
        }
        total += sum * h / 3.0;
    }
    2.0 * std::f64::consts::PI * total
}

#[test]
fn a_sharp_lobe_seen_head_on_is_integrated_within_its_stated_bound() {
    // The file's float32 density at roughness 0.08 seen head-on integrates to 1.00037 (its D rounds a^2 - 1),
    // which the command stated as 1.000374 ± 6.7e-5 and failed; the model's is 0.99998. The commands now
    // integrate a .brdf file in double precision: every stated integral within its bound of an independent
    // one, and the sampler, right, passes at every view.
    let mut renderer = renderer();
    let brdf = burley_ggx(0.08);
    let options = SamplingOptions { views: views(&mut renderer, &brdf, &DEFAULT_THETA_O, None).unwrap(), ..options() };
    let report = test_sampler(&mut renderer, &brdf, &options, || ()).unwrap();
    assert!(report.passed(), "{:#?}", failures(&report));
    let head_on = &report.views[0];
    assert!(head_on.in_double && head_on.theta_o == 0.0);
    let density = head_on_integral(|t| burley_ggx_head_on(0.08, t).0);
    let albedo = head_on_integral(|t| burley_ggx_head_on(0.08, t).1);
    let (integral, bound) = head_on.density_integral();
    assert!((integral - density).abs() <= bound + 1e-9, "{integral} ± {bound} against {density}");
    assert!(
        (head_on.albedo()[0] - albedo).abs() <= head_on.cells.f_cos_error + 1e-9,
        "{:?} against {albedo}",
        head_on.albedo()
    );
    // `plot albedo`'s cubature, at 0 and 1° (where the float32 one stated 2.2e-4 and was 4.2e-4 off).
    let stated = vk_render::analysis::albedo::directional_albedos(&mut renderer, &brdf, &[0.0], 1e-5).unwrap();
    assert!((stated[0].rho[0] - albedo).abs() <= stated[0].error_bound + 1e-9, "{:?} against {albedo}", stated[0]);
}

#[test]
fn the_double_precision_functions_are_rusts_and_a_broken_one_is_caught() {
    // A .brdf file whose BRDF is GLSL's float-only functions of L's x and y, evaluated in double precision
    // (shaders/common/float64.glsl) at directions with z = 1, against Rust's f64.
    type Function = (&'static str, fn(f64, f64) -> f64);
    let sets: [[Function; 3]; 5] = [
        [
            ("exp(30.0 * x)", |x, _| (30.0 * x).exp()),
            ("log(1e-3 + abs(y) * 1e3)", |_, y| (1e-3 + y.abs() * 1e3).ln()),
            ("pow(abs(x) + 0.01, 7.3 * y)", |x, y| (x.abs() + 0.01).powf(7.3 * y)),
        ],
        [
            ("sin(50.0 * x)", |x, _| (50.0 * x).sin()),
            ("cos(50.0 * y)", |_, y| (50.0 * y).cos()),
            ("tan(1.5 * x)", |x, _| (1.5 * x).tan()),
        ],
        [("atan(10.0 * x)", |x, _| (10.0 * x).atan()), ("atan(y, x)", |x, y| y.atan2(x)), ("asin(y)", |_, y| y.asin())],
        [
            ("acos(x)", |x, _| x.acos()),
            ("sinh(3.0 * y)", |_, y| (3.0 * y).sinh()),
            ("tanh(2.0 * x)", |x, _| (2.0 * x).tanh()),
        ],
        [
            ("exp2(10.0 * x)", |x, _| (10.0 * x).exp2()),
            ("log2(abs(y) + 0.1)", |_, y| (y.abs() + 0.1).log2()),
            ("atanh(0.9 * x) + asinh(y) + acosh(2.0 + x)", |x, y| (0.9 * x).atanh() + y.asinh() + (2.0 + x).acosh()),
        ],
    ];
    let directions: Vec<glam::DVec3> = (0..41)
        .flat_map(|i| {
            (0..41).map(move |j| glam::DVec3::new(-1.0 + 0.05 * i as f64 + 1e-3, -1.0 + 0.05 * j as f64 + 2e-3, 1.0))
        })
        .collect();
    let folder = temp_dir();
    let worst_error = |renderer: &mut vk_render::Renderer, set: &[Function; 3], index: usize| -> f64 {
        let path = folder.path().join(format!("functions{index}.brdf"));
        let body = format!(
            "analytic\n::begin parameters\nfloat unused 0 1 0\n::end parameters\n::begin shader\nvec3 BRDF(vec3 L, vec3 V, \
             vec3 N, vec3 X, vec3 Y)\n{{\n    float x = L.x;\n    float y = L.y;\n    return vec3({}, {}, {});\n}}\n::end shader\n",
            set[0].0, set[1].0, set[2].0
        );
        std::fs::write(&path, body).unwrap();
        let brdf = Brdf::Analytic(Analytic::defaults(vk_render::brdf::AnalyticModel::load(&path).unwrap()));
        let values = renderer.brdf_sampler_densities_double(&brdf, Vec3::Z, &directions).unwrap().expect("doubles");
        let mut worst = 0.0f64;
        for (d, v) in directions.iter().zip(&values) {
            for (k, (_, f)) in set.iter().enumerate() {
                let expected = f(d.x, d.y);
                worst = worst.max((v[k + 1] - expected).abs() / expected.abs().max(1.0));
            }
        }
        worst
    };
    let mut renderer = renderer();
    for (index, set) in sets.iter().enumerate() {
        let worst = worst_error(&mut renderer, set, index);
        assert!(worst < 1e-14, "{:?}: {worst:e}", set.map(|f| f.0));
    }
    drop(renderer);
    // exp's series cut before its r^8 term, sin's before its r^11: caught.
    let source = ShaderSources::default();
    let float64 = source.text("common/float64.glsl").unwrap();
    let cuts = [
        ("for (int n = 13; n >= 1; --n)", "for (int n = 7; n >= 1; --n)", 0),
        ("f64_odd_series(-r2, 9)", "f64_odd_series(-r2, 4)", 1),
    ];
    for (series, cut, set) in cuts {
        assert!(float64.contains(series));
        let mut mutant = common::renderer_with_shaders(
            source.clone().with_file("common/float64.glsl", float64.replace(series, cut)),
        );
        let worst = worst_error(&mut mutant, &sets[set], 10 + set);
        assert!(worst > 1e-12, "{cut}: {worst:e}");
    }
}
