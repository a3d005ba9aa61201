//! Cook-Torrance microfacet reflection with GGX, Smith-Schlick and Schlick (the Unreal Engine 4 choices,
//! Karis 2013); mirrors `shaders/brdf/cook_torrance.glsl`.

use std::f32::consts::PI;

use glam::Vec3;

use super::blinn_phong::half_vector;
use super::{lambert, oren_nayar, DiffuseModel};

/// D(h) = alpha^2 / (pi ((n.h)^2 (alpha^2 - 1) + 1)^2), alpha = roughness^2 (Trowbridge and Reitz 1975;
/// Walter et al. 2007, "Microfacet models for refraction through rough surfaces").
///
/// The denominator is written (1 - (n.h)^2) + (n.h)^2 alpha^2 with 1 - (n.h)^2 = |n x h|^2: as given, it
/// cancels to 0 in float when h is near n and alpha is small, and D becomes infinite.
pub fn d_ggx(n: Vec3, h: Vec3, alpha: f32) -> f32 {
    let n_o_h = n.dot(h);
    let a2 = alpha * alpha;
    let d = n.cross(h).length_squared() + n_o_h * n_o_h * a2;
    a2 / (PI * d * d)
}

/// k = (roughness + 1)^2 / 8, Karis's remapping of Schlick's k for analytic lights.
pub fn smith_schlick_k(roughness: f32) -> f32 {
    (roughness + 1.0) * (roughness + 1.0) / 8.0
}

/// V = G / (4 (n.wo)(n.wi)), G = G1(n.wo) G1(n.wi), G1(x) = x / (x (1 - k) + k) (Schlick 1994, "An
/// inexpensive BRDF model for physically-based rendering", approximating Smith 1967). The cosines cancel,
/// so V stays finite at grazing angles where G and the denominator both vanish.
pub fn v_smith_schlick(n_o_v: f32, n_o_l: f32, k: f32) -> f32 {
    0.25 / ((n_o_v * (1.0 - k) + k) * (n_o_l * (1.0 - k) + k))
}

/// The shadowing-masking term itself: G = G1(n.wo) G1(n.wi) = 4 (n.wo)(n.wi) V (the G view shows it).
pub fn g_smith_schlick(n_o_v: f32, n_o_l: f32, k: f32) -> f32 {
    4.0 * n_o_v * n_o_l * v_smith_schlick(n_o_v, n_o_l, k)
}

/// F = F0 + (1 - F0)(1 - h.wo)^5 (Schlick 1994).
pub fn f_schlick(v_o_h: f32, f0: Vec3) -> Vec3 {
    let m = (1.0 - v_o_h).clamp(0.0, 1.0);
    let m2 = m * m;
    f0 + (Vec3::ONE - f0) * (m2 * m2 * m)
}

/// GGX's alpha from the course's roughness: alpha = roughness^2 (Burley 2012's perceptual remapping, which
/// the Unreal Engine 4 took). Mirrors `ggx_alpha` in `shaders/brdf/cook_torrance.glsl`.
pub fn ggx_alpha(roughness: f32) -> f32 {
    roughness * roughness
}

/// The specular lobe D F G / (4 (n.wo)(n.wi)) (Cook and Torrance 1982, "A reflectance model for computer
/// graphics"). Needs n.wi > 0 and n.wo > 0 (checked once by `Brdf::eval`).
pub fn cook_torrance_specular(n: Vec3, wi: Vec3, wo: Vec3, f0: Vec3, roughness: f32) -> Vec3 {
    let (n_o_l, n_o_v) = (n.dot(wi), n.dot(wo));
    let h = half_vector(wi, wo);
    let v_o_h = wo.dot(h).clamp(0.0, 1.0);
    d_ggx(n, h, ggx_alpha(roughness)) * v_smith_schlick(n_o_v, n_o_l, smith_schlick_k(roughness)) * f_schlick(v_o_h, f0)
}

/// f = (1 - metalness) f_diffuse + metalness f_specular, the diffuse lobe Oren-Nayar with
/// sigma = roughness (the course) or Lambert.
#[allow(clippy::too_many_arguments)] // the model's own parameters, as the GLSL takes them
pub fn cook_torrance(
    n: Vec3,
    wi: Vec3,
    wo: Vec3,
    kd: Vec3,
    f0: Vec3,
    roughness: f32,
    metalness: f32,
    diffuse: DiffuseModel,
) -> Vec3 {
    let f_diffuse = match diffuse {
        DiffuseModel::OrenNayar => oren_nayar(n, wi, wo, kd, roughness),
        DiffuseModel::Lambert => lambert(kd),
    };
    (1.0 - metalness) * f_diffuse + metalness * cook_torrance_specular(n, wi, wo, f0, roughness)
}
