//! A conductor's eta and k whose Fresnel reflectance follows Schlick's curve of a given F0: equal at normal
//! incidence, nearest in least squares elsewhere, found along Gulbrandsen's (2014, "Artist friendly metallic
//! Fresnel") family of conductors of reflectivity F0 and edge colour g. Mitsuba's and pbrt's conductors take
//! eta and k; MaterialX Standard Surface's metal takes F0 and the edge colour itself.

use glam::Vec3;

/// The conductor nearest Schlick's curve of `f0`, per channel, its reflectivity clamped to `max`: (eta, k).
pub fn nearest_schlick(f0: Vec3, max: f32) -> (Vec3, Vec3) {
    let channels = f0.to_array().map(|r| {
        let g = edge_colour(r, max);
        let (eta, k) = artistic_ior(f64::from(r.clamp(0.0, max)), f64::from(g));
        (eta as f32, k as f32)
    });
    (Vec3::from_array(channels.map(|c| c.0)), Vec3::from_array(channels.map(|c| c.1)))
}

/// The edge colour g in [0, 1] whose conductor of reflectivity `f0` (clamped to `max`) has the Fresnel curve
/// nearest Schlick's of the same F0, least squares over cos theta in (0, 1]: a search over g in steps of 1/200.
pub fn edge_colour(f0: f32, max: f32) -> f32 {
    let r = f64::from(f0.clamp(0.0, max));
    let cosines: Vec<f64> = (1..=200).map(|k| f64::from(k) / 200.0).collect();
    let error = |g: f64| {
        let (eta, k) = artistic_ior(r, g);
        let schlick = |c: f64| r + (1.0 - r) * (1.0 - c).powi(5);
        cosines.iter().map(|&c| (fresnel_conductor(eta, k, c) - schlick(c)).powi(2)).sum::<f64>()
    };
    let steps = (0..=200).map(|step| f64::from(step) / 200.0);
    steps.min_by(|a, b| error(*a).total_cmp(&error(*b))).unwrap_or(1.0) as f32
}

/// Gulbrandsen 2014: the eta and k of reflectivity r (below 1) and edge colour g.
fn artistic_ior(r: f64, g: f64) -> (f64, f64) {
    let n_min = (1.0 - r) / (1.0 + r);
    let n_max = (1.0 + r.sqrt()) / (1.0 - r.sqrt());
    let eta = n_max + (n_min - n_max) * g;
    let k2 = ((eta + 1.0).powi(2) * r - (eta - 1.0).powi(2)) / (1.0 - r);
    (eta, k2.max(0.0).sqrt())
}

/// The unpolarised Fresnel reflectance of a conductor eta + i k, from the air, at cos theta.
fn fresnel_conductor(eta: f64, k: f64, cos: f64) -> f64 {
    let (cos2, sin2) = (cos * cos, 1.0 - cos * cos);
    let t0 = eta * eta - k * k - sin2;
    let a2_plus_b2 = (t0 * t0 + 4.0 * eta * eta * k * k).sqrt();
    let a = (0.5 * (a2_plus_b2 + t0)).max(0.0).sqrt();
    let (t1, t2) = (a2_plus_b2 + cos2, 2.0 * cos * a);
    let rs = (t1 - t2) / (t1 + t2);
    let (t3, t4) = (cos2 * a2_plus_b2 + sin2 * sin2, t2 * sin2);
    let rp = rs * (t3 - t4) / (t3 + t4);
    (rs + rp) / 2.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_conductor_reflects_f0_at_normal_incidence_all_at_grazing_and_follows_schlick_between() {
        for f0 in [0.04, 0.57, 0.85] {
            for g in [0.0, 0.5, 1.0] {
                let (eta, k) = artistic_ior(f0, g);
                assert!((fresnel_conductor(eta, k, 1.0) - f0).abs() < 1e-9, "{f0} {g}");
            }
        }
        let (eta, k) = artistic_ior(0.5, 0.3);
        assert!((fresnel_conductor(eta, k, 1e-6) - 1.0).abs() < 1e-4);
        // eta 1: k^2 / (4 + k^2) at normal incidence, by hand.
        assert!((fresnel_conductor(1.0, 2.0, 1.0) - 0.5).abs() < 1e-12);
        // Gold's blue, F0 0.57: edge colour 1 is 0.10 from Schlick's curve in root mean square, the chosen
        // edge colour (0.91) 0.003.
        let rms = |g: f32| {
            let (eta, k) = artistic_ior(0.57, f64::from(g));
            let squares: f64 = (1..=200)
                .map(|i| f64::from(i) / 200.0)
                .map(|c| (fresnel_conductor(eta, k, c) - (0.57 + 0.43 * (1.0 - c).powi(5))).powi(2))
                .sum();
            (squares / 200.0).sqrt()
        };
        let g = edge_colour(0.57, 0.99);
        assert!((g - 0.91).abs() < 0.02 && rms(g) < 0.005 && rms(1.0) > 0.09, "{g} {} {}", rms(g), rms(1.0));
        let (eta, k) = nearest_schlick(Vec3::new(0.57, 1.0, 0.04), 0.9999);
        assert!(eta.is_finite() && k.is_finite(), "{eta} {k}");
    }
}
