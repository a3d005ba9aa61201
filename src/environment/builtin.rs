//! The built-in environments: the white furnace, a sky with a sun, and a studio of soft panels, each made
//! as a map from an analytic radiance so that the renderers and the reference read them as any map.

use std::f32::consts::PI;

use glam::Vec3;

use super::EnvironmentMap;
use crate::scene::BuiltinEnvironment;

/// The side of the built-in maps: 0.35 degrees a texel, the sky's sun some 9 texels across.
const BUILTIN_WIDTH: u32 = 1024;

/// Each texel of a built-in averages SUPERSAMPLES x SUPERSAMPLES directions, so that the sun's and the
/// panels' edges are antialiased.
const SUPERSAMPLES: u32 = 3;

/// The map of a built-in environment.
pub fn map(builtin: BuiltinEnvironment) -> EnvironmentMap {
    match builtin {
        // Constant: a tiny map holds it exactly.
        BuiltinEnvironment::White => EnvironmentMap { width: 8, height: 4, texels: vec![Vec3::ONE; 32] },
        BuiltinEnvironment::Sky => supersampled(sky),
        BuiltinEnvironment::Studio => supersampled(studio),
    }
}

fn supersampled(radiance: fn(Vec3) -> Vec3) -> EnvironmentMap {
    let (width, height) = (BUILTIN_WIDTH * SUPERSAMPLES, BUILTIN_WIDTH * SUPERSAMPLES / 2);
    let fine = EnvironmentMap::from_fn(width, radiance);
    let n = SUPERSAMPLES;
    let texels = (0..height / n)
        .flat_map(|y| (0..width / n).map(move |x| (x, y)))
        .map(|(x, y)| {
            let mut sum = Vec3::ZERO;
            for j in 0..n {
                for i in 0..n {
                    sum += fine.texel(n * x + i, n * y + j);
                }
            }
            sum / (n * n) as f32
        })
        .collect();
    EnvironmentMap { width: width / n, height: height / n, texels }
}

/// A unit direction at `elevation` above the horizon and `azimuth` from +z towards +x (degrees).
fn direction(elevation: f32, azimuth: f32) -> Vec3 {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    Vec3::new(e.cos() * a.sin(), e.sin(), e.cos() * a.cos())
}

/// Hermite smoothstep.
fn smoothstep(from: f32, to: f32, x: f32) -> f32 {
    let t = ((x - from) / (to - from)).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The sky's sun: 40 degrees up, behind and to the right of the practical's camera (which looks along +z
/// with +x on the image's left).
fn sun_direction() -> Vec3 {
    direction(40.0, 215.0)
}

/// The sun's angular radius: 1.5 degrees (three times the real sun's, so that a map holds it).
const SUN_RADIUS: f32 = 1.5 * PI / 180.0;

/// The irradiance the sun's disc gives a surface facing it.
const SUN_IRRADIANCE: f32 = 3.0;

/// A blue sky brighter towards the horizon, a warm glow and disc around the sun, and a brown ground with a
/// short blend at the horizon.
fn sky(d: Vec3) -> Vec3 {
    let zenith = Vec3::new(0.16, 0.32, 0.75);
    let horizon = Vec3::new(0.72, 0.82, 0.95);
    let ground = Vec3::new(0.26, 0.23, 0.19);
    let up = d.y.max(0.0);
    let air = zenith.lerp(horizon, (1.0 - up).powi(4));
    let cos_sun = d.dot(sun_direction()).clamp(-1.0, 1.0);
    let glow = Vec3::new(1.0, 0.8, 0.55) * (1.2 * (-(1.0 - cos_sun) * 30.0).exp());
    let angle = cos_sun.acos();
    // The disc's radiance such that it gives SUN_IRRADIANCE, darkened towards its limb: over the last 15%
    // of the radius by a smoothstep, which leaves the disc 0.85675 of a uniform one's light.
    let disc_radiance = SUN_IRRADIANCE / (PI * SUN_RADIUS * SUN_RADIUS * 0.85675);
    let disc = Vec3::new(1.0, 0.93, 0.82) * (disc_radiance * (1.0 - smoothstep(0.85, 1.0, angle / SUN_RADIUS)));
    let above = air + glow + disc * f32::from(d.y > -0.01);
    above.lerp(ground, smoothstep(0.0, -0.02, d.y))
}

/// A rectangular soft panel: `radiance` within `half_size` (degrees, azimuth by elevation) of its centre,
/// its edge softened over the last 15%.
struct Panel {
    elevation: f32,
    azimuth: f32,
    half_size: (f32, f32),
    radiance: Vec3,
}

impl Panel {
    fn at(&self, d: Vec3) -> Vec3 {
        let elevation = d.y.clamp(-1.0, 1.0).asin().to_degrees();
        let azimuth = d.x.atan2(d.z).to_degrees();
        let mut da = (azimuth - self.azimuth + 540.0).rem_euclid(360.0) - 180.0;
        da *= elevation.to_radians().cos();
        let de = elevation - self.elevation;
        let edge = |offset: f32, half: f32| 1.0 - smoothstep(0.85, 1.0, offset.abs() / half);
        self.radiance * edge(da, self.half_size.0) * edge(de, self.half_size.1)
    }
}

/// Soft panels (a large key light behind the camera to the left, a fill to the right, a strip overhead and
/// two rim lights behind the subject) in a grey room, brighter towards its ceiling, over a darker floor.
fn studio(d: Vec3) -> Vec3 {
    const PANELS: [Panel; 5] = [
        Panel { elevation: 30.0, azimuth: 150.0, half_size: (22.0, 14.0), radiance: Vec3::new(5.0, 4.9, 4.7) },
        Panel { elevation: 12.0, azimuth: 240.0, half_size: (14.0, 20.0), radiance: Vec3::new(1.6, 1.7, 1.8) },
        Panel { elevation: 75.0, azimuth: 0.0, half_size: (60.0, 5.0), radiance: Vec3::new(3.0, 3.0, 3.0) },
        Panel { elevation: 18.0, azimuth: 40.0, half_size: (8.0, 22.0), radiance: Vec3::new(3.5, 3.5, 3.6) },
        Panel { elevation: 18.0, azimuth: -40.0, half_size: (8.0, 22.0), radiance: Vec3::new(3.5, 3.5, 3.6) },
    ];
    let walls = Vec3::splat(0.22 + 0.18 * d.y.max(0.0));
    let floor = Vec3::splat(0.12);
    let base = walls.lerp(floor, smoothstep(0.0, -0.03, d.y));
    PANELS.iter().fold(base, |sum, panel| sum + panel.at(d))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_suns_disc_gives_its_irradiance() {
        // The sky's radiance times cos summed over the texels within two sun radii of the sun.
        let sky_map = map(BuiltinEnvironment::Sky);
        let sun = sun_direction();
        let texel_solid_angle = |y: u32| {
            let theta = PI * (y as f32 + 0.5) / sky_map.height as f32;
            (2.0 * PI / sky_map.width as f32) * (PI / sky_map.height as f32) * theta.sin()
        };
        let mut irradiance = 0.0;
        for y in 0..sky_map.height {
            for x in 0..sky_map.width {
                let d = crate::environment::direction_of(glam::Vec2::new(
                    (x as f32 + 0.5) / sky_map.width as f32,
                    (y as f32 + 0.5) / sky_map.height as f32,
                ));
                if d.dot(sun) > (2.0 * SUN_RADIUS).cos() {
                    irradiance += sky_map.texel(x, y).y * d.dot(sun) * texel_solid_angle(y);
                }
            }
        }
        // The disc's green, 0.93 of SUN_IRRADIANCE, and a little glow and air.
        let expected = 0.93 * SUN_IRRADIANCE;
        assert!((irradiance - expected).abs() < 0.03 * expected, "{irradiance} against {expected}");
    }
}
