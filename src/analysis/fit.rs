//! Fitting one model to a material: the parameters of a model that best match, in least squares, another
//! model's f_r cos(theta_o) over the hemisphere of wo for a set of incidence angles ([`fit`]), or a
//! measurement's entries by the measure of Ngan, Durand and Matusik 2005 ([`fit_measurement`]); every model's
//! value from the probe pass (`brdf_eval`).
//!
//! Each model is linear in its colours once its one shape parameter is fixed (Phong's shininess, Oren-Nayar's
//! sigma, GGX's roughness): f = sum over k of c_k b_k(wi, wo), the b_k being the model evaluated with unit
//! colours. So the colours come from linear least squares per channel (variable projection) and the shape
//! parameter from a scan of its range followed by a golden-section search around the best value of the scan.

use std::f64::consts::PI;

use glam::Vec3;

use super::Channel;
use crate::brdf::measured::{directions_at, entry_angles, entry_index, PHI_D_BINS, THETA_D_BINS, THETA_H_BINS};
use crate::brdf::{Brdf, DiffuseModel, Measured};
use crate::error::Result;
use crate::render::{ProbeCase, Renderer};

/// The models a material can be fitted with, by their scene-file names.
pub const FIT_MODELS: [&str; 5] = ["lambert", "oren-nayar", "phong", "blinn-phong", "cook-torrance"];

/// The incidence angles fitted over unless told otherwise (degrees).
pub const DEFAULT_THETA_I: [f64; 6] = [0.0, 15.0, 30.0, 45.0, 60.0, 75.0];

/// The grid of wo: theta_o every degree, phi_o every 2 degrees over half the hemisphere (every model here
/// is symmetric about the plane of incidence).
const THETA_STEPS: usize = 90;
const PHI_STEPS: usize = 90;

/// A fitted model: its parameters, and the residual and the target's size on the same measure.
#[derive(Clone, Debug, PartialEq)]
pub struct Fit {
    pub brdf: Brdf,
    /// The weighted root mean square of (fitted - target) over the samples, on the fit's [`Measure`], and
    /// the target's own root mean square.
    pub residual: f64,
    pub target_rms: f64,
}

/// One sample: the directions, its weight (the solid angle it stands for) and the cosine its values are
/// multiplied by.
struct Sample {
    wi: Vec3,
    wo: Vec3,
    weight: f64,
    cosine: f32,
}

/// How the difference of two samples' colours is made one number before it is squared.
#[derive(Clone, Copy)]
enum Measure {
    /// Its luminance.
    Luminance,
    /// Each channel apart (the sum of their squares over three).
    Channels,
}

/// Ngan et al.'s limit: entries with theta_i or theta_o above 80 degrees are left out, measurements at
/// grazing angles being unreliable.
pub const NGAN_MAX_THETA: f64 = 80.0;

/// The entries of a measurement the fit reads: every theta_h entry, every second theta_d and every fourth
/// phi_d (182,250 of 1,458,000 before the limits). Measured on a Cook-Torrance copy (roughness 0.4) fitted
/// with Blinn-Phong and Phong: shininess within 0.3% and the residual within 0.6% of the whole table's, in
/// a ninth of the time (3.6 s against 33 s on lavapipe).
const MEASUREMENT_STRIDES: (usize, usize, usize) = (1, 2, 4);

fn samples(theta_i: &[f64]) -> Vec<Sample> {
    let (d_theta, d_phi) = (0.5 * PI / THETA_STEPS as f64, PI / PHI_STEPS as f64);
    let mut samples = Vec::new();
    for &incidence in theta_i {
        let incidence = incidence.to_radians();
        let wi = Vec3::new(incidence.sin() as f32, 0.0, incidence.cos() as f32);
        for t in 0..THETA_STEPS {
            let theta = (t as f64 + 0.5) * d_theta;
            for p in 0..PHI_STEPS {
                // phi_o from the mirror side (0) round to wi's side (pi).
                let phi = (p as f64 + 0.5) * d_phi;
                let wo =
                    Vec3::new((-theta.sin() * phi.cos()) as f32, (theta.sin() * phi.sin()) as f32, theta.cos() as f32);
                samples.push(Sample { wi, wo, weight: theta.sin() * d_theta * d_phi, cosine: wo.z });
            }
        }
    }
    samples
}

/// The model `name` with shape parameter `shape`: the brdfs whose values are its basis functions (unit
/// colours), and how coefficients (per channel, one per basis function) make the model's brdf.
struct Family {
    name: &'static str,
    /// The shape parameter's name, range, and whether it is searched on a log scale; None: no shape.
    shape: Option<(&'static str, f64, f64, bool)>,
    /// The Cook-Torrance diffuse lobe, kept from the target when it is Cook-Torrance.
    diffuse: DiffuseModel,
}

impl Family {
    fn new(name: &str, target: &Brdf) -> Option<Self> {
        let diffuse = match *target {
            Brdf::CookTorrance { diffuse, .. } => diffuse,
            _ => DiffuseModel::OrenNayar,
        };
        let (name, shape) = match name {
            "lambert" => ("lambert", None),
            "oren-nayar" => ("oren-nayar", Some(("sigma", 0.0, 1.5, false))),
            "phong" => ("phong", Some(("shininess", 0.5, 20000.0, true))),
            "blinn-phong" => ("blinn-phong", Some(("shininess", 0.5, 20000.0, true))),
            "cook-torrance" => ("cook-torrance", Some(("roughness", 0.02, 1.0, true))),
            _ => return None,
        };
        Some(Self { name, shape, diffuse })
    }

    fn basis(&self, shape: f32) -> Vec<Brdf> {
        let (zero, one) = (Vec3::ZERO, Vec3::ONE);
        match self.name {
            "lambert" => vec![Brdf::Lambert { kd: one }],
            "oren-nayar" => vec![Brdf::OrenNayar { kd: one, sigma: shape }],
            "phong" => vec![Brdf::Lambert { kd: one }, Brdf::Phong { kd: zero, ks: one, shininess: shape }],
            "blinn-phong" => vec![Brdf::Lambert { kd: one }, Brdf::BlinnPhong { kd: zero, ks: one, shininess: shape }],
            _ => {
                // (1 - m) kd f_diffuse + m (S0 + f0 (S1 - S0)): Schlick's F is affine in f0, so the specular
                // lobe is S0 (f0 = 0) plus f0 times (S1 - S0) (S1: f0 = 1).
                let lobe = |metalness: f32, f0: Vec3| Brdf::CookTorrance {
                    kd: one,
                    f0,
                    roughness: shape,
                    metalness,
                    diffuse: self.diffuse,
                };
                vec![lobe(0.0, zero), lobe(1.0, zero), lobe(1.0, one)]
            }
        }
    }

    /// The per-channel coefficients of [`Family::basis`] that make `brdf` (of this family, at the basis's
    /// shape): [`Family::assemble`] undone, so that the model's values are the basis's combined.
    fn coefficients(&self, brdf: &Brdf) -> Vec<Vec3> {
        match *brdf {
            Brdf::Lambert { kd } | Brdf::OrenNayar { kd, .. } => vec![kd],
            Brdf::Phong { kd, ks, .. } | Brdf::BlinnPhong { kd, ks, .. } => vec![kd, ks],
            Brdf::CookTorrance { kd, f0, metalness: m, .. } => vec![(1.0 - m) * kd, m * (Vec3::ONE - f0), m * f0],
            Brdf::Measured(_) | Brdf::Analytic(_) => Vec::new(),
        }
    }

    /// The model from its shape and per-channel coefficients of [`Family::basis`] (the last two of
    /// Cook-Torrance's are S0 and S1, recombined as metalness and f0 here).
    fn assemble(&self, shape: f32, c: &[Vec3]) -> Brdf {
        let unit = |v: Vec3| v.clamp(Vec3::ZERO, Vec3::ONE);
        match self.name {
            "lambert" => Brdf::Lambert { kd: unit(c[0]) },
            "oren-nayar" => Brdf::OrenNayar { kd: unit(c[0]), sigma: shape },
            "phong" => Brdf::Phong { kd: unit(c[0]), ks: c[1].max(Vec3::ZERO), shininess: shape },
            "blinn-phong" => Brdf::BlinnPhong { kd: unit(c[0]), ks: c[1].max(Vec3::ZERO), shininess: shape },
            _ => {
                // c1 S0 + c2 S1 = m S0 + m f0 (S1 - S0): m = c1 + c2 (one metalness for the three channels:
                // their mean), f0 = c2 / m; kd = c0 / (1 - m). Where S0 was not told apart (c1 = 0), m f0 = c2
                // alone is known: m is then the least that keeps f0 within 1, the largest c2.
                let m = ((c[1] + c[2]).element_sum() / 3.0).max(c[2].max_element()).clamp(0.0, 1.0);
                let f0 = if m > 0.0 { unit(c[2] / m) } else { Vec3::ZERO };
                let kd = if m < 1.0 { unit(c[0] / (1.0 - m)) } else { Vec3::ZERO };
                Brdf::CookTorrance { kd, f0, roughness: shape, metalness: m, diffuse: self.diffuse }
            }
        }
    }
}

/// How many models a fit tries ([`fit`]'s progress counts them): the scan's, the search's and the last.
pub const FIT_STEPS: usize = SCAN + 1 + 2 + GOLDEN_STEPS + 1;
const SCAN: usize = 24;
const GOLDEN_STEPS: usize = 40;

/// Fits `model` (one of [`FIT_MODELS`]) to `target` over the incidence angles `theta_i` (degrees), telling
/// `progress` how many models it has tried. `None` when the model is not one of them.
///
/// # Errors
/// What the probe pass returns.
pub fn fit(
    renderer: &mut Renderer,
    target: &Brdf,
    model: &str,
    theta_i: &[f64],
    progress: impl FnMut(usize),
) -> Result<Option<Fit>> {
    let Some(family) = Family::new(model, target) else { return Ok(None) };
    let samples = samples(theta_i);
    let wanted = lobe_values(renderer, std::slice::from_ref(target), &samples)?.remove(0);
    let weights: Vec<f64> = samples.iter().map(|s| s.weight).collect();
    let values = |brdfs: &[Brdf]| lobe_values(renderer, brdfs, &samples);
    solve_family(&family, &wanted, &weights, Measure::Luminance, values, progress).map(Some)
}

/// Fits `model` (one of [`FIT_MODELS`]) to a measurement as Ngan, Durand and Matusik 2005 fit the MERL
/// materials ("Experimental Analysis of BRDF Models", EGSR): least squares of f_r cos(theta_i) over the
/// measured entries (all three channels measured), theta_i and theta_o below [`NGAN_MAX_THETA`], each entry
/// weighed by the solid angle it stands for, each channel apart; the residual is their
/// E = sqrt(sum w (f cos theta_i - f' cos theta_i)^2 / sum w), over the three channels. The entries are
/// read at their centres, as measured (not interpolated), every [`MEASUREMENT_STRIDES`]. `None` when the
/// model is not one of them.
///
/// # Errors
/// What the probe pass returns.
pub fn fit_measurement(
    renderer: &mut Renderer,
    measured: &Measured,
    model: &str,
    progress: impl FnMut(usize),
) -> Result<Option<Fit>> {
    let Some(family) = Family::new(model, &Brdf::Measured(measured.clone())) else { return Ok(None) };
    let (samples, wanted) = measurement_samples(measured);
    let weights: Vec<f64> = samples.iter().map(|s| s.weight).collect();
    let values = |brdfs: &[Brdf]| lobe_values(renderer, brdfs, &samples);
    solve_family(&family, &wanted, &weights, Measure::Channels, values, progress).map(Some)
}

/// Fits `model` (one of [`FIT_MODELS`]) to values that the model's render makes at some samples:
/// `values(brdfs)` gives each brdf's, linear in its colours, to match `wanted` in weighted least squares,
/// each channel apart (a fit to an image: [`super::image_fit`]). `target`'s Cook-Torrance diffuse lobe is
/// kept. `None` when the model is not one of them.
///
/// # Errors
/// What `values` returns.
pub(super) fn fit_values(
    target: &Brdf,
    model: &str,
    wanted: &[[f64; 3]],
    weights: &[f64],
    values: impl FnMut(&[Brdf]) -> Result<Vec<Vec<[f64; 3]>>>,
    progress: impl FnMut(usize),
) -> Result<Option<Fit>> {
    let Some(family) = Family::new(model, target) else { return Ok(None) };
    solve_family(&family, wanted, weights, Measure::Channels, values, progress).map(Some)
}

/// A model's parameters by their scene-file names, each with its components (three for a colour); none for a
/// measurement.
pub fn parameters(brdf: &Brdf) -> Vec<(&'static str, Vec<f32>)> {
    let colour = |c: Vec3| c.to_array().to_vec();
    match *brdf {
        Brdf::Lambert { kd } => vec![("kd", colour(kd))],
        Brdf::OrenNayar { kd, sigma } => vec![("kd", colour(kd)), ("sigma", vec![sigma])],
        Brdf::Phong { kd, ks, shininess } | Brdf::BlinnPhong { kd, ks, shininess } => {
            vec![("kd", colour(kd)), ("ks", colour(ks)), ("shininess", vec![shininess])]
        }
        Brdf::CookTorrance { kd, f0, roughness, metalness, .. } => {
            vec![("kd", colour(kd)), ("f0", colour(f0)), ("roughness", vec![roughness]), ("metalness", vec![metalness])]
        }
        Brdf::Measured(_) | Brdf::Analytic(_) => Vec::new(),
    }
}

/// `brdf` with component `component` of parameter `name` ([`parameters`]) set to `value`.
pub fn with_parameter(brdf: &Brdf, name: &str, component: usize, value: f32) -> Brdf {
    let mut changed = brdf.clone();
    let scalar = match (&mut changed, name) {
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

/// The entries a measurement is fitted over, at their centres, and their values times cos(theta_i).
///
/// An entry's weight is the solid angle of its cell in (wi, wo): d wi d wo = 4 cos(theta_d) d w_h d w_d
/// (Rusinkiewicz 1998), so sin(theta_h) cos(theta_d) sin(theta_d) times the cell's widths, theta_h's growing
/// with its index (theta_h = (index / 90)^2 90 degrees).
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
                let (wi, wo) = directions_at(angles);
                let value = table.entry(entry_index(h, d, p));
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

/// The solver: for each shape parameter tried, the colours by weighted linear least squares of the
/// family's basis (`values` gives each brdf's value at every sample) against `wanted`, the residual on
/// `measure`; over the shape, a scan of its range and a golden-section search around the scan's best.
fn solve_family(
    family: &Family,
    wanted: &[[f64; 3]],
    weights: &[f64],
    measure: Measure,
    mut values: impl FnMut(&[Brdf]) -> Result<Vec<Vec<[f64; 3]>>>,
    mut progress: impl FnMut(usize),
) -> Result<Fit> {
    let mut tried = 0;
    let mut solve = |shape: f64| -> Result<(f64, Brdf)> {
        tried += 1;
        progress(tried);
        let shape = shape as f32;
        let basis = values(&family.basis(shape))?;
        let coefficients = least_squares(&basis, wanted, weights);
        let brdf = family.assemble(shape, &coefficients);
        // The model is linear in its colours: its values are the basis's, combined by its own coefficients
        // (those of the least squares, clamped to the model's ranges).
        let own = family.coefficients(&brdf);
        let fitted: Vec<[f64; 3]> = (0..wanted.len())
            .map(|s| std::array::from_fn(|c| own.iter().zip(&basis).map(|(k, b)| f64::from(k[c]) * b[s][c]).sum()))
            .collect();
        Ok((rms_difference(&fitted, wanted, weights, measure), brdf))
    };
    let (residual, brdf) = match family.shape {
        None => solve(0.0)?,
        Some((_, low, high, log)) => {
            let (to, from) = scale(log);
            let (a, b) = (to(low), to(high));
            // A scan of the range, then a golden-section search between the best point's neighbours.
            let scan = SCAN;
            let mut best = (f64::INFINITY, 0);
            for k in 0..=scan {
                let (residual, _) = solve(from(a + (b - a) * k as f64 / scan as f64))?;
                if residual < best.0 {
                    best = (residual, k);
                }
            }
            let step = (b - a) / scan as f64;
            let (mut lo, mut hi) =
                ((a + step * (best.1 as f64 - 1.0)).max(a), (a + step * (best.1 as f64 + 1.0)).min(b));
            // Each step keeps one of its two inner points (the golden ratio puts it where the next step's
            // point falls), so it tries one new model.
            let golden = 0.5 * (5f64.sqrt() - 1.0);
            let (mut x1, mut x2) = (hi - golden * (hi - lo), lo + golden * (hi - lo));
            let (mut f1, mut f2) = (solve(from(x1))?.0, solve(from(x2))?.0);
            for _ in 0..GOLDEN_STEPS {
                if f1 <= f2 {
                    (hi, x2, f2) = (x2, x1, f1);
                    x1 = hi - golden * (hi - lo);
                    f1 = solve(from(x1))?.0;
                } else {
                    (lo, x1, f1) = (x1, x2, f2);
                    x2 = lo + golden * (hi - lo);
                    f2 = solve(from(x2))?.0;
                }
            }
            solve(from(0.5 * (lo + hi)))?
        }
    };
    let zero = vec![[0.0; 3]; wanted.len()];
    Ok(Fit { brdf, residual, target_rms: rms_difference(&zero, wanted, weights, measure) })
}

/// A map of a shape parameter to or from the scale it is searched on.
type ScaleMap = fn(f64) -> f64;

/// The maps to and from the scale a shape parameter is searched on.
fn scale(log: bool) -> (ScaleMap, ScaleMap) {
    if log {
        (f64::ln, f64::exp)
    } else {
        (|x| x, |x| x)
    }
}

/// f_r times each sample's cosine, of each brdf at each sample, from the probe pass.
fn lobe_values(renderer: &mut Renderer, brdfs: &[Brdf], samples: &[Sample]) -> Result<Vec<Vec<[f64; 3]>>> {
    let cases: Vec<ProbeCase> = brdfs
        .iter()
        .flat_map(|brdf| samples.iter().map(move |s| ProbeCase { brdf: brdf.clone(), n: Vec3::Z, wi: s.wi, wo: s.wo }))
        .collect();
    let values = renderer.probe_brdfs(&cases)?;
    Ok(values
        .chunks_exact(samples.len())
        .map(|lobe| lobe.iter().zip(samples).map(|(f, s)| (f.as_dvec3() * f64::from(s.cosine)).to_array()).collect())
        .collect())
}

/// Per channel, the coefficients c minimising sum of w (sum_k c_k basis_k - wanted)^2 (normal equations,
/// at most three unknowns, solved by Gauss-Jordan elimination on the diagonal, which the symmetric positive
/// semi-definite matrix allows). A basis function the samples cannot tell from the ones before it (its pivot
/// under 1e-9 of the largest diagonal entry: Cook-Torrance's S0, f0 = 0, where the Fresnel term does not vary
/// over the samples) is left out: its coefficient is 0.
fn least_squares(basis: &[Vec<[f64; 3]>], wanted: &[[f64; 3]], weights: &[f64]) -> Vec<Vec3> {
    let k = basis.len();
    let mut coefficients = vec![Vec3::ZERO; k];
    for channel in 0..3 {
        let mut a = vec![vec![0.0f64; k + 1]; k];
        for (i, row) in a.iter_mut().enumerate() {
            for j in 0..k {
                row[j] = (0..wanted.len()).map(|s| weights[s] * basis[i][s][channel] * basis[j][s][channel]).sum();
            }
            row[k] = (0..wanted.len()).map(|s| weights[s] * basis[i][s][channel] * wanted[s][channel]).sum();
        }
        let negligible = 1e-9 * (0..k).map(|i| a[i][i]).fold(1e-300, f64::max);
        for column in 0..k {
            if a[column][column].abs() < negligible {
                a[column].iter_mut().for_each(|v| *v = 0.0);
                a.iter_mut().for_each(|row| row[column] = 0.0);
                continue;
            }
            let pivot_row = a[column].clone();
            for (row, values) in a.iter_mut().enumerate() {
                if row != column {
                    let factor = values[column] / pivot_row[column];
                    for (value, pivot) in values.iter_mut().zip(&pivot_row).skip(column) {
                        *value -= factor * pivot;
                    }
                }
            }
        }
        for (i, c) in coefficients.iter_mut().enumerate() {
            if a[i][i].abs() >= negligible {
                c[channel] = (a[i][k] / a[i][i]) as f32;
            }
        }
    }
    coefficients
}

/// The weighted root mean square of (a - b) on `measure`.
fn rms_difference(a: &[[f64; 3]], b: &[[f64; 3]], weights: &[f64], measure: Measure) -> f64 {
    let squared = |x: [f64; 3], y: [f64; 3]| match measure {
        Measure::Luminance => (Channel::Luminance.of(x) - Channel::Luminance.of(y)).powi(2),
        Measure::Channels => (0..3).map(|c| (x[c] - y[c]).powi(2)).sum::<f64>() / 3.0,
    };
    let total: f64 = weights.iter().sum();
    let sum: f64 = a.iter().zip(b).zip(weights).map(|((x, y), w)| w * squared(*x, *y)).sum();
    (sum / total).sqrt()
}
