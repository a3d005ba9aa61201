//! Hand-worked values and properties of every BRDF (the GPU is checked against these functions in
//! tests/brdf_gpu.rs).

use std::f32::consts::PI;

use glam::Vec3;

use super::*;

const N: Vec3 = Vec3::Z;

/// A unit direction at polar angle theta and azimuth phi (degrees) about N = +z.
fn dir(theta: f32, phi: f32) -> Vec3 {
    let (t, p) = (theta.to_radians(), phi.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

fn close(a: Vec3, b: Vec3, tolerance: f32) -> bool {
    (a - b).abs().max_element() <= tolerance * b.abs().max_element().max(1e-6)
}

#[test]
fn oren_nayar_by_hand() {
    // sigma = 0.5: A = 1 - 0.5 * 0.25/0.58 = 0.784483, B = 0.45 * 0.25/0.34 = 0.330882.
    assert!((oren_nayar_a(0.5) - 0.784_483).abs() < 1e-6);
    assert!((oren_nayar_b(0.5) - 0.330_882).abs() < 1e-6);
    // theta_i = 60, theta_o = 30, same azimuth: sin(60) tan(30) = 0.5, cos(phi_i - phi_o) = 1,
    // f = (0.784483 + 0.330882 * 0.5) / pi = 0.302370.
    let f = Brdf::OrenNayar { kd: Vec3::ONE, sigma: 0.5 }.eval(N, dir(60.0, 0.0), dir(30.0, 0.0));
    assert!(close(f, Vec3::splat(0.302_370), 1e-5), "{f}");
    // Azimuths 90 degrees apart: the B term vanishes, f = A / pi.
    let f = Brdf::OrenNayar { kd: Vec3::ONE, sigma: 0.5 }.eval(N, dir(60.0, 0.0), dir(30.0, 90.0));
    assert!(close(f, Vec3::splat(0.784_483 / PI), 1e-5), "{f}");
    // The course's Figure 2, sigma = 0.6, sphere centre (wi = wo = n): A = 0.739130, radiance 0.5/pi * A * 60/16
    // = 0.441136 -> 112.
    let f = Brdf::OrenNayar { kd: Vec3::splat(0.5), sigma: 0.6 }.eval(N, N, N);
    assert_eq!((f.x * 60.0 / 16.0 * 255.0) as u8, 112);
}

#[test]
fn phong_by_hand() {
    let plastic = Brdf::Phong { kd: Vec3::splat(0.5), ks: Vec3::splat(0.3), shininess: 16.0 };
    // wo on the mirror direction of wi (45 degrees): cos(alpha) = 1, f = 0.5/pi + 0.3 / cos(45)
    // = 0.159155 + 0.424264 = 0.583419.
    let f = plastic.eval(N, dir(45.0, 0.0), dir(45.0, 180.0));
    assert!(close(f, Vec3::splat(0.583_419), 1e-5), "{f}");
    // 10 degrees off the mirror direction: 0.159155 + 0.3 * cos(10)^16 / cos(45) = 0.491248.
    let f = plastic.eval(N, dir(45.0, 0.0), dir(55.0, 180.0));
    assert!(close(f, Vec3::splat(0.491_248), 1e-5), "{f}");
}

#[test]
fn blinn_phong_by_hand() {
    let plastic = Brdf::BlinnPhong { kd: Vec3::splat(0.5), ks: Vec3::splat(0.3), shininess: 8.0 };
    // wi at 45 degrees, wo = n: h is at 22.5 degrees, cos(22.5)^8 = 0.530790,
    // f = 0.5/pi + 0.3 * 0.530790 / cos(45) = 0.384350.
    let f = plastic.eval(N, dir(45.0, 0.0), N);
    assert!(close(f, Vec3::splat(0.384_350), 1e-5), "{f}");
}

#[test]
fn cook_torrance_by_hand() {
    let f0 = Vec3::new(1.0, 0.85, 0.57);
    // Normal incidence and view, roughness 0.5: alpha = 0.25, D = 1/(pi alpha^2) = 5.092958, G = 1, F = F0,
    // spec = D F G / 4 = 1.273240 F0.
    let metal = Brdf::CookTorrance { kd: f0, f0, roughness: 0.5, metalness: 1.0, diffuse: DiffuseModel::OrenNayar };
    assert!((d_ggx(N, N, 0.25) - 5.092_958).abs() < 1e-5);
    assert!(close(metal.eval(N, N, N), 1.273_24 * f0, 1e-5));
    // wi at 60 degrees, wo = n, roughness 0.5, F0 = 0.04: h at 30 degrees, D = 0.225727,
    // k = 1.5^2/8 = 0.28125, G = 0.5/(0.5*0.71875+0.28125) * 1 = 0.780488, F = 0.04 + 0.96 (1-cos 30)^5
    // = 0.040041, spec = D F G / (4 * 0.5 * 1) = 0.00352719.
    let dielectric = Brdf::CookTorrance {
        kd: Vec3::ZERO,
        f0: Vec3::splat(0.04),
        roughness: 0.5,
        metalness: 1.0,
        diffuse: DiffuseModel::Lambert,
    };
    assert!((smith_schlick_k(0.5) - 0.281_25).abs() < 1e-7);
    let f = dielectric.eval(N, dir(60.0, 0.0), N);
    assert!(close(f, Vec3::splat(0.003_527_19), 1e-4), "{f}");
    // The course's gold, metalness 0, sphere centre: Oren-Nayar(F0, sigma 0.3) only, A = 0.892857,
    // radiance F0/pi * A * 60/16 -> (255, 231, 154) after the clamp.
    let gold = Brdf::CookTorrance { kd: f0, f0, roughness: 0.3, metalness: 0.0, diffuse: DiffuseModel::OrenNayar };
    let radiance = gold.eval(N, N, N) * 60.0 / 16.0;
    let bytes = radiance.to_array().map(|c| (c.clamp(0.0, 1.0) * 255.0) as u8);
    assert_eq!(bytes, [255, 231, 154]);
}

/// A grid of directions over the upper hemisphere, grazing ones included.
fn hemisphere() -> Vec<Vec3> {
    let mut directions = Vec::new();
    for theta in [0.0, 10.0, 30.0, 45.0, 60.0, 75.0, 85.0, 89.0, 89.99] {
        for phi in [0.0, 45.0, 90.0, 135.0, 180.0, 270.0] {
            directions.push(dir(theta, phi));
        }
    }
    directions
}

fn every_model() -> Vec<Brdf> {
    let kd = Vec3::new(0.8, 0.5, 0.2);
    let ks = Vec3::splat(0.3);
    let f0 = Vec3::new(1.0, 0.85, 0.57);
    vec![
        Brdf::Lambert { kd },
        Brdf::OrenNayar { kd, sigma: 0.0 },
        Brdf::OrenNayar { kd, sigma: 1.5 },
        Brdf::Phong { kd, ks, shininess: 0.0 },
        Brdf::Phong { kd, ks, shininess: 64.0 },
        Brdf::BlinnPhong { kd, ks, shininess: 0.0 },
        Brdf::BlinnPhong { kd, ks, shininess: 64.0 },
        Brdf::CookTorrance { kd, f0, roughness: 0.01, metalness: 0.5, diffuse: DiffuseModel::OrenNayar },
        Brdf::CookTorrance { kd, f0, roughness: 1.0, metalness: 1.0, diffuse: DiffuseModel::Lambert },
    ]
}

#[test]
fn degenerate_directions_give_finite_values() {
    // Grazing (theta = 90), below the horizon, along the normal, opposite directions (h undefined).
    let below = dir(120.0, 0.0);
    let grazing = Vec3::X;
    let pairs = [(grazing, grazing), (grazing, -grazing), (below, N), (N, below), (N, N), (grazing, N), (N, grazing)];
    for brdf in every_model() {
        for (wi, wo) in pairs.iter().copied().chain(hemisphere().into_iter().map(|d| (d, -d))) {
            let f = brdf.eval(N, wi, wo);
            assert!(f.is_finite() && f.min_element() >= 0.0, "{brdf:?} at wi {wi} wo {wo}: {f}");
        }
        assert_eq!(brdf.eval(N, below, N), Vec3::ZERO, "{brdf:?} reflects light from below");
        assert_eq!(brdf.eval(N, N, below), Vec3::ZERO, "{brdf:?} reflects light to below");
    }
}

#[test]
fn oren_nayar_with_sigma_0_is_lambert_exactly() {
    let kd = Vec3::new(0.8, 0.5, 0.2);
    for wi in hemisphere() {
        for wo in hemisphere() {
            assert_eq!(Brdf::OrenNayar { kd, sigma: 0.0 }.eval(N, wi, wo), Brdf::Lambert { kd }.eval(N, wi, wo));
        }
    }
}

#[test]
fn cook_torrance_metal_is_reciprocal() {
    let f0 = Vec3::new(1.0, 0.85, 0.57);
    for roughness in [0.05, 0.3, 1.0] {
        let metal = Brdf::CookTorrance { kd: f0, f0, roughness, metalness: 1.0, diffuse: DiffuseModel::OrenNayar };
        for wi in hemisphere() {
            for wo in hemisphere() {
                let (a, b) = (metal.eval(N, wi, wo), metal.eval(N, wo, wi));
                assert!(close(a, b, 1e-5), "roughness {roughness}, wi {wi}, wo {wo}: {a} vs {b}");
            }
        }
    }
}

/// The directional albedo: the integral of f cos(theta_i) over the hemisphere of wi, by the midpoint rule.
fn albedo(brdf: &Brdf, wo: Vec3) -> Vec3 {
    let (steps_theta, steps_phi) = (400, 400);
    let (d_theta, d_phi) = (0.5 * PI / steps_theta as f32, 2.0 * PI / steps_phi as f32);
    let mut sum = Vec3::ZERO;
    for i in 0..steps_theta {
        let theta = (i as f32 + 0.5) * d_theta;
        for j in 0..steps_phi {
            let phi = (j as f32 + 0.5) * d_phi;
            let wi = Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos());
            sum += brdf.eval(N, wi, wo) * theta.cos() * theta.sin() * d_theta * d_phi;
        }
    }
    sum
}

#[test]
fn diffuse_albedo_does_not_exceed_kd() {
    let kd = Vec3::new(0.9, 0.5, 0.1);
    for theta_o in [0.0, 45.0, 80.0, 89.0] {
        let a = albedo(&Brdf::Lambert { kd }, dir(theta_o, 0.0));
        assert!(close(a, kd, 1e-3), "Lambert's albedo {a} should be kd");
    }
    // Oren-Nayar's qualitative model (the course's formula) keeps its albedo under kd for views up to 60
    // degrees. Beyond, its B term overshoots: integrating by hand, the albedo tends to kd (A + B/2) as
    // theta_o -> 90, at most 1.015 kd (near sigma = 0.2); the second bound holds the model to that.
    for sigma in [0.1, 0.2, 0.3, 0.6, 1.0, 3.0] {
        for theta_o in [0.0, 30.0, 45.0, 60.0] {
            let a = albedo(&Brdf::OrenNayar { kd, sigma }, dir(theta_o, 0.0));
            assert!(a.cmple(kd * 1.001).all(), "Oren-Nayar sigma {sigma} theta_o {theta_o}: albedo {a} > kd {kd}");
        }
        for theta_o in [70.0, 80.0, 89.0] {
            let a = albedo(&Brdf::OrenNayar { kd, sigma }, dir(theta_o, 0.0));
            assert!(a.cmple(kd * 1.016).all(), "Oren-Nayar sigma {sigma} theta_o {theta_o}: albedo {a} > 1.016 kd");
        }
    }
}
