//! Lobes: f_r(wi, wo) (times cos(theta_o) unless asked otherwise) along a cut of the hemisphere of wo, from
//! the probe pass (`brdf_eval` on the GPU).
//!
//! The frame: n = +z, wi in the xz-plane at +x. The cut is the plane of incidence turned by phi about n;
//! theta_o runs from -90 to 90 degrees, negative on the side of wi, so that with phi = 0 the mirror direction
//! is at theta_o = theta_i.

use glam::Vec3;

use crate::brdf::Brdf;
use crate::error::Result;
use crate::render::{ProbeCase, Renderer};

/// The lobe's sampling: every half degree.
pub const LOBE_STEP_DEGREES: f64 = 0.5;

/// What a lobe plots.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LobeCut {
    /// The incidence angle, in degrees from the normal.
    pub theta_i: f64,
    /// The cut's turn about the normal from the plane of incidence, in degrees.
    pub phi: f64,
    /// f_r cos(theta_o) (BRDF Explorer's default) or f_r alone.
    pub cosine: bool,
}

/// theta_o from -90 to 90 degrees in [`LOBE_STEP_DEGREES`].
pub fn lobe_angles() -> Vec<f64> {
    let steps = (180.0 / LOBE_STEP_DEGREES).round() as i32;
    (0..=steps).map(|k| -90.0 + f64::from(k) * LOBE_STEP_DEGREES).collect()
}

/// The unit vectors of a cut: wi, and wo for each theta_o (degrees).
pub fn cut_directions(cut: &LobeCut, theta_o: &[f64]) -> (Vec3, Vec<Vec3>) {
    let theta_i = cut.theta_i.to_radians();
    let wi = Vec3::new(theta_i.sin() as f32, 0.0, theta_i.cos() as f32);
    let phi = cut.phi.to_radians();
    let wo = theta_o
        .iter()
        .map(|theta| {
            let theta = theta.to_radians();
            // Negative theta_o on the side of wi (+x when phi = 0).
            Vec3::new((-theta.sin() * phi.cos()) as f32, (-theta.sin() * phi.sin()) as f32, theta.cos() as f32)
        })
        .collect();
    (wi, wo)
}

/// The lobe of each material along the cut, at [`lobe_angles`]: one value per channel per angle.
///
/// # Errors
/// What the probe pass returns.
pub fn lobes(renderer: &mut Renderer, brdfs: &[Brdf], cut: &LobeCut) -> Result<Vec<Vec<Vec3>>> {
    let angles = lobe_angles();
    let (wi, wo) = cut_directions(cut, &angles);
    let n = Vec3::Z;
    let cases: Vec<ProbeCase> =
        brdfs.iter().flat_map(|brdf| wo.iter().map(move |&wo| ProbeCase { brdf: brdf.clone(), n, wi, wo })).collect();
    let values = renderer.probe_brdfs(&cases)?;
    Ok(values
        .chunks_exact(angles.len())
        .map(|lobe| lobe.iter().zip(&wo).map(|(&f, wo)| if cut.cosine { f * wo.z.max(0.0) } else { f }).collect())
        .collect())
}
