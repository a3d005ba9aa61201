//! Scene files (SCENE_FORMAT version 1): parsing, `--set` overrides and validation.
//!
//! No GPU types here: a `Scene` is plain data that the Vulkan renderer and the CPU code both read.

mod file;
mod overrides;
mod validate;

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};

use crate::brdf::Brdf;
use crate::error::{Error, Result};

pub use overrides::Override;

/// The installed Stanford bunny that `path = "bunny"` names (Debian package glmark2-data).
pub const BUNNY_PATH: &str = "/usr/share/glmark2/models/bunny.obj";

/// A validated scene, ready to render.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The file it was read from: error messages name it and mesh paths are relative to it.
    pub source: PathBuf,
    pub image: ImageSettings,
    pub camera: Camera,
    pub lights: Vec<PointLight>,
    pub objects: Vec<Object>,
}

/// `[image]`: the output's size, sampling and output transform.
#[derive(Clone, Debug, PartialEq)]
pub struct ImageSettings {
    pub width: u32,
    pub height: u32,
    /// MSAA samples per pixel; the device decides which counts it supports.
    pub samples: u32,
    /// Linear radiance where no object is seen.
    pub background: Vec3,
    pub tonemap: Tonemap,
    pub exposure: f32,
    pub encoding: Encoding,
}

/// The tone curve applied after exposure and before the clamp.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Tonemap {
    /// Nothing before the clamp (the course).
    Clamp,
    /// c / (1 + c).
    Reinhard,
    /// Narkowicz's 2015 fit of the ACES filmic curve.
    Aces,
}

/// How a [0, 1] value becomes an 8-bit one.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Encoding {
    /// x255, truncated, no gamma (the course).
    Linear,
    /// The sRGB transfer function, x255, rounded.
    Srgb,
}

/// `[camera]`: a right-handed look-at camera (world +x on the image's left when looking along +z).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Camera {
    pub position: Vec3,
    pub look_at: Vec3,
    pub up: Vec3,
    /// Vertical field of view, in degrees.
    pub fov_y: f32,
}

impl Camera {
    /// World to camera: glam's right-handed look-at, whose image-right axis is normalize(cross(forward, up)),
    /// the same as the course's u = normalize(cross(up, w)) with w = normalize(position - look_at).
    pub fn view(&self) -> Mat4 {
        Mat4::look_at_rh(self.position, self.look_at, self.up)
    }
}

/// One `[[light]]` of type "point".
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PointLight {
    pub position: Vec3,
    pub color: Vec3,
    /// Incident radiance at distance d is color * power / d^2.
    pub power: f32,
    pub shadows: bool,
}

/// One `[[object]]` with its material resolved.
#[derive(Clone, Debug, PartialEq)]
pub struct Object {
    pub shape: Shape,
    /// The `[material.NAME]` it uses, kept for messages.
    pub material: String,
    pub brdf: Brdf,
}

/// An object's geometry.
#[derive(Clone, Debug, PartialEq)]
pub enum Shape {
    Sphere { center: Vec3, radius: f32 },
    /// An infinite plane through `point`; `normal` is unit length.
    Plane { point: Vec3, normal: Vec3 },
    /// An OBJ file, placed by scale, then rotations about x, y, z (degrees), then translation.
    Mesh { path: PathBuf, scale: f32, rotate: Vec3, translate: Vec3 },
}

impl Shape {
    /// Object to world for a mesh: translate * Rz * Ry * Rx * scale, so x turns first.
    pub fn mesh_transform(scale: f32, rotate: Vec3, translate: Vec3) -> Mat4 {
        let r = rotate * (std::f32::consts::PI / 180.0);
        Mat4::from_translation(translate)
            * Mat4::from_rotation_z(r.z)
            * Mat4::from_rotation_y(r.y)
            * Mat4::from_rotation_x(r.x)
            * Mat4::from_scale(Vec3::splat(scale))
    }
}

impl Scene {
    /// Reads, overrides and validates a scene file.
    ///
    /// # Errors
    /// `Error::Scene` naming the file, the key and the value for anything the format does not allow:
    /// an unreadable file, a TOML syntax error (with its line), an unknown key, a wrong type, a value out of
    /// range, an undefined material or an unknown brdf; an override whose path the format does not have.
    pub fn load(path: &Path, overrides: &[Override]) -> Result<Scene> {
        let text = std::fs::read_to_string(path).map_err(|e| Error::Scene {
            file: path.to_path_buf(),
            message: format!("cannot read the scene file: {e}"),
        })?;
        Self::parse(&text, path, overrides)
    }

    /// Parses scene text as if read from `path` (used for messages and relative mesh paths).
    ///
    /// # Errors
    /// As [`Scene::load`].
    pub fn parse(text: &str, path: &Path, overrides: &[Override]) -> Result<Scene> {
        let scene_error = |message: String| Error::Scene { file: path.to_path_buf(), message };
        // Deserializing the text itself keeps toml's spans, so syntax errors, unknown keys and wrong types
        // are reported with their line and the offending source line.
        let mut raw: file::SceneFile = toml::from_str(text).map_err(|e| scene_error(e.to_string()))?;
        if !overrides.is_empty() {
            let mut table: toml::Table = toml::from_str(text).map_err(|e| scene_error(e.to_string()))?;
            raw = overrides::apply(&mut table, overrides).map_err(scene_error)?;
        }
        validate::validate(raw, path).map_err(scene_error)
    }
}
