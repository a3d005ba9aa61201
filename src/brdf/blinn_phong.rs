//! Blinn's half-vector variant of the plastic; mirrors `shaders/brdf/blinn_phong.glsl`.

use glam::Vec3;

use super::lambert;
use super::phong::cosine_lobe;

/// The half vector normalize(wi + wo); defined whenever both directions are above the surface.
pub fn half_vector(wi: Vec3, wo: Vec3) -> Vec3 {
    (wi + wo).normalize()
}

/// ks / cos(theta_i) * max(0, n . h)^s (Blinn 1977, "Models of light reflection for computer synthesized
/// pictures"): the angle between n and the half vector replaces Phong's angle to the mirror direction.
/// Needs n.wi > 0 and n.wo > 0 (checked once by `Brdf::eval`).
pub fn blinn_phong_specular(n: Vec3, wi: Vec3, wo: Vec3, ks: Vec3, shininess: f32) -> Vec3 {
    let n_o_h = n.dot(half_vector(wi, wo)).max(0.0);
    cosine_lobe(ks, n_o_h, shininess, n.dot(wi))
}

/// Lambert(kd) + Blinn-Phong specular(ks, s).
pub fn blinn_phong(n: Vec3, wi: Vec3, wo: Vec3, kd: Vec3, ks: Vec3, shininess: f32) -> Vec3 {
    lambert(kd) + blinn_phong_specular(n, wi, wo, ks, shininess)
}
