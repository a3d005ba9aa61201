//! The fast mode's prefiltered maps: the environment averaged over Phong lobes of exponent 1, 2, 4, ...,
//! 1024 about each direction, and itself for sharper lobes, all in layers of one size.
//!
//! Layer k holds Pre_s(r) = integral of L(w) (s + 1) / (2 pi) max(0, r . w)^s dw with s = 2^k: the radiance
//! averaged by a normalized cosine-power lobe about r. Exponent 1 about the normal is the irradiance over
//! pi, what a Lambert surface reflects per unit albedo; the course's Phong lobe, (wo . r)^s about the
//! mirror direction, is exactly such a lobe (cut by the horizon); Blinn-Phong's and GGX's are close to one
//! (shaders/common/environment.glsl says which exponent each takes). Each texel is a direct sum over the
//! texels of a level of the map's box-filtered pyramid fine enough for the lobe (half its width a
//! texel, and at most 2.8 degrees), within two and a half widths of its axis (where cos^s has fallen to 4%), divided by the sum of the same weights: a constant map stays
//! exactly constant, and no light is lost or made however small a bright source is (a sun).

use std::f32::consts::PI;

use glam::Vec3;

use super::{uv_of, EnvironmentMap};

/// The side of every layer: 256 x 128 texels, 1.4 degrees each.
pub const LAYER_WIDTH: u32 = 256;

/// The lobe exponents of the layers before the last: 2^k for k = 0..=10.
pub const LOBE_LAYERS: u32 = 11;

/// All layers: the lobes', then the map itself (box-filtered to the layer size), for lobes sharper than the
/// last lobe layer's.
pub const LAYERS: u32 = LOBE_LAYERS + 1;

/// The largest texel a layer is summed from: 2.8 degrees (a pyramid level 64 texels high).
const MAX_SOURCE_TEXEL: f32 = PI / 64.0;

/// Every layer, LAYER_WIDTH x LAYER_WIDTH / 2 texels each, one after the other.
pub fn prefiltered_layers(map: &EnvironmentMap) -> Vec<Vec3> {
    let mut pyramid = vec![map.clone()];
    while pyramid.last().is_some_and(|level| level.width > 2) {
        let next = pyramid.last().map(EnvironmentMap::halved);
        pyramid.extend(next);
    }
    let mut layers = Vec::with_capacity((LAYERS * LAYER_WIDTH * LAYER_WIDTH / 2) as usize);
    for k in 0..LOBE_LAYERS {
        let exponent = (1u32 << k) as f32;
        // A broad lobe varies slowly: computed on a coarser grid, then read bilinearly.
        let width = (8.0 * exponent.sqrt()).max(32.0).min(LAYER_WIDTH as f32).log2().ceil().exp2() as u32;
        let coarse = lobe_layer(&pyramid, exponent, width.min(LAYER_WIDTH));
        layers.extend(resampled(&coarse, LAYER_WIDTH).texels);
    }
    let mirror = pyramid.iter().find(|level| level.width <= LAYER_WIDTH).unwrap_or(&pyramid[0]);
    layers.extend(resampled(mirror, LAYER_WIDTH).texels);
    layers
}

/// The layer of lobe `exponent`, `width` texels across.
fn lobe_layer(pyramid: &[EnvironmentMap], exponent: f32, width: u32) -> EnvironmentMap {
    // cos^s(a) is close to exp(-s a^2 / 2): a Gaussian of width 1 / sqrt(s).
    let lobe_width = 1.0 / exponent.sqrt();
    // Texels of half the lobe's width, and never over MAX_SOURCE_TEXEL: a bright source averaged into a
    // coarser texel would move to its centre, and the cosine lobes see where the light comes from.
    let texel_wanted = (lobe_width / 2.0).min(MAX_SOURCE_TEXEL);
    let source = pyramid.iter().rev().find(|level| PI / level.height as f32 <= texel_wanted).unwrap_or(&pyramid[0]);
    let (w, h) = (i64::from(source.width), i64::from(source.height));
    let texel = PI / h as f32;
    let reach = (2.5 * lobe_width + texel).min(PI);
    let least_cos = reach.cos();
    // Each row's colatitude and its texels' solid angle, and every texel's direction.
    let rows: Vec<(f32, f32)> = (0..h)
        .map(|j| {
            let theta = PI * (j as f32 + 0.5) / h as f32;
            (theta, (2.0 * PI / w as f32) * texel * theta.sin())
        })
        .collect();
    let directions = EnvironmentMap::from_fn(source.width, |d| d).texels;
    EnvironmentMap::from_fn(width, |r| {
        let theta_r = r.y.clamp(-1.0, 1.0).acos();
        let phi_r = r.x.atan2(r.z);
        let first = (((theta_r - reach) / texel - 0.5).floor() as i64).max(0);
        let last = (((theta_r + reach) / texel - 0.5).ceil() as i64).min(h - 1);
        let (mut sum, mut weights) = (Vec3::ZERO, 0.0f32);
        for j in first..=last {
            let (theta, solid_angle) = rows[j as usize];
            // The columns within `reach` of r's azimuth at this row; all of them near the poles.
            let half =
                if reach < PI / 2.0 && theta.sin() > reach.sin() { (reach.sin() / theta.sin()).asin() } else { PI };
            let span = (half / (2.0 * PI) * w as f32).ceil() as i64 + 1;
            let centre = ((phi_r / (2.0 * PI) + 0.5) * w as f32 - 0.5).round() as i64;
            let columns = if 2 * span + 1 >= w { 0..w } else { centre - span..centre + span + 1 };
            for i in columns {
                let at = (j * w + i.rem_euclid(w)) as usize;
                let cos = r.dot(directions[at]);
                if cos > least_cos.max(0.0) {
                    let weight = cos.powf(exponent) * solid_angle;
                    sum += weight * source.texels[at];
                    weights += weight;
                }
            }
        }
        if weights > 0.0 {
            sum / weights
        } else {
            source.bilinear(uv_of(r))
        }
    })
}

/// `map` read bilinearly at the texel centres of a map `width` across.
fn resampled(map: &EnvironmentMap, width: u32) -> EnvironmentMap {
    if map.width == width {
        return map.clone();
    }
    EnvironmentMap::from_fn(width, |d| map.bilinear(uv_of(d)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_map_stays_constant_and_the_cosine_layer_is_the_irradiance_over_pi() {
        let white = EnvironmentMap { width: 64, height: 32, texels: vec![Vec3::splat(2.0); 64 * 32] };
        let layers = prefiltered_layers(&white);
        assert!(layers.iter().all(|t| (t.x - 2.0).abs() < 1e-3), "a constant environment is its own average");
        // Radiance 1 from the upper hemisphere only: the irradiance over pi at a point facing up is 1, at one
        // facing sideways 1/2.
        let sky = EnvironmentMap::from_fn(256, |d| Vec3::splat(f32::from(d.y > 0.0)));
        let layers = prefiltered_layers(&sky);
        let size = (LAYER_WIDTH * LAYER_WIDTH / 2) as usize;
        let at = |x: u32, y: u32| layers[(y * LAYER_WIDTH + x) as usize];
        assert!((at(0, 0).x - 1.0).abs() < 0.01, "{}", at(0, 0));
        assert!((at(LAYER_WIDTH / 2, LAYER_WIDTH / 4).x - 0.5).abs() < 0.01, "{}", at(128, 64));
        assert_eq!(layers.len(), size * LAYERS as usize);
    }
}
