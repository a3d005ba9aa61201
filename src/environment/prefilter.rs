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
//!
//! A layer's rows are not at texel centres but at colatitudes pi j / (rows - 1), its first row at the pole
//! +y and its last at -y, each pole's texels all its one value: straight up, an upward floor's normal, is
//! read there, not a texel's width away at whatever azimuth (GLSL leaves atan(0, 0) undefined). On a grid
//! of texel centres, bilinear reads clamped above the first row, an upward floor's irradiance under the
//! sky was up to 1.4% off the pole's (the sun is low; read from a 32-texel layer's first row, 5.6 degrees
//! from the pole), and NVIDIA's atan(0, 0) and lavapipe's picked opposite sides: their fast renders of a
//! floor differed by 5%. The shaders map v onto these rows (shaders/common/environment.glsl, layer_uv).

use std::f32::consts::PI;

use glam::Vec3;

use super::{uv_of, EnvironmentMap};

/// The side of every layer: 256 x 128 texels, 1.4 degrees each (rows 180 / 127 degrees apart).
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
        layers.extend(coarse.resampled(LAYER_WIDTH).texels);
    }
    let mirror = pyramid.iter().find(|level| level.width <= LAYER_WIDTH).unwrap_or(&pyramid[0]);
    layers.extend(Layer::from_fn(LAYER_WIDTH, |d| mirror.bilinear(uv_of(d))).texels);
    layers
}

/// A layer: `width` columns at texel centres in u, as a map's, and `width / 2` rows from pole to pole.
struct Layer {
    width: u32,
    texels: Vec<Vec3>,
}

impl Layer {
    /// The layer whose texel in direction d is `value(d)`, its rows made on all the cores.
    fn from_fn(width: u32, value: impl Fn(Vec3) -> Vec3 + Sync) -> Self {
        let rows = width / 2;
        let texels = crate::parallel::rows(rows, |y| {
            let theta = PI * y as f32 / (rows - 1) as f32;
            (0..width)
                .map(|x| {
                    let phi = 2.0 * PI * ((x as f32 + 0.5) / width as f32 - 0.5);
                    value(Vec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos()))
                })
                .collect()
        });
        Self { width, texels }
    }

    /// The layer read at the texels of a layer `width` across: bilinear in u (wrapping) and in the
    /// colatitude, between the rows around it (the poles' own rows included).
    fn resampled(self, width: u32) -> Self {
        if self.width == width {
            return self;
        }
        let (w, rows) = (i64::from(self.width), i64::from(self.width / 2));
        let texel = |x: i64, y: i64| self.texels[(y.clamp(0, rows - 1) * w + x.rem_euclid(w)) as usize];
        Self::from_fn(width, |d| {
            let uv = uv_of(d);
            let fx = uv.x * w as f32 - 0.5;
            let fy = uv.y * (rows - 1) as f32;
            let (x0, y0) = (fx.floor(), fy.floor());
            let (tx, ty) = (fx - x0, fy - y0);
            let (x0, y0) = (x0 as i64, y0 as i64);
            let top = texel(x0, y0).lerp(texel(x0 + 1, y0), tx);
            let bottom = texel(x0, y0 + 1).lerp(texel(x0 + 1, y0 + 1), tx);
            top.lerp(bottom, ty)
        })
    }
}

/// The layer of lobe `exponent`, `width` texels across.
fn lobe_layer(pyramid: &[EnvironmentMap], exponent: f32, width: u32) -> Layer {
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
    Layer::from_fn(width, |r| {
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

    /// The irradiance over pi about unit direction `n`: the sum over every texel of `map`, in double precision.
    fn irradiance_over_pi(map: &EnvironmentMap, n: Vec3) -> f64 {
        let directions = EnvironmentMap::from_fn(map.width, |d| d).texels;
        let (w, h) = (f64::from(map.width), f64::from(map.height));
        let sum: f64 = (0..map.texels.len())
            .map(|i| {
                let theta = std::f64::consts::PI * (f64::from(i as u32 / map.width) + 0.5) / h;
                let solid_angle = (2.0 * std::f64::consts::PI / w) * (std::f64::consts::PI / h) * theta.sin();
                f64::from(map.texels[i].x) * f64::from(n.dot(directions[i]).max(0.0)) * solid_angle
            })
            .sum();
        sum / std::f64::consts::PI
    }

    /// Straight up, an upward floor's normal, the shaders read the cosine layer's first row, at whatever
    /// azimuth the device's atan(0, 0) gives: every texel of it must be the irradiance about the pole, and
    /// the next row's each about its own direction. Under a sun 20 degrees from the zenith, a first row of
    /// texel centres (a 32-texel layer's, 5.6 degrees from the pole) was 3.5% above or below it as it faced
    /// the sun or not.
    #[test]
    fn the_cosine_layer_holds_the_irradiance_about_the_pole_and_about_each_texel_near_it() {
        let sun = Vec3::new(20f32.to_radians().sin(), 20f32.to_radians().cos(), 0.0);
        let map =
            EnvironmentMap::from_fn(LAYER_WIDTH, |d| Vec3::splat(0.1 + 20.0 * (100.0 * (d.dot(sun) - 1.0)).exp()));
        let layers = prefiltered_layers(&map);
        let theta = PI / (LAYER_WIDTH / 2 - 1) as f32;
        let mut worst = 0.0f64;
        for y in 0..2 {
            for x in (0..LAYER_WIDTH).step_by(16) {
                let phi = 2.0 * PI * ((x as f32 + 0.5) / LAYER_WIDTH as f32 - 0.5);
                let t = theta * y as f32;
                let direction = Vec3::new(t.sin() * phi.sin(), t.cos(), t.sin() * phi.cos());
                let expected = irradiance_over_pi(&map, direction);
                let got = f64::from(layers[(y * LAYER_WIDTH + x) as usize].x);
                worst = worst.max((got / expected - 1.0).abs());
                assert!((got / expected - 1.0).abs() < 0.005, "texel ({x}, {y}): {got} against {expected}");
            }
        }
        eprintln!("the first two rows within {:.3}% of the irradiance about their directions", 100.0 * worst);
    }
}
