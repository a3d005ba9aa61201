//! The course's Phong "plastic": Lambert plus Phong's specular cone; mirrors `shaders/brdf/phong.glsl`.

use glam::Vec3;

use super::lambert;

/// The smallest cos(theta_i) the specular lobes divide by: keeps f finite at grazing incidence, where the
/// integrand lobe * cos(theta_i) then fades to 0 over the last 1e-6 of the cosine.
pub const MIN_COS_THETA_I: f32 = 1e-6;

/// The mirror direction of wi about n: reflect(-wi, n) = 2 (n . wi) n - wi.
pub fn mirror(n: Vec3, wi: Vec3) -> Vec3 {
    2.0 * n.dot(wi) * n - wi
}

/// x^s for x >= 0 with 0^0 = 1 (GLSL's pow leaves 0^0 undefined).
pub fn pow_lobe(x: f32, s: f32) -> f32 {
    if x > 0.0 {
        x.powf(s)
    } else if s == 0.0 {
        1.0
    } else {
        0.0
    }
}

/// ks / cos(theta_i) * cos_alpha^s: the course's specular lobe, shared by Phong and Blinn-Phong, which differ
/// only in the angle alpha they measure. The division by cos(theta_i) makes the lighting model a BRDF.
pub fn cosine_lobe(ks: Vec3, cos_alpha: f32, shininess: f32, n_o_l: f32) -> Vec3 {
    ks * (pow_lobe(cos_alpha, shininess) / n_o_l.max(MIN_COS_THETA_I))
}

/// ks / cos(theta_i) * max(0, wo . r)^s, r the mirror of wi (Phong 1975, "Illumination for computer
/// generated pictures"). Needs n.wi > 0 and n.wo > 0 (checked once by `Brdf::eval`).
pub fn phong_specular(n: Vec3, wi: Vec3, wo: Vec3, ks: Vec3, shininess: f32) -> Vec3 {
    let cos_alpha = wo.dot(mirror(n, wi)).max(0.0);
    cosine_lobe(ks, cos_alpha, shininess, n.dot(wi))
}

/// Lambert(kd) + Phong specular(ks, s).
pub fn phong(n: Vec3, wi: Vec3, wo: Vec3, kd: Vec3, ks: Vec3, shininess: f32) -> Vec3 {
    lambert(kd) + phong_specular(n, wi, wo, ks, shininess)
}
