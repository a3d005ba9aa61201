//! The reference's environment light: Monte Carlo integration of the Rust BRDF mirror against the
//! environment's map, with many samples and its own standard error. Written apart from the GPU's exact mode
//! (shaders/common/environment.glsl) on purpose: its own random numbers (SplitMix64, jittered strata), its
//! own importance table (every texel of the map), and the multi-sample form of the balance heuristic
//! (Veach and Guibas 1995) with a fixed count per strategy.

use std::f64::consts::PI;

use glam::{DVec3, Vec2, Vec3};

use super::Reflectance;
use crate::brdf::{mirror, Brdf};
use crate::environment::sampling::luminance;
use crate::environment::{direction_of, uv_of, EnvironmentMap, PlacedEnvironment};

/// Samples a pixel the reference takes by default (in BATCHES batches, each stratified apart).
pub const DEFAULT_SAMPLES: u32 = 8192;

/// Batches a pixel's samples are cut into: their spread gives the standard error.
pub const BATCHES: u32 = 16;

/// The environment as the reference integrates it.
pub struct EnvironmentLight<'a> {
    placed: PlacedEnvironment<'a>,
    table: Option<TexelTable>,
    samples_per_batch: u32,
}

/// The environment light at a point, and the standard error of its estimate.
pub struct Estimate {
    pub radiance: Vec3,
    pub standard_error: Vec3,
}

impl<'a> EnvironmentLight<'a> {
    pub fn new(placed: PlacedEnvironment<'a>, samples: u32) -> Self {
        let table = (!placed.map.is_constant()).then(|| TexelTable::new(placed.map));
        Self { placed, table, samples_per_batch: (samples / BATCHES).max(1) }
    }

    /// The radiance arriving from world direction `d`.
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        self.placed.radiance(d)
    }

    /// The integral of L(wi) f(wi, wo) cos(theta_i) over the hemisphere of `n` (its tangent `t`, which only an
    /// analytic model reads); `seed` picks the pixel's random numbers.
    pub fn reflected(&self, reflectance: &Reflectance, (n, t): (Vec3, Vec3), wo: Vec3, seed: u64) -> Estimate {
        let lobe = reflectance.model().and_then(|brdf| Lobe::of(brdf, n, wo));
        let strategies = 1 + usize::from(lobe.is_some()) + usize::from(self.table.is_some());
        let per_strategy = (self.samples_per_batch as usize / strategies).max(1);
        let side = (per_strategy as f64).sqrt().ceil() as usize;
        let count = (side * side) as f64;
        let mut random = SplitMix64(seed);
        let mut batches = Vec::with_capacity(BATCHES as usize);
        for _ in 0..BATCHES {
            let mut sum = DVec3::ZERO;
            for strategy in 0..strategies {
                for cell in 0..side * side {
                    let u = Vec2::new(
                        ((cell % side) as f64 + random.next()) as f32 / side as f32,
                        ((cell / side) as f64 + random.next()) as f32 / side as f32,
                    );
                    let wi = match (strategy, &lobe, &self.table) {
                        (0, _, _) => cosine_sample(n, u),
                        (1, Some(lobe), _) => lobe.sample(u),
                        (_, _, Some(table)) => self.placed.to_world(table.sample(u)),
                        _ => continue,
                    };
                    let cos = n.dot(wi);
                    if cos <= 0.0 {
                        continue;
                    }
                    // The balance heuristic's denominator: every strategy's count times its density.
                    let mut density = f64::from(cos) / PI;
                    if let Some(lobe) = &lobe {
                        density += lobe.pdf(wi);
                    }
                    if let Some(table) = &self.table {
                        density += table.pdf(self.placed.to_map(wi));
                    }
                    if density <= 0.0 {
                        continue;
                    }
                    let f = reflectance.eval(n, t, wi, wo) * self.placed.radiance(wi) * cos;
                    sum += f.as_dvec3() / (count * density);
                }
            }
            batches.push(sum);
        }
        let mean = batches.iter().copied().sum::<DVec3>() / f64::from(BATCHES);
        let variance = batches.iter().map(|b| (*b - mean) * (*b - mean)).sum::<DVec3>() / f64::from(BATCHES - 1);
        Estimate { radiance: mean.as_vec3(), standard_error: (variance / f64::from(BATCHES)).map(f64::sqrt).as_vec3() }
    }
}

/// Steele, Lea and Flood 2014's SplitMix64: uniform numbers in [0, 1).
pub(crate) struct SplitMix64(pub(crate) u64);

impl SplitMix64 {
    pub(crate) fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^= z >> 31;
        (z >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// A unit vector at `cos_theta` from `axis`, azimuth `phi`.
fn around(axis: Vec3, cos_theta: f32, phi: f32) -> Vec3 {
    let (t, b) = axis.any_orthonormal_pair();
    let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
    (t * phi.cos() + b * phi.sin()) * sin_theta + axis * cos_theta
}

fn cosine_sample(n: Vec3, u: Vec2) -> Vec3 {
    around(n, (1.0 - u.x).sqrt(), 2.0 * std::f32::consts::PI * u.y)
}

/// A material's specular lobe as a density to draw from: a cosine power about the mirror of wo (Phong),
/// or of half vectors about n (Blinn-Phong's cosine power, GGX's D (n . h)).
enum Lobe {
    Phong { axis: Vec3, exponent: f32 },
    HalfVectors { n: Vec3, wo: Vec3, exponent: Option<f32>, alpha: f32 },
}

impl Lobe {
    fn of(brdf: &Brdf, n: Vec3, wo: Vec3) -> Option<Lobe> {
        match *brdf {
            Brdf::Phong { ks, shininess, .. } if ks.max_element() > 0.0 => {
                Some(Lobe::Phong { axis: mirror(n, wo), exponent: shininess })
            }
            Brdf::BlinnPhong { ks, shininess, .. } if ks.max_element() > 0.0 => {
                Some(Lobe::HalfVectors { n, wo, exponent: Some(shininess), alpha: 0.0 })
            }
            Brdf::CookTorrance { roughness, metalness, .. } if metalness > 0.0 => {
                Some(Lobe::HalfVectors { n, wo, exponent: None, alpha: roughness * roughness })
            }
            _ => None,
        }
    }

    fn sample(&self, u: Vec2) -> Vec3 {
        let phi = 2.0 * std::f32::consts::PI * u.y;
        match *self {
            Lobe::Phong { axis, exponent } => around(axis, u.x.powf(1.0 / (exponent + 1.0)), phi),
            Lobe::HalfVectors { n, wo, exponent, alpha } => {
                let cos = match exponent {
                    Some(s) => u.x.powf(1.0 / (s + 1.0)),
                    None => ((1.0 - u.x) / (1.0 + (alpha * alpha - 1.0) * u.x)).max(0.0).sqrt(),
                };
                mirror(around(n, cos, phi), wo)
            }
        }
    }

    fn pdf(&self, wi: Vec3) -> f64 {
        let power = |cos: f32, s: f32| f64::from(s + 1.0) / (2.0 * PI) * f64::from(cos.max(0.0)).powf(f64::from(s));
        match *self {
            Lobe::Phong { axis, exponent } => power(axis.dot(wi), exponent),
            Lobe::HalfVectors { n, wo, exponent, alpha } => {
                let h = (wi + wo).normalize_or_zero();
                let (wo_h, n_h) = (f64::from(wo.dot(h)), f64::from(n.dot(h)));
                if wo_h <= 0.0 || n_h <= 0.0 {
                    return 0.0;
                }
                let half = match exponent {
                    Some(s) => power(n.dot(h), s),
                    None => {
                        let a2 = f64::from(alpha) * f64::from(alpha);
                        let d = n_h * n_h * (a2 - 1.0) + 1.0;
                        a2 / (PI * d * d) * n_h
                    }
                };
                half / (4.0 * wo_h)
            }
        }
    }
}

/// Every texel of the map, drawn in proportion to the brightest of it and its eight neighbours (the map is
/// read bilinearly, so their light reaches into it) times its solid angle, with a floor.
struct TexelTable {
    width: usize,
    height: usize,
    rows: Vec<f64>,
    columns: Vec<f64>,
}

impl TexelTable {
    fn new(map: &EnvironmentMap) -> Self {
        let (width, height) = (map.width as usize, map.height as usize);
        let texel_luminance = |x: i64, y: i64| {
            let t = map.texel(x.rem_euclid(width as i64) as u32, y.clamp(0, height as i64 - 1) as u32);
            f64::from(luminance(t))
        };
        let mut weights = vec![0.0; width * height];
        for y in 0..height {
            let sin = (PI * (y as f64 + 0.5) / height as f64).sin();
            for x in 0..width {
                let mut brightest: f64 = 0.0;
                for dy in -1..=1 {
                    for dx in -1..=1 {
                        brightest = brightest.max(texel_luminance(x as i64 + dx, y as i64 + dy));
                    }
                }
                weights[y * width + x] = brightest * sin;
            }
        }
        let floor = 1e-3 * weights.iter().sum::<f64>() / weights.len() as f64 + 1e-30;
        let mut rows = vec![0.0];
        let mut columns = Vec::with_capacity(height * (width + 1));
        for row in weights.chunks_exact(width) {
            let mut running = 0.0;
            columns.push(0.0);
            for w in row {
                running += w + floor;
                columns.push(running);
            }
            rows.push(rows.last().copied().unwrap_or(0.0) + running);
        }
        Self { width, height, rows, columns }
    }

    fn row(&self, y: usize) -> &[f64] {
        &self.columns[y * (self.width + 1)..(y + 1) * (self.width + 1)]
    }

    /// A direction of the map's frame.
    fn sample(&self, u: Vec2) -> Vec3 {
        let total = self.rows[self.height];
        let target = f64::from(u.x) * total;
        let y = (self.rows.partition_point(|&c| c <= target) - 1).min(self.height - 1);
        let v = (y as f64 + ((target - self.rows[y]) / (self.rows[y + 1] - self.rows[y])).clamp(0.0, 1.0))
            / self.height as f64;
        let row = self.row(y);
        let target = f64::from(u.y) * row[self.width];
        let x = (row.partition_point(|&c| c <= target) - 1).min(self.width - 1);
        let s = (x as f64 + ((target - row[x]) / (row[x + 1] - row[x])).clamp(0.0, 1.0)) / self.width as f64;
        direction_of(Vec2::new(s as f32, v as f32))
    }

    /// The density of drawing direction `d` of the map's frame, per steradian.
    fn pdf(&self, d: Vec3) -> f64 {
        let uv = uv_of(d);
        let x = ((uv.x * self.width as f32) as usize).min(self.width - 1);
        let y = ((uv.y * self.height as f32) as usize).min(self.height - 1);
        let row = self.row(y);
        let probability = (row[x + 1] - row[x]) / self.rows[self.height];
        let sin = f64::from((1.0 - d.y * d.y).max(0.0).sqrt()).max(1e-6);
        probability * (self.width * self.height) as f64 / (2.0 * PI * PI * sin)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{BuiltinEnvironment, Environment, EnvironmentMode, EnvironmentSource};

    fn white() -> Environment {
        Environment {
            source: EnvironmentSource::Builtin(BuiltinEnvironment::White),
            intensity: 1.0,
            rotation: 0.0,
            visible: true,
            mode: EnvironmentMode::Exact,
        }
    }

    #[test]
    fn the_texel_tables_density_integrates_to_one() {
        let map = EnvironmentMap::from_fn(64, |d| Vec3::splat(1.0 + 50.0 * d.x.max(0.0).powi(8)));
        let table = TexelTable::new(&map);
        // Midpoint rule over the sphere on a fine grid.
        let (nu, nv) = (400, 200);
        let mut total = 0.0;
        for j in 0..nv {
            for i in 0..nu {
                let uv = Vec2::new((i as f32 + 0.5) / nu as f32, (j as f32 + 0.5) / nv as f32);
                let d = direction_of(uv);
                let solid_angle = (2.0 * PI / nu as f64) * (PI / nv as f64) * f64::from(d.y.acos().sin());
                total += table.pdf(d) * solid_angle;
            }
        }
        assert!((total - 1.0).abs() < 0.01, "{total}");
    }

    #[test]
    fn a_lambert_surface_under_a_white_sky_reflects_kd() {
        let map = EnvironmentMap { width: 8, height: 4, texels: vec![Vec3::ONE; 32] };
        let setting = white();
        let light = EnvironmentLight::new(PlacedEnvironment { map: &map, environment: &setting }, 1024);
        let brdf = Reflectance::Model(Brdf::Lambert { kd: Vec3::splat(0.6) });
        let estimate = light.reflected(&brdf, (Vec3::Y, Vec3::X), Vec3::new(0.6, 0.8, 0.0), 7);
        // Cosine sampling alone: every sample is kd exactly.
        assert!((estimate.radiance - Vec3::splat(0.6)).abs().max_element() < 1e-5, "{}", estimate.radiance);
    }
}
