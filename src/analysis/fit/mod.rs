//! Fitting one model to a material: the parameters of a model that best match, in least squares, another
//! model's f_r cos(theta_o) over the hemisphere of wo for a set of incidence angles ([`fit`]), or a
//! measurement's entries by the measure of Ngan, Durand and Matusik 2005 ([`fit_measurement`]); every model's
//! value from the probe pass (`brdf_eval`), so a course's model and a `.brdf` file's alike.
//!
//! What a fit varies of each model is its family (`family.rs`); every fit goes through the one solver
//! (`solver.rs`): variable projection over the colours a model is linear in, bounded Levenberg-Marquardt over
//! the rest.

mod family;
mod solver;

use std::f64::consts::PI;

use glam::Vec3;

use family::{analytic_family, linear_colours, Family};
use solver::{solve, Problem};

use crate::brdf::measured::{directions_at, entry_angles, entry_index, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use crate::brdf::{Analytic, Brdf, DiffuseModel, Measured, ParameterKind, ParameterValue};
use crate::error::{Error, Result};
use crate::render::Renderer;

/// Each brdf's values at every sample (f_r times the sample's cosine), from the probe pass.
type Values<'a> = dyn FnMut(&[Brdf]) -> Result<Vec<Vec<[f64; 3]>>> + 'a;

/// The models a material can be fitted with, by their scene-file names.
pub const FIT_MODELS: [&str; 5] = ["lambert", "oren-nayar", "phong", "blinn-phong", "cook-torrance"];

/// Cook-Torrance with one base colour for both lobes (kd = f0), its metalness searched beside its roughness:
/// the metallic-roughness material of glTF, Standard Surface and OpenPBR, which have one base colour (a
/// fit's Cook-Torrance has two, which these formats cannot hold at a metalness between 0 and 1).
pub const BASE_COLOUR_MODEL: &str = "metallic-roughness";

/// The incidence angles fitted over unless told otherwise (degrees).
pub const DEFAULT_THETA_I: [f64; 6] = [0.0, 15.0, 30.0, 45.0, 60.0, 75.0];

/// The grid of wo: theta_o every degree, phi_o every 2 degrees over half the hemisphere where both models are
/// symmetric about the plane of incidence (the course's and measured ones), over all of it otherwise.
const THETA_STEPS: usize = 90;
const PHI_STEPS: usize = 90;

/// A fitted model: its parameters, and the residual and the target's size on the same measure.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    /// The fitted model with its parameters.
    pub brdf: Brdf,
    /// The weighted root mean square of (fitted - target) over the samples, on the fit's measure, and
    /// the target's own root mean square.
    pub residual: f64,
    /// The target's own root mean square on the same measure, to judge `residual` by.
    pub target_rms: f64,
    /// Each parameter the fit determined (a built-in model's every one; an analytic model's searched and
    /// solved ones, not those held) with its standard error per component: the Gauss-Newton estimate
    /// sqrt(s^2 (J^T W J)^-1) at the fit, J the change of the fitted values with the parameter, W the
    /// samples' weights and s^2 the residuals' variance. `None` for a component the samples do not determine.
    /// Against another model (no noise), it says how sharply the residual's minimum is defined.
    pub parameters: Vec<Determined>,
}

/// A parameter's value and how well it is determined.
#[derive(Clone, Debug, PartialEq)]
pub struct Determined {
    /// The parameter's name: the scene file's key, or the name the `.brdf` file declares.
    pub name: String,
    /// Its fitted components: one, or three for a colour.
    pub values: Vec<f32>,
    /// Each component's standard error, `None` where the samples do not determine it.
    pub errors: Vec<Option<f64>>,
}

/// A model to fit: one of the course's, by its scene-file name ([`FIT_MODELS`]), or an analytic model (a
/// `.brdf` file) searched from a material of it, some of its parameters held at that material's values.
#[derive(Clone, Debug, PartialEq)]
pub enum FitModel {
    /// One of the course's models, by its name in [`FIT_MODELS`], or [`BASE_COLOUR_MODEL`].
    BuiltIn(&'static str),
    /// An analytic model, searched from a material of it.
    Analytic {
        /// The material the search starts from: its model and first values.
        start: Analytic,
        /// The parameters kept at `start`'s values (bools always are).
        held: Vec<String>,
    },
}

impl FitModel {
    /// The course's model `name`, one of [`FIT_MODELS`], or [`BASE_COLOUR_MODEL`].
    pub fn named(name: &str) -> Option<Self> {
        FIT_MODELS.iter().chain([&BASE_COLOUR_MODEL]).find(|m| **m == name).map(|m| FitModel::BuiltIn(m))
    }

    /// The scene files' name of the model its fits are (the base colour model's are Cook-Torrance); none for
    /// an analytic model.
    pub fn scene_model(&self) -> Option<&'static str> {
        match self {
            FitModel::BuiltIn(BASE_COLOUR_MODEL) => Some("cook-torrance"),
            FitModel::BuiltIn(name) => Some(name),
            FitModel::Analytic { .. } => None,
        }
    }

    /// An analytic model searched from `start`, the parameters `held` kept at its values (bools always are).
    ///
    /// # Errors
    /// A message naming a held parameter the model does not have, and those it has.
    pub fn analytic(start: Analytic, held: Vec<String>) -> std::result::Result<Self, String> {
        for name in &held {
            if start.value(name).is_none() {
                let names: Vec<&str> = start.values().map(|(p, _)| p.name.as_str()).collect();
                return Err(format!(
                    "--hold {name}: {} has no such parameter (it has {})",
                    start.model().name(),
                    names.join(", ")
                ));
            }
        }
        Ok(FitModel::Analytic { start, held })
    }

    /// The model of `brdf` itself, searched from its values: a measurement has none.
    pub fn of(brdf: &Brdf) -> Option<Self> {
        match brdf {
            Brdf::Measured(_) => None,
            Brdf::Analytic(material) => Some(FitModel::Analytic { start: material.clone(), held: Vec::new() }),
            built_in => Self::named(built_in.name()),
        }
    }

    /// The model's name: the course's, or the `.brdf` file's.
    pub fn name(&self) -> String {
        match self {
            FitModel::BuiltIn(name) => (*name).to_string(),
            FitModel::Analytic { start, .. } => start.model().name(),
        }
    }

    /// What a fit varies of the model against `target` (whose Cook-Torrance diffuse lobe a Cook-Torrance fit
    /// keeps); an analytic model's colours are solved linearly where the model is linear in them at the
    /// samples `values` evaluates.
    fn family(&self, target: &Brdf, values: &mut Values) -> Result<Family> {
        match self {
            FitModel::BuiltIn(name) => {
                let diffuse = match *target {
                    Brdf::CookTorrance { diffuse, .. } => diffuse,
                    _ => DiffuseModel::OrenNayar,
                };
                Family::built_in(name, diffuse).ok_or_else(|| Error::Input {
                    path: (*name).into(),
                    message: format!(
                        "not a model to fit (expected one of {}, {BASE_COLOUR_MODEL})",
                        FIT_MODELS.join(", ")
                    ),
                })
            }
            FitModel::Analytic { start, held } => {
                let linear = linear_colours(start, held, values)?;
                Ok(analytic_family(start.clone(), held, linear))
            }
        }
    }
}

/// One sample: the directions, its weight (the solid angle it stands for) and the cosine its values are
/// multiplied by.
struct Sample {
    wi: Vec3,
    wo: Vec3,
    weight: f64,
    cosine: f32,
}

/// Ngan et al.'s limit: entries with theta_i or theta_o above 80 degrees are left out, measurements at
/// grazing angles being unreliable.
pub const NGAN_MAX_THETA: f64 = 80.0;

/// The entries of a measurement the fit reads: every theta_h entry, every second theta_d and every fourth
/// phi_d (182,250 of 1,458,000 before the limits). Measured on a Cook-Torrance copy (roughness 0.4) fitted
/// with Blinn-Phong and Phong: shininess within 0.3% and the residual within 0.6% of the whole table's, in
/// a ninth of the time (3.6 s against 33 s on lavapipe).
const MEASUREMENT_STRIDES: (usize, usize, usize) = (1, 2, 4);

/// The samples of wo at each incidence angle: over half the hemisphere when `symmetric`, all of it otherwise.
fn samples(theta_i: &[f64], symmetric: bool) -> Vec<Sample> {
    let (phi_steps, phi_range) = if symmetric { (PHI_STEPS, PI) } else { (2 * PHI_STEPS, 2.0 * PI) };
    let (d_theta, d_phi) = (0.5 * PI / THETA_STEPS as f64, phi_range / phi_steps as f64);
    let mut samples = Vec::new();
    for &incidence in theta_i {
        let incidence = incidence.to_radians();
        let wi = Vec3::new(incidence.sin() as f32, 0.0, incidence.cos() as f32);
        for t in 0..THETA_STEPS {
            let theta = (t as f64 + 0.5) * d_theta;
            for p in 0..phi_steps {
                // phi_o from the mirror side (0) round to wi's side (pi), and on round for all of it.
                let phi = (p as f64 + 0.5) * d_phi;
                let wo =
                    Vec3::new((-theta.sin() * phi.cos()) as f32, (theta.sin() * phi.sin()) as f32, theta.cos() as f32);
                samples.push(Sample { wi, wo, weight: theta.sin() * d_theta * d_phi, cosine: wo.z });
            }
        }
    }
    samples
}

/// Fits `model` to `target` over the incidence angles `theta_i` (degrees), telling `progress` how many models
/// it has evaluated: weighted least squares of f_r cos(theta_o) over the hemispheres of wo (weighed by solid
/// angle), each channel apart, the residual their root mean square over the three channels.
///
/// # Errors
/// What the probe pass returns.
pub fn fit(
    renderer: &mut Renderer,
    target: &Brdf,
    model: &FitModel,
    theta_i: &[f64],
    mut progress: impl FnMut(usize),
) -> Result<Fit> {
    let analytic = |b: &Brdf| matches!(b, Brdf::Analytic(_));
    let samples = samples(theta_i, !analytic(target) && matches!(model, FitModel::BuiltIn(_)));
    let wanted = lobe_values(renderer, std::slice::from_ref(target), &samples)?.remove(0);
    let weights: Vec<f64> = samples.iter().map(|s| s.weight).collect();
    let mut values = |brdfs: &[Brdf]| lobe_values(renderer, brdfs, &samples);
    let family = model.family(target, &mut values)?;
    solve(&Problem::new(&family, &wanted, &weights), &mut values, &mut progress)
}

/// Fits `model` to a measurement as Ngan, Durand and Matusik 2005 fit the MERL materials ("Experimental
/// Analysis of BRDF Models", EGSR): least squares of f_r cos(theta_i) over the measured entries (all three
/// channels measured), theta_i and theta_o below [`NGAN_MAX_THETA`], each entry weighed by the solid angle it
/// stands for, each channel apart; the residual is their E = sqrt(sum w (f cos theta_i - f' cos theta_i)^2 /
/// sum w), over the three channels. The entries are read at their centres, as measured (not interpolated),
/// every theta_h entry, every second theta_d and every fourth phi_d (`MEASUREMENT_STRIDES`).
///
/// # Errors
/// What the probe pass returns.
pub fn fit_measurement(
    renderer: &mut Renderer,
    measured: &Measured,
    model: &FitModel,
    mut progress: impl FnMut(usize),
) -> Result<Fit> {
    let (samples, wanted) = measurement_samples(measured);
    let weights: Vec<f64> = samples.iter().map(|s| s.weight).collect();
    let mut values = |brdfs: &[Brdf]| lobe_values(renderer, brdfs, &samples);
    let family = model.family(&Brdf::Measured(measured.clone()), &mut values)?;
    solve(&Problem::new(&family, &wanted, &weights), &mut values, &mut progress)
}

/// Fits `model` to values that its render makes at some samples: `values(brdfs)` gives each brdf's, to match
/// `wanted` in weighted least squares, each channel apart (a fit to an image: [`super::image_fit`]).
/// `target`'s Cook-Torrance diffuse lobe is kept.
///
/// # Errors
/// What `values` returns.
pub(super) fn fit_values(
    target: &Brdf,
    model: &FitModel,
    wanted: &[[f64; 3]],
    weights: &[f64],
    mut values: impl FnMut(&[Brdf]) -> Result<Vec<Vec<[f64; 3]>>>,
    mut progress: impl FnMut(usize),
) -> Result<Fit> {
    let family = model.family(target, &mut values)?;
    solve(&Problem::new(&family, wanted, weights), &mut values, &mut progress)
}

/// A model's parameters by their scene-file names, each with its components (three for a colour): an
/// analytic model's floats and colours (not its bools); none for a measurement.
pub fn parameters(brdf: &Brdf) -> Vec<(String, Vec<f32>)> {
    let colour = |c: Vec3| c.to_array().to_vec();
    let named = |list: Vec<(&str, Vec<f32>)>| list.into_iter().map(|(n, v)| (n.to_string(), v)).collect();
    match brdf {
        Brdf::Lambert { kd } => named(vec![("kd", colour(*kd))]),
        Brdf::OrenNayar { kd, sigma } => named(vec![("kd", colour(*kd)), ("sigma", vec![*sigma])]),
        Brdf::Phong { kd, ks, shininess } | Brdf::BlinnPhong { kd, ks, shininess } => {
            named(vec![("kd", colour(*kd)), ("ks", colour(*ks)), ("shininess", vec![*shininess])])
        }
        Brdf::CookTorrance { kd, f0, roughness, metalness, .. } => named(vec![
            ("kd", colour(*kd)),
            ("f0", colour(*f0)),
            ("roughness", vec![*roughness]),
            ("metalness", vec![*metalness]),
        ]),
        Brdf::Analytic(material) => material
            .values()
            .filter_map(|(parameter, value)| match value {
                ParameterValue::Float(v) => Some((parameter.name.clone(), vec![v])),
                ParameterValue::Color(c) => Some((parameter.name.clone(), colour(c))),
                ParameterValue::Bool(_) => None,
            })
            .collect(),
        Brdf::Measured(_) => Vec::new(),
    }
}

/// `brdf` with component `component` of parameter `name` ([`parameters`]) set to `value`; an analytic
/// model's float within its range.
pub fn with_parameter(brdf: &Brdf, name: &str, component: usize, value: f32) -> Brdf {
    let mut changed = brdf.clone();
    let scalar = match (&mut changed, name) {
        (Brdf::Analytic(material), _) => {
            return Brdf::Analytic(with_analytic_parameter(material, name, component, value))
        }
        (
            Brdf::Lambert { kd }
            | Brdf::OrenNayar { kd, .. }
            | Brdf::Phong { kd, .. }
            | Brdf::BlinnPhong { kd, .. }
            | Brdf::CookTorrance { kd, .. },
            "kd",
        ) => &mut kd[component],
        (Brdf::Phong { ks, .. } | Brdf::BlinnPhong { ks, .. }, "ks") => &mut ks[component],
        (Brdf::CookTorrance { f0, .. }, "f0") => &mut f0[component],
        (Brdf::OrenNayar { sigma, .. }, "sigma") => sigma,
        (Brdf::Phong { shininess, .. } | Brdf::BlinnPhong { shininess, .. }, "shininess") => shininess,
        (Brdf::CookTorrance { roughness, .. }, "roughness") => roughness,
        (Brdf::CookTorrance { metalness, .. }, "metalness") => metalness,
        _ => return changed,
    };
    *scalar = value;
    changed
}

/// An analytic material with component `component` of its float or colour `name` set to `value` (a float
/// clamped to its range); unchanged for a name it does not have.
fn with_analytic_parameter(material: &Analytic, name: &str, component: usize, value: f32) -> Analytic {
    let Some(parameter) = material.model().parameter(name) else { return material.clone() };
    let value = match (parameter.kind, material.value(name)) {
        (ParameterKind::Float { min, max, .. }, _) => ParameterValue::Float(value.clamp(min, max)),
        (ParameterKind::Color { .. }, Some(ParameterValue::Color(mut c))) if component < 3 => {
            c[component] = value;
            ParameterValue::Color(c)
        }
        _ => return material.clone(),
    };
    material.clone().with(name, value).unwrap_or_else(|_| material.clone())
}

/// The entries a measurement is fitted over, at their centres, and their values times cos(theta_i).
///
/// An entry's weight is the solid angle of its cell in (wi, wo): d wi d wo = 4 cos(theta_d) d w_h d w_d
/// (Rusinkiewicz 1998), so sin(theta_h) cos(theta_d) sin(theta_d) times the cell's widths, theta_h's growing
/// with its index (theta_h = (index / 90)^2 90 degrees).
///
/// A MERL entry stands for every azimuth of the half vector (the material is isotropic), so each entry's
/// directions are turned about the normal by an azimuth of their own (the golden ratio's sequence over the
/// entries): an anisotropic model is then fitted over every azimuth, not along X alone, where its Y width
/// and the specular colour would trade off.
fn measurement_samples(measured: &Measured) -> (Vec<Sample>, Vec<[f64; 3]>) {
    let table = measured.table();
    let (stride_h, stride_d, stride_p) = MEASUREMENT_STRIDES;
    let max_cos = NGAN_MAX_THETA.to_radians().cos() as f32;
    let (mut samples, mut wanted) = (Vec::new(), Vec::new());
    for h in (0..THETA_H_BINS).step_by(stride_h) {
        let h_width = (2 * h + 1) as f64 / (THETA_H_BINS * THETA_H_BINS) as f64 * 0.5 * PI;
        for d in (0..THETA_D_BINS).step_by(stride_d) {
            for p in (0..PHI_D_BINS).step_by(stride_p) {
                let angles = entry_angles(h, d, p);
                let turn = glam::Quat::from_rotation_z(azimuth(samples.len()));
                let (wi, wo) = directions_at(angles);
                let (wi, wo) = (turn * wi, turn * wo);
                let value = table.measurement(entry_index(h, d, p), wi, wo);
                if wi.z <= max_cos || wo.z <= max_cos || value.min_element() < 0.0 {
                    continue;
                }
                let (theta_h, theta_d) = (f64::from(angles.x), f64::from(angles.y));
                let weight = theta_h.sin() * theta_d.cos() * theta_d.sin() * h_width;
                samples.push(Sample { wi, wo, weight, cosine: wi.z });
                wanted.push((value.as_dvec3() * f64::from(wi.z)).to_array());
            }
        }
    }
    (samples, wanted)
}

/// Point `index` of the golden ratio's sequence over [0, 2 pi): evenly spread azimuths for any count.
fn azimuth(index: usize) -> f32 {
    let golden = 0.5 * (5f64.sqrt() - 1.0);
    ((index as f64 * golden).fract() * 2.0 * PI) as f32
}

/// f_r times each sample's cosine, of each brdf at each sample, from the probe pass.
fn lobe_values(renderer: &mut Renderer, brdfs: &[Brdf], samples: &[Sample]) -> Result<Vec<Vec<[f64; 3]>>> {
    let pairs: Vec<(Vec3, Vec3)> = samples.iter().map(|s| (s.wi, s.wo)).collect();
    let values = renderer.probe_brdf_grid(brdfs, &pairs)?;
    Ok(values
        .chunks_exact(samples.len())
        .map(|lobe| lobe.iter().zip(samples).map(|(f, s)| (f.as_dvec3() * f64::from(s.cosine)).to_array()).collect())
        .collect())
}
