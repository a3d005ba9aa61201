//! The reflectance models, as scene data and as a Rust mirror of the GLSL in `shaders/brdf/`.
//!
//! Each model has one file here and one in `shaders/brdf/` with the same function names, so that the
//! GLSL evaluated on the GPU can be checked term by term against this code. Every function returns
//! f_r without the cosine: the caller multiplies by `n . wi` once.

mod lambert;

use glam::Vec3;

pub use lambert::lambert;

/// Which diffuse lobe a Cook-Torrance material uses under its specular lobe.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DiffuseModel {
    /// Oren-Nayar with sigma = roughness (the course's choice).
    OrenNayar,
    /// Lambert.
    Lambert,
}

/// A material's reflectance model and its parameters, as validated from the scene file.
///
/// A closed set, dispatched by one `match` on the CPU and by one `switch` in `shaders/common/brdf.glsl`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Brdf {
    /// Perfectly diffuse: kd / pi.
    Lambert { kd: Vec3 },
    /// Rough diffuse (Oren and Nayar 1994); sigma is the facet slope in radians.
    OrenNayar { kd: Vec3, sigma: f32 },
    /// The course's "plastic": Lambert + ks / cos(theta_i) * cos(alpha)^s (Phong 1975).
    Phong { kd: Vec3, ks: Vec3, shininess: f32 },
    /// Lambert + ks / cos(theta_i) * (n . h)^s (Blinn 1977).
    BlinnPhong { kd: Vec3, ks: Vec3, shininess: f32 },
    /// Microfacet model (Cook and Torrance 1982) with GGX D, Smith-Schlick G and Schlick F.
    CookTorrance { kd: Vec3, f0: Vec3, roughness: f32, metalness: f32, diffuse: DiffuseModel },
}

impl Brdf {
    /// The model's name as written in scene files.
    pub fn name(&self) -> &'static str {
        match self {
            Brdf::Lambert { .. } => "lambert",
            Brdf::OrenNayar { .. } => "oren-nayar",
            Brdf::Phong { .. } => "phong",
            Brdf::BlinnPhong { .. } => "blinn-phong",
            Brdf::CookTorrance { .. } => "cook-torrance",
        }
    }

    /// Whether the renderer can shade this model yet (the others parse and validate, then answer
    /// "not yet supported").
    pub fn is_supported(&self) -> bool {
        matches!(self, Brdf::Lambert { .. })
    }

    /// Evaluates f_r(wi, wo) at a surface with normal `n` (all unit vectors, pointing away from the
    /// surface), or `None` for a model the renderer does not support yet.
    pub fn eval(&self, _n: Vec3, _wi: Vec3, _wo: Vec3) -> Option<Vec3> {
        match *self {
            Brdf::Lambert { kd } => Some(lambert(kd)),
            _ => None,
        }
    }
}
