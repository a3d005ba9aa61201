//! The reflectance models, as scene data and as a Rust mirror of the GLSL in `shaders/brdf/`.
//!
//! Each model has one file here and one in `shaders/brdf/` with the same function names, so that the
//! GLSL evaluated on the GPU can be checked term by term against this code. Every function returns
//! f_r without the cosine: the caller multiplies by `n . wi` once.

pub mod analytic;
mod blinn_phong;
pub(crate) mod cook_torrance;
mod lambert;
pub mod measured;
pub mod measured_sampler;
mod oren_nayar;
mod phong;
pub mod rgl;
#[cfg(test)]
mod tests;

use glam::Vec3;

pub use analytic::{
    default_tangent, plane_tangent, surface_tangent, Analytic, AnalyticModel, ParameterKind, ParameterValue,
};
pub use blinn_phong::{blinn_phong, blinn_phong_specular, half_vector};
pub use cook_torrance::{
    cook_torrance, cook_torrance_specular, d_ggx, f_schlick, g_smith_schlick, ggx_alpha, smith_schlick_k,
    v_smith_schlick,
};
pub use lambert::lambert;
pub use measured::{Measured, MeasuredTable};
pub use oren_nayar::{cos_phi_difference, oren_nayar, oren_nayar_a, oren_nayar_b};
pub use phong::{cosine_lobe, mirror, phong, phong_specular, pow_lobe, MIN_COS_THETA_I};

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
/// Not `Copy`: a measured material holds its table (shared, so a clone is cheap).
#[derive(Clone, Debug, PartialEq)]
pub enum Brdf {
    /// Perfectly diffuse: kd / pi.
    Lambert {
        /// Diffuse reflectance, linear RGB in `[0, 1]`.
        kd: Vec3,
    },
    /// Rough diffuse (Oren and Nayar 1994); sigma is the facet slope in radians.
    OrenNayar {
        /// Diffuse reflectance, linear RGB in `[0, 1]`.
        kd: Vec3,
        /// The standard deviation of the facets' slope, in radians, at least 0 (0 is Lambert).
        sigma: f32,
    },
    /// The course's "plastic": Lambert + ks / cos(theta_i) * cos(alpha)^s (Phong 1975).
    Phong {
        /// Diffuse reflectance, linear RGB in `[0, 1]`.
        kd: Vec3,
        /// Specular reflectance, linear RGB in `[0, 1]`.
        ks: Vec3,
        /// The lobe's exponent s, at least 0 (higher is a tighter highlight).
        shininess: f32,
    },
    /// Lambert + ks / cos(theta_i) * (n . h)^s (Blinn 1977).
    BlinnPhong {
        /// Diffuse reflectance, linear RGB in `[0, 1]`.
        kd: Vec3,
        /// Specular reflectance, linear RGB in `[0, 1]`.
        ks: Vec3,
        /// The lobe's exponent s, at least 0 (higher is a tighter highlight).
        shininess: f32,
    },
    /// Microfacet model (Cook and Torrance 1982) with GGX D, Smith-Schlick G and Schlick F.
    CookTorrance {
        /// The diffuse lobe's reflectance, linear RGB in `[0, 1]`.
        kd: Vec3,
        /// Fresnel reflectance at normal incidence, linear RGB in `[0, 1]`.
        f0: Vec3,
        /// In (0, 1]: GGX's alpha is its square; the Oren-Nayar diffuse lobe's sigma is it too.
        roughness: f32,
        /// In `[0, 1]` (default 0): the lobes are weighed (1 - metalness) diffuse + metalness specular.
        metalness: f32,
        /// The diffuse lobe's model (default Oren-Nayar).
        diffuse: DiffuseModel,
    },
    /// A measured table (a MERL file, Matusik et al. 2003), interpolated: see [`measured`].
    Measured(Measured),
    /// A user's model, BRDF Explorer's `.brdf` file, with a value for each of its parameters: see [`analytic`].
    Analytic(Analytic),
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
            Brdf::Measured(_) => "measured",
            Brdf::Analytic(_) => "analytic",
        }
    }

    /// Evaluates f_r(wi, wo) at a surface with normal `n`, all unit vectors pointing away from the surface;
    /// mirrors `brdf_eval` in `shaders/common/brdf.glsl`.
    ///
    /// Reflection only: zero when wi or wo is at or below the horizon. Every model relies on this check,
    /// made here once: with both cosines positive, the half vector exists and no denominator vanishes.
    ///
    /// An analytic model is evaluated in the tangent frame the probe gives it ([`default_tangent`]), by its
    /// Rust mirror: the shipped models of `assets/brdfs/` have one, any other file none, and gives NaN
    /// ([`Brdf::has_mirror`] says which).
    pub fn eval(&self, n: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        self.eval_in_frame(n, default_tangent(n), wi, wo)
    }

    /// As [`Brdf::eval`], in the tangent frame X = `t`, Y = n x t (which only an analytic model reads).
    pub fn eval_in_frame(&self, n: Vec3, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        if n.dot(wi) <= 0.0 || n.dot(wo) <= 0.0 {
            return Vec3::ZERO;
        }
        match self {
            Brdf::Lambert { kd } => lambert(*kd),
            Brdf::OrenNayar { kd, sigma } => oren_nayar(n, wi, wo, *kd, *sigma),
            Brdf::Phong { kd, ks, shininess } => phong(n, wi, wo, *kd, *ks, *shininess),
            Brdf::BlinnPhong { kd, ks, shininess } => blinn_phong(n, wi, wo, *kd, *ks, *shininess),
            Brdf::CookTorrance { kd, f0, roughness, metalness, diffuse } => {
                cook_torrance(n, wi, wo, *kd, *f0, *roughness, *metalness, *diffuse)
            }
            Brdf::Measured(table) => table.eval(n, t, wi, wo),
            Brdf::Analytic(material) => material.mirror_eval(n, t, wi, wo).unwrap_or(Vec3::NAN),
        }
    }

    /// Whether [`Brdf::eval`] has a Rust mirror to evaluate: every built-in model and measurement, and the
    /// analytic models shipped in `assets/brdfs/`.
    pub fn has_mirror(&self) -> bool {
        match self {
            Brdf::Analytic(material) => material.has_mirror(),
            _ => true,
        }
    }

    /// The diffuse lobe of [`Brdf::eval`] (with [`Brdf::eval_specular`] they add up to it): Lambert and
    /// Oren-Nayar are all diffuse, Phong and Blinn-Phong are Lambert plus their lobe, Cook-Torrance weighs
    /// its lobes by metalness. A measurement or an analytic model is not split into lobes: it counts whole as
    /// diffuse. Mirrors `brdf_eval_diffuse` in `shaders/common/brdf.glsl`.
    pub fn eval_diffuse(&self, n: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        if n.dot(wi) <= 0.0 || n.dot(wo) <= 0.0 {
            return Vec3::ZERO;
        }
        match *self {
            Brdf::OrenNayar { kd, sigma } => oren_nayar(n, wi, wo, kd, sigma),
            Brdf::Measured(_) | Brdf::Analytic(_) => self.eval(n, wi, wo),
            Brdf::CookTorrance { kd, roughness, metalness, diffuse, .. } => {
                (1.0 - metalness)
                    * match diffuse {
                        DiffuseModel::Lambert => lambert(kd),
                        DiffuseModel::OrenNayar => oren_nayar(n, wi, wo, kd, roughness),
                    }
            }
            Brdf::Lambert { kd } | Brdf::Phong { kd, .. } | Brdf::BlinnPhong { kd, .. } => lambert(kd),
        }
    }

    /// The same material with its diffuse lobe taken out (kd = 0), so that [`Brdf::eval`] is its specular
    /// lobe alone; `None` for the models that are all diffuse (a measurement and an analytic model count as
    /// one).
    pub fn specular_only(&self) -> Option<Brdf> {
        match *self {
            Brdf::Lambert { .. } | Brdf::OrenNayar { .. } | Brdf::Measured(_) | Brdf::Analytic(_) => None,
            Brdf::Phong { ks, shininess, .. } => Some(Brdf::Phong { kd: Vec3::ZERO, ks, shininess }),
            Brdf::BlinnPhong { ks, shininess, .. } => Some(Brdf::BlinnPhong { kd: Vec3::ZERO, ks, shininess }),
            Brdf::CookTorrance { f0, roughness, metalness, diffuse, .. } => {
                Some(Brdf::CookTorrance { kd: Vec3::ZERO, f0, roughness, metalness, diffuse })
            }
        }
    }

    /// How wide its sharpest lobe is, as GGX's alpha (about the radians of the half vector's spread): the
    /// roughness squared for Cook-Torrance with a metal lobe, sqrt(2 / (s + 2)) for a cosine power of
    /// exponent s (Walter et al. 2007's correspondence), 1 for a diffuse model or one whose lobe reflects
    /// nothing; `None` for a measurement or an analytic model, which do not say.
    pub fn lobe_width(&self) -> Option<f32> {
        match *self {
            Brdf::Lambert { .. } | Brdf::OrenNayar { .. } => Some(1.0),
            Brdf::Phong { ks, shininess, .. } | Brdf::BlinnPhong { ks, shininess, .. } => {
                Some(if ks.max_element() > 0.0 { (2.0 / (shininess + 2.0)).sqrt().min(1.0) } else { 1.0 })
            }
            Brdf::CookTorrance { roughness, metalness, .. } => {
                Some(if metalness > 0.0 { cook_torrance::ggx_alpha(roughness).min(1.0) } else { 1.0 })
            }
            Brdf::Measured(_) | Brdf::Analytic(_) => None,
        }
    }

    /// Its file of `shaders/brdf/` (eval, sample and pdf), which `brdf_eval` and the samplers call for it
    /// alone, dispatching on the material's model; `None` for a measurement or an analytic model, which are
    /// not told apart here.
    pub fn shader_file(&self) -> Option<&'static str> {
        Some(match self {
            Brdf::Lambert { .. } => "brdf/lambert.glsl",
            Brdf::OrenNayar { .. } => "brdf/oren_nayar.glsl",
            Brdf::Phong { .. } => "brdf/phong.glsl",
            Brdf::BlinnPhong { .. } => "brdf/blinn_phong.glsl",
            Brdf::CookTorrance { .. } => "brdf/cook_torrance.glsl",
            Brdf::Measured(_) | Brdf::Analytic(_) => return None,
        })
    }

    /// The specular lobe of [`Brdf::eval`]; mirrors `brdf_eval_specular` in `shaders/common/brdf.glsl`.
    pub fn eval_specular(&self, n: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        if n.dot(wi) <= 0.0 || n.dot(wo) <= 0.0 {
            return Vec3::ZERO;
        }
        match *self {
            Brdf::Phong { ks, shininess, .. } => phong_specular(n, wi, wo, ks, shininess),
            Brdf::BlinnPhong { ks, shininess, .. } => blinn_phong_specular(n, wi, wo, ks, shininess),
            Brdf::CookTorrance { f0, roughness, metalness, .. } => {
                metalness * cook_torrance_specular(n, wi, wo, f0, roughness)
            }
            Brdf::Lambert { .. } | Brdf::OrenNayar { .. } | Brdf::Measured(_) | Brdf::Analytic(_) => Vec3::ZERO,
        }
    }
}
