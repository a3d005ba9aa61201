//! Every GLSL BRDF, evaluated on the GPU by the probe pass, against its Rust mirror: over a grid of
//! (theta_i, theta_o, delta phi) including grazing angles, and of parameters, at least 4000 cases per model.

mod common;

use glam::{Mat3, Vec3};
use vk_render::brdf::{Brdf, DiffuseModel};
use vk_render::render::ProbeCase;

/// Polar angles (degrees), grazing ones included; 90 is exactly on the horizon, where only finiteness is
/// checked (see [`sign_determined`]).
const THETAS: [f32; 11] = [0.0, 5.0, 20.0, 35.0, 45.0, 60.0, 75.0, 85.0, 89.0, 89.9, 90.0];
/// Azimuth differences (degrees).
const DELTA_PHIS: [f32; 7] = [0.0, 10.0, 45.0, 90.0, 135.0, 179.0, 180.0];

/// Two shading frames: the z axis and a tilted normal, so that no formula depends on n = +z.
fn frames() -> [Mat3; 2] {
    let tilted = Vec3::new(0.3, -0.5, 0.8).normalize();
    let (t, b) = tilted.any_orthonormal_pair();
    [Mat3::IDENTITY, Mat3::from_cols(t, b, tilted)]
}

fn direction(frame: &Mat3, theta: f32, phi: f32) -> Vec3 {
    let (t, p) = (theta.to_radians(), phi.to_radians());
    (*frame * Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())).normalize()
}

fn cases(models: &[Brdf]) -> Vec<ProbeCase> {
    let mut cases = Vec::new();
    for brdf in models {
        for frame in frames() {
            for theta_i in THETAS {
                for theta_o in THETAS {
                    for delta_phi in DELTA_PHIS {
                        let (wi, wo) = (direction(&frame, theta_i, 30.0), direction(&frame, theta_o, 30.0 + delta_phi));
                        cases.push(ProbeCase { brdf: brdf.clone(), n: frame.z_axis, wi, wo });
                    }
                }
            }
        }
    }
    cases
}

/// Runs the probe and compares with the Rust mirror: relative error <= 1e-4, absolute floor 1e-6.
fn gpu_matches_rust(name: &str, models: &[Brdf]) {
    let cases = cases(models);
    let compared = cases.iter().filter(|c| sign_determined(c)).count();
    assert!(compared >= 4000, "{name}: only {compared} cases compared");
    let gpu = common::renderer().probe_brdfs(&cases).expect("probe with no validation message");
    let (error, i) = worst_error(&cases, &gpu, name);
    let case = &cases[i];
    assert!(
        error <= 1.0,
        "{name}: GPU {} vs Rust {} ({error:.2}x the tolerance) for {case:?}",
        gpu[i],
        case.brdf.eval(case.n, case.wi, case.wo)
    );
}

/// Whether the side of the horizon of both directions is certain. At exactly 90 degrees n . w is a rounding
/// error (about 1e-8), and its sign decides whether a BRDF is zero: it depends on how the driver orders and
/// contracts the dot product's multiply-adds, so two right answers can differ there. Such cases are only
/// checked to be finite.
fn sign_determined(case: &ProbeCase) -> bool {
    let n = case.n.as_dvec3();
    [case.wi, case.wo].iter().all(|w| n.dot(w.as_dvec3()).abs() > 1e-5)
}

/// The largest error in units of the tolerance, and the case it occurs at, over the cases whose directions'
/// sides of the horizon are certain; every case must be finite.
fn worst_error(cases: &[ProbeCase], gpu: &[Vec3], name: &str) -> (f32, usize) {
    let mut worst = (0.0f32, 0usize);
    for (i, (case, g)) in cases.iter().zip(gpu).enumerate() {
        assert!(g.is_finite(), "{name}: GPU gave {g} for {case:?}");
        if !sign_determined(case) {
            continue;
        }
        let cpu = case.brdf.eval(case.n, case.wi, case.wo);
        let error = ((*g - cpu).abs() / (cpu.abs() * 1e-4).max(Vec3::splat(1e-6))).max_element();
        if error > worst.0 {
            worst = (error, i);
        }
    }
    worst
}

const KD: Vec3 = Vec3::new(0.8, 0.5, 0.2);
const GOLD: Vec3 = Vec3::new(1.0, 0.85, 0.57);

#[test]
fn lambert_on_the_gpu_equals_the_rust_mirror() {
    let models: Vec<Brdf> = [KD, Vec3::splat(0.5), Vec3::ONE, Vec3::ZERO].map(|kd| Brdf::Lambert { kd }).to_vec();
    gpu_matches_rust("lambert", &models);
}

#[test]
fn oren_nayar_on_the_gpu_equals_the_rust_mirror() {
    let models: Vec<Brdf> = [0.0, 0.2, 0.4, 0.6, 1.5].map(|sigma| Brdf::OrenNayar { kd: KD, sigma }).to_vec();
    gpu_matches_rust("oren-nayar", &models);
}

#[test]
fn phong_on_the_gpu_equals_the_rust_mirror() {
    let ks = Vec3::splat(0.3);
    let models: Vec<Brdf> =
        [0.0, 1.0, 8.0, 16.0, 64.0].map(|shininess| Brdf::Phong { kd: KD * 0.7, ks, shininess }).to_vec();
    gpu_matches_rust("phong", &models);
}

#[test]
fn blinn_phong_on_the_gpu_equals_the_rust_mirror() {
    let ks = Vec3::splat(0.3);
    let models: Vec<Brdf> =
        [0.0, 1.0, 8.0, 16.0, 64.0].map(|shininess| Brdf::BlinnPhong { kd: KD * 0.7, ks, shininess }).to_vec();
    gpu_matches_rust("blinn-phong", &models);
}

#[test]
fn cook_torrance_on_the_gpu_equals_the_rust_mirror() {
    let mut models = Vec::new();
    for roughness in [0.05, 0.3, 0.6, 1.0] {
        for (metalness, diffuse) in
            [(0.0, DiffuseModel::OrenNayar), (0.5, DiffuseModel::Lambert), (1.0, DiffuseModel::OrenNayar)]
        {
            models.push(Brdf::CookTorrance { kd: GOLD, f0: GOLD, roughness, metalness, diffuse });
        }
    }
    gpu_matches_rust("cook-torrance", &models);
}

#[test]
fn a_wrong_schlick_exponent_fails_the_probe_comparison() {
    // The comparison must catch a real mistake: (1 - h.wo)^4 instead of ^5.
    let mut renderer = common::mutant_renderer("brdf/cook_torrance.glsl", "(m2 * m2 * m)", "(m2 * m2)");
    let models = [Brdf::CookTorrance {
        kd: GOLD,
        f0: Vec3::splat(0.04),
        roughness: 0.3,
        metalness: 1.0,
        diffuse: DiffuseModel::Lambert,
    }];
    let cases = cases(&models);
    let gpu = renderer.probe_brdfs(&cases).unwrap();
    let (error, _) = worst_error(&cases, &gpu, "broken cook-torrance");
    assert!(error > 100.0, "the broken Fresnel went unnoticed (worst error {error}x the tolerance)");
}

/// The grid probe (every material at every direction pair, as the fits ask for lobes) gives exactly what the
/// list of its cases does: materials of several pipelines (the built-ins and an analytic file), three Lambert
/// ones among them (one pipeline: 1.2 million evaluations, over two dispatches of at most 2^20 each, the
/// boundary inside the third one's lobe), given apart in the list.
#[test]
fn a_grid_of_materials_and_directions_gives_what_the_list_of_its_cases_does() {
    let ward = vk_render::brdf::Analytic::defaults(common::shipped("ward.brdf"));
    let lambert = |kd: f32| Brdf::Lambert { kd: Vec3::new(kd, 0.4, 0.3) };
    let models = [
        lambert(0.5),
        lambert(0.6),
        Brdf::BlinnPhong { kd: Vec3::splat(0.2), ks: Vec3::splat(0.5), shininess: 30.0 },
        lambert(0.7),
        Brdf::Analytic(ward),
    ];
    let count = 400_000;
    let pairs: Vec<(Vec3, Vec3)> = (0..count)
        .map(|k| {
            let t = k as f32 / count as f32;
            (
                direction(&Mat3::IDENTITY, 89.0 * t, 360.0 * t * 7.0),
                direction(&Mat3::IDENTITY, 80.0 * (1.0 - t), 13.0 * k as f32),
            )
        })
        .collect();
    let mut renderer = common::renderer();
    let grid = renderer.probe_brdf_grid(&models, &pairs).expect("probe with no validation message");
    assert_eq!(grid.len(), models.len() * count);
    // Every 997th element, and those around the Lambert pipeline's dispatch boundary (its 2^20th case: the
    // third Lambert material, models[3], at pair 2^20 - 2 count) and the materials' boundaries.
    let boundary = 3 * count + ((1usize << 20) - 2 * count);
    let chosen: Vec<usize> = (0..grid.len())
        .filter(|&i| i % 997 == 0 || i.abs_diff(boundary) < 3 || (i % count < 2 || i % count > count - 3))
        .collect();
    let cases: Vec<ProbeCase> = chosen
        .iter()
        .map(|&i| {
            let (wi, wo) = pairs[i % count];
            ProbeCase { brdf: models[i / count].clone(), n: Vec3::Z, wi, wo }
        })
        .collect();
    let listed = renderer.probe_brdfs(&cases).expect("probe with no validation message");
    for (&i, value) in chosen.iter().zip(&listed) {
        assert_eq!(grid[i], *value, "element {i}: material {}, pair {}", i / count, i % count);
    }
    assert!(listed.iter().filter(|v| v.max_element() > 0.0).count() > chosen.len() / 4, "mostly zeros");
}
