//! Oren-Nayar rough diffuse reflection; mirrors `shaders/brdf/oren_nayar.glsl`.

use glam::Vec3;

use super::lambert;

/// A = 1 - 0.5 sigma^2 / (sigma^2 + 0.33) (Oren and Nayar 1994, qualitative model).
pub fn oren_nayar_a(sigma: f32) -> f32 {
    let s2 = sigma * sigma;
    1.0 - 0.5 * s2 / (s2 + 0.33)
}

/// B = 0.45 sigma^2 / (sigma^2 + 0.09) (Oren and Nayar 1994, qualitative model).
pub fn oren_nayar_b(sigma: f32) -> f32 {
    let s2 = sigma * sigma;
    0.45 * s2 / (s2 + 0.09)
}

/// cos(phi_i - phi_o): the cosine between wi and wo projected on the tangent plane.
///
/// When either direction is along the normal its azimuth is undefined; 0 is returned, and the term it
/// multiplies vanishes there anyway (beta = 0, so tan beta = 0).
pub fn cos_phi_difference(n: Vec3, wi: Vec3, wo: Vec3) -> f32 {
    let wi_t = wi - n * n.dot(wi);
    let wo_t = wo - n * n.dot(wo);
    let lengths = (wi_t.length_squared() * wo_t.length_squared()).sqrt();
    // 1e-12 = (1e-6)^2: both projections shorter than 1e-6 mean a direction within 1e-6 rad of the normal.
    if lengths <= 1e-12 {
        0.0
    } else {
        wi_t.dot(wo_t) / lengths
    }
}

/// f_r = kd/pi (A + B max(0, cos(phi_i - phi_o)) sin(alpha) tan(beta)), alpha = max(theta_i, theta_o),
/// beta = min(theta_i, theta_o) (Oren and Nayar 1994, "Generalization of Lambert's reflectance model").
/// Needs n.wi > 0 and n.wo > 0 (checked once by `Brdf::eval`).
pub fn oren_nayar(n: Vec3, wi: Vec3, wo: Vec3, kd: Vec3, sigma: f32) -> Vec3 {
    let (n_o_l, n_o_v) = (n.dot(wi), n.dot(wo));
    // The larger angle has the smaller cosine.
    let cos_alpha = n_o_l.min(n_o_v).min(1.0);
    let cos_beta = n_o_l.max(n_o_v).min(1.0);
    let sin_alpha = (1.0 - cos_alpha * cos_alpha).sqrt();
    // cos_beta >= cos_alpha > 0, so tan(beta) is finite.
    let tan_beta = (1.0 - cos_beta * cos_beta).sqrt() / cos_beta;
    let cos_phi = cos_phi_difference(n, wi, wo).max(0.0);
    lambert(kd) * (oren_nayar_a(sigma) + oren_nayar_b(sigma) * cos_phi * sin_alpha * tan_beta)
}
