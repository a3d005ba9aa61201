//! The GPU's images against the independent CPU reference, on scenes beyond the figures, and proof that
//! the comparison catches real mistakes: shaders broken on purpose must fail it.

mod common;

use common::*;
use vk_render::pictures::compare::{compare, silhouette_band, Comparison};
use vk_render::{reference, Scene};

#[test]
fn scenes_beyond_the_figures_match_the_reference() {
    for name in ["five-brdfs.toml", "two-spheres.toml", "side-light-metal.toml"] {
        let scene = test_scene(name);
        // Shadow edges fall on different pixels in a shadow map than in a ray tracer: no bound on the maximum.
        let c = check_against_reference(name, &scene, |c| acceptable(c) && c.mean_abs <= 0.05);
        eprintln!("{name}: {c}");
    }
}

/// Renders `scene` with one shader file edited (`from` replaced by `to`) and compares with the reference.
fn compare_mutant(shader: &str, from: &str, to: &str, scene: &Scene) -> Comparison {
    let mut renderer = mutant_renderer(shader, from, to);
    let gpu = renderer.render(scene).unwrap().to_rgb8(&scene.image);
    let traced = reference::render(scene).unwrap();
    let band = silhouette_band(&traced.object_ids, scene.image.width, scene.image.height, 2);
    let c = compare(&gpu, &traced.image.to_rgb8(&scene.image), &band);
    eprintln!("{shader} with {from:?} -> {to:?}: {c}");
    c
}

fn asset(name: &str) -> Scene {
    asset_scene(name, &[])
}

#[test]
fn lambert_without_its_1_over_pi_fails() {
    let c = compare_mutant("brdf/lambert.glsl", "return kd * INV_PI;", "return kd;", &asset("fig1-lambert.toml"));
    assert!(!acceptable(&c), "the mutant passed: {c}");
}

#[test]
fn a_wrong_schlick_exponent_fails() {
    let c =
        compare_mutant("brdf/cook_torrance.glsl", "(m2 * m2 * m)", "(m2 * m2)", &test_scene("side-light-metal.toml"));
    assert!(!acceptable(&c), "the mutant passed: {c}");
}

#[test]
fn smith_k_from_alpha_instead_of_roughness_fails() {
    let c = compare_mutant(
        "brdf/cook_torrance.glsl",
        "v_smith_schlick(NoV, NoL, smith_schlick_k(roughness))",
        "v_smith_schlick(NoV, NoL, smith_schlick_k(ggx_alpha(roughness)))",
        &test_scene("side-light-metal.toml"),
    );
    assert!(!acceptable(&c), "the mutant passed: {c}");
}

#[test]
fn phong_without_its_1_over_cos_fails() {
    let c = compare_mutant("brdf/phong.glsl", "/ max(NoL, MIN_COS_THETA_I)", "", &asset("fig6-phong.toml"));
    assert!(!acceptable(&c), "the mutant passed: {c}");
}

#[test]
fn oren_nayar_without_its_b_term_fails() {
    let c = compare_mutant(
        "brdf/oren_nayar.glsl",
        "oren_nayar_a(sigma) + oren_nayar_b(sigma) * cos_phi * sin_alpha * tan_beta",
        "oren_nayar_a(sigma)",
        &test_scene("five-brdfs.toml"),
    );
    assert!(!acceptable(&c), "the mutant passed: {c}");
}
