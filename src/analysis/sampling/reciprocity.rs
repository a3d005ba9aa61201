//! Helmholtz reciprocity, f_r(wi, wo) = f_r(wo, wi), measured with the probe pass (`brdf_eval` on the GPU) on
//! pairs of directions spread over both hemispheres of the frame.
//!
//! The course's Phong and Blinn-Phong divide their lobe by cos θi alone, so that their f_r is not reciprocal
//! by definition: for them the symmetry held is their lobe's times cos θi, (f_r - kd / π) cos θi = ks cos^s α,
//! and that is what is tested.

use glam::Vec3;

use super::{view_direction, Verdict};
use crate::brdf::Brdf;
use crate::error::Result;
use crate::render::{ProbeCase, Renderer};

/// The relative difference float32 evaluations may leave between f_r(wi, wo) and f_r(wo, wi) (the same sums
/// taken in another order).
const RELATIVE_TOLERANCE: f64 = 1e-3;

/// The absolute floor of the tolerance, as a share of the largest value measured.
const ABSOLUTE_TOLERANCE: f64 = 1e-5;

/// A pair of directions: (θi, φi, θo, φo) in degrees.
pub type PairAngles = (f64, f64, f64, f64);

/// What the measure found.
#[derive(Clone, Debug, PartialEq)]
pub struct Reciprocity {
    /// Whether the lobe times cos θi is what is symmetric (the course's Phong and Blinn-Phong), not f_r.
    pub with_cosine: bool,
    /// The pairs measured.
    pub pairs: usize,
    /// The worst pair: (θi, φi, θo, φo) in degrees, and the two values.
    pub worst: Option<(PairAngles, f64, f64)>,
    /// The worst difference as a share of what is allowed (at most 1 passes).
    pub worst_ratio: f64,
}

impl Reciprocity {
    /// The verdict of the test.
    pub fn verdict(&self) -> Verdict {
        let what =
            if self.with_cosine { "(f - kd/π) cos θi (the course's lobe divides by cos θi alone)" } else { "f" };
        let detail = match self.worst {
            Some(((ti, pi, to, po), a, b)) if self.worst_ratio > 0.0 => format!(
                "{what} over {} pairs, worst at θi {ti}° φi {pi}°, θo {to}° φo {po}°: {a:.6e} against {b:.6e} \
                 ({:.2} of what float allows)",
                self.pairs, self.worst_ratio
            ),
            _ => format!("{what} over {} pairs: equal", self.pairs),
        };
        Verdict { test: "reciprocity", view: None, passed: self.worst_ratio <= 1.0, detail }
    }
}

/// The pairs of directions measured: θ every 15° from 5° to 80° and 88°, φ of the pair's difference every 30°,
/// and each pair's first direction turned 10° about the normal (anisotropic models see it).
fn pairs() -> Vec<PairAngles> {
    let thetas = [5.0, 20.0, 35.0, 50.0, 65.0, 80.0, 88.0];
    let mut pairs = Vec::new();
    for &theta_i in &thetas {
        for &theta_o in &thetas {
            for k in 0..12 {
                let phi_o = -180.0 + 30.0 * k as f64;
                pairs.push((theta_i, 10.0, theta_o, 10.0 + phi_o));
            }
        }
    }
    pairs
}

/// Measures `brdf`'s reciprocity.
///
/// # Errors
/// What the probe pass returns.
pub fn measure(renderer: &mut Renderer, brdf: &Brdf) -> Result<Reciprocity> {
    // The course's lobes: what is symmetric is f_r less the Lambert term, times cos θi.
    let course_lobe = match brdf {
        Brdf::Phong { kd, .. } | Brdf::BlinnPhong { kd, .. } => Some(*kd / std::f32::consts::PI),
        _ => None,
    };
    let with_cosine = course_lobe.is_some();
    let pairs = pairs();
    let n = Vec3::Z;
    let cases: Vec<ProbeCase> = pairs
        .iter()
        .flat_map(|&(ti, pi, to, po)| {
            let (wi, wo) = (view_direction(ti, pi), view_direction(to, po));
            [ProbeCase { brdf: brdf.clone(), n, wi, wo }, ProbeCase { brdf: brdf.clone(), n, wi: wo, wo: wi }]
        })
        .collect();
    let values = renderer.probe_brdfs(&cases)?;
    // Each value as compared: f_r, or the course's lobe times cos θi.
    let value = |case: &ProbeCase, f: Vec3| match course_lobe {
        Some(lambert) => (0..3).map(|k| (f[k] - lambert[k]) as f64 * case.wi.z as f64).collect::<Vec<f64>>(),
        None => (0..3).map(|k| f[k] as f64).collect(),
    };
    let measured: Vec<Vec<f64>> = cases.iter().zip(&values).map(|(c, &f)| value(c, f)).collect();
    let scale = measured.iter().flatten().fold(0.0f64, |m, v| m.max(v.abs()));
    let mut outcome = Reciprocity { with_cosine, pairs: pairs.len(), worst: None, worst_ratio: 0.0 };
    for (pair, both) in pairs.iter().zip(measured.chunks_exact(2)) {
        for (&a, &b) in both[0].iter().zip(&both[1]) {
            let allowed = RELATIVE_TOLERANCE * a.abs().max(b.abs()) + ABSOLUTE_TOLERANCE * scale;
            let ratio = if a.is_finite() && b.is_finite() {
                if allowed > 0.0 {
                    (a - b).abs() / allowed
                } else {
                    0.0
                }
            } else {
                f64::INFINITY
            };
            if ratio > outcome.worst_ratio || outcome.worst.is_none() {
                outcome.worst_ratio = outcome.worst_ratio.max(ratio);
                outcome.worst = Some((*pair, a, b));
            }
        }
    }
    Ok(outcome)
}
