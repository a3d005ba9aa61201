//! Lambert's perfectly diffuse reflection; mirrors `shaders/brdf/lambert.glsl`.

use glam::Vec3;

use std::f32::consts::FRAC_1_PI;

/// f_r = kd / pi (Lambert 1760, "Photometria"): the same in every direction, and energy-conserving
/// for kd <= 1 since the cosine-weighted hemisphere integrates to pi.
pub fn lambert(kd: Vec3) -> Vec3 {
    kd * FRAC_1_PI
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grey_lambert_by_hand() {
        // 0.5 / pi = 0.159154943
        let f = lambert(Vec3::splat(0.5));
        assert!((f.x - 0.159_154_94).abs() < 1e-7);
        // The course's sphere centre: 0.5/pi * 60/4^2 * cos 0 = 0.596831 -> x255 = 152.19 -> 152.
        let radiance = f.x * 60.0 / 16.0;
        assert!((radiance - 0.596_831).abs() < 1e-5);
        assert_eq!((radiance * 255.0) as u8, 152);
    }
}
