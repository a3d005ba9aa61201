//! Environments: the radiance arriving from every direction, as an equirectangular map read from a file or
//! made from a built-in (`builtin.rs`), with what the renderers need to integrate it: the luminance table
//! that importance-samples it (`sampling.rs`) and the prefiltered maps of the fast mode (`prefilter.rs`).
//!
//! The map's texel at (u, v), each from 0 to 1 left to right and top to bottom, holds the radiance arriving
//! from direction (sin(theta) sin(phi), cos(theta), sin(theta) cos(phi)), theta = pi v, phi = 2 pi (u - 0.5):
//! its top row is straight up (+y), its centre +z. Between texel centres it is read bilinearly, wrapping
//! around in u and clamped in v, as the GPU's sampler reads it.

mod builtin;
pub mod prefilter;
pub mod sampling;

use std::f32::consts::PI;
use std::path::Path;

use glam::{Vec2, Vec3};

use crate::error::{Error, Result};
use crate::scene::{Environment, EnvironmentSource, Scene};

/// An equirectangular radiance map, twice as wide as high, rows from the top.
#[derive(Clone, Debug, PartialEq)]
pub struct EnvironmentMap {
    /// Width in texels: 2 x `height`.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// `width * height` linear RGB radiances, row by row from the top: see [`EnvironmentMap::texel`].
    pub texels: Vec<Vec3>,
}

impl EnvironmentMap {
    /// The map of `environment` (unscaled and unrotated): its file read, or its built-in made.
    ///
    /// # Errors
    /// `Error::Map` naming the scene file and the map's path: unreadable, not an image, not 2:1, or a texel
    /// that is not a finite radiance of at least 0.
    pub fn of(scene: &Scene, environment: &Environment) -> Result<Self> {
        match &environment.source {
            EnvironmentSource::Builtin(builtin) => Ok(builtin::map(*builtin)),
            EnvironmentSource::Map(path) => Self::read(path).map_err(|message| Error::Map {
                scene: scene.source.clone(),
                value: path.display().to_string(),
                message,
            }),
        }
    }

    fn read(path: &Path) -> std::result::Result<Self, String> {
        let bytes = crate::files::read_regular(path, "environment map", crate::files::MAX_IMAGE_BYTES)?;
        let decoded = image::load_from_memory(&bytes)
            .map_err(|e| format!("not a map vk-render can read (Radiance .hdr or OpenEXR): {e}"))?
            .into_rgb32f();
        let (width, height) = decoded.dimensions();
        if width != 2 * height {
            return Err(format!(
                "the map is {width} x {height} texels: an equirectangular map is twice as wide as high"
            ));
        }
        let texels: Vec<Vec3> = decoded.pixels().map(|p| Vec3::from(p.0)).collect();
        if let Some(i) = texels.iter().position(|t| !(t.is_finite() && t.min_element() >= 0.0)) {
            let (x, y) = (i as u32 % width, i as u32 / width);
            return Err(format!("texel ({x}, {y}) holds {}: radiance must be finite and at least 0", texels[i]));
        }
        Ok(Self { width, height, texels })
    }

    /// A map of `width` x `width / 2` texels, each `radiance` of its centre's direction, its rows made on
    /// all the cores.
    pub fn from_fn(width: u32, radiance: impl Fn(Vec3) -> Vec3 + Sync) -> Self {
        let height = width / 2;
        let texels = crate::parallel::rows(height, |y| {
            let v = (y as f32 + 0.5) / height as f32;
            (0..width).map(|x| radiance(direction_of(Vec2::new((x as f32 + 0.5) / width as f32, v)))).collect()
        });
        Self { width, height, texels }
    }

    /// Whether every texel holds the same radiance (the white furnace): nothing to importance-sample.
    pub fn is_constant(&self) -> bool {
        self.texels.iter().all(|t| *t == self.texels[0])
    }

    /// The radiance of texel (x, y), x from the left and y from the top.
    pub fn texel(&self, x: u32, y: u32) -> Vec3 {
        self.texels[(y * self.width + x) as usize]
    }

    /// The radiance at map coordinates `uv`, bilinear between texel centres, wrapping in u, clamped in v.
    pub fn bilinear(&self, uv: Vec2) -> Vec3 {
        let (w, h) = (self.width as i64, self.height as i64);
        let fx = uv.x * self.width as f32 - 0.5;
        let fy = uv.y * self.height as f32 - 0.5;
        let (x0, y0) = (fx.floor(), fy.floor());
        let (tx, ty) = (fx - x0, fy - y0);
        let column = |x: i64| x.rem_euclid(w) as u32;
        let row = |y: i64| y.clamp(0, h - 1) as u32;
        let (x0, y0) = (x0 as i64, y0 as i64);
        let top = self.texel(column(x0), row(y0)).lerp(self.texel(column(x0 + 1), row(y0)), tx);
        let bottom = self.texel(column(x0), row(y0 + 1)).lerp(self.texel(column(x0 + 1), row(y0 + 1)), tx);
        top.lerp(bottom, ty)
    }

    /// The map halved in each direction, each texel the mean of four (for maps wider than 2 texels).
    pub fn halved(&self) -> Self {
        let (width, height) = ((self.width / 2).max(2), (self.height / 2).max(1));
        let texels = (0..height)
            .flat_map(|y| (0..width).map(move |x| (x, y)))
            .map(|(x, y)| {
                let (x0, y0) = ((2 * x).min(self.width - 1), (2 * y).min(self.height - 1));
                let (x1, y1) = ((x0 + 1).min(self.width - 1), (y0 + 1).min(self.height - 1));
                0.25 * (self.texel(x0, y0) + self.texel(x1, y0) + self.texel(x0, y1) + self.texel(x1, y1))
            })
            .collect();
        Self { width, height, texels }
    }
}

/// The map coordinates of unit direction `d` in the map's own frame; straight up or down, whose azimuth is
/// none, u = 1/2 (as the shaders' `map_uv`: atan2(0, -0) would be pi here).
pub fn uv_of(d: Vec3) -> Vec2 {
    let theta = d.y.clamp(-1.0, 1.0).acos();
    let phi = if d.x == 0.0 && d.z == 0.0 { 0.0 } else { d.x.atan2(d.z) };
    Vec2::new(phi / (2.0 * PI) + 0.5, theta / PI)
}

/// The unit direction at map coordinates `uv`, in the map's own frame.
pub fn direction_of(uv: Vec2) -> Vec3 {
    let theta = PI * uv.y;
    let phi = 2.0 * PI * (uv.x - 0.5);
    Vec3::new(theta.sin() * phi.sin(), theta.cos(), theta.sin() * phi.cos())
}

/// An environment placed in the world: its map, turned by its rotation and scaled by its intensity.
pub struct PlacedEnvironment<'a> {
    /// The map, unrotated and unscaled.
    pub map: &'a EnvironmentMap,
    /// The scene's `[environment]`: its rotation and intensity.
    pub environment: &'a Environment,
}

impl PlacedEnvironment<'_> {
    /// The radiance arriving from world direction `d` (unit).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        self.environment.intensity * self.map.bilinear(uv_of(self.to_map(d)))
    }

    /// A world direction in the map's frame: the map turned by `rotation` degrees about +y, so the world
    /// turns by minus that.
    pub fn to_map(&self, d: Vec3) -> Vec3 {
        let (sin, cos) = (-self.environment.rotation.to_radians()).sin_cos();
        Vec3::new(cos * d.x + sin * d.z, d.y, -sin * d.x + cos * d.z)
    }

    /// A direction of the map's frame in the world.
    pub fn to_world(&self, d: Vec3) -> Vec3 {
        let (sin, cos) = self.environment.rotation.to_radians().sin_cos();
        Vec3::new(cos * d.x + sin * d.z, d.y, -sin * d.x + cos * d.z)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_map_frame_is_the_documented_one() {
        // Top row straight up, centre +z, a quarter to the right +x.
        assert!(direction_of(Vec2::new(0.5, 0.0)).abs_diff_eq(Vec3::Y, 1e-6));
        assert!(direction_of(Vec2::new(0.5, 0.5)).abs_diff_eq(Vec3::Z, 1e-6));
        assert!(direction_of(Vec2::new(0.75, 0.5)).abs_diff_eq(Vec3::X, 1e-6));
        for uv in [Vec2::new(0.1, 0.3), Vec2::new(0.9, 0.7), Vec2::new(0.5, 0.99)] {
            assert!(uv_of(direction_of(uv)).abs_diff_eq(uv, 1e-5), "{uv}");
        }
    }

    #[test]
    fn bilinear_reads_texel_centres_and_wraps_in_u() {
        let map = EnvironmentMap { width: 4, height: 2, texels: (0..8).map(|i| Vec3::splat(i as f32)).collect() };
        assert_eq!(map.bilinear(Vec2::new(0.125, 0.25)), Vec3::splat(0.0));
        assert_eq!(map.bilinear(Vec2::new(0.25, 0.25)), Vec3::splat(0.5));
        // Left of the first centre: half way to the last texel of the row.
        assert_eq!(map.bilinear(Vec2::new(0.0, 0.25)), Vec3::splat(1.5));
        // Above the first row's centres: clamped.
        assert_eq!(map.bilinear(Vec2::new(0.125, 0.0)), Vec3::splat(0.0));
    }
}
