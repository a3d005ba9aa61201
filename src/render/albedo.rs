//! Directional albedos by the adaptive cubature of crates/cubature, its cells integrated by the albedo
//! probe (`shaders/brdf_albedo.comp`, `brdf_eval` itself, on the device).

use glam::Vec3;

pub use cubature::{albedo_angles, Albedo, ALBEDO_TOLERANCE, MAX_REFINEMENTS};
use cubature::{Cell, CellEstimate, Cubature};

use super::{AlbedoJob, Renderer};
use crate::brdf::Brdf;
use crate::error::Result;

/// The most cells sent to the GPU at once (32 bytes in and out each).
const CELLS_PER_DISPATCH: usize = 1 << 20;

/// The directional albedo of `brdf` seen from each of `theta_o` (radians, from the normal, below pi/2),
/// each within `tolerance` (see [`Albedo::error_bound`] for what was reached).
///
/// # Errors
/// What the albedo probe returns (`Error::Vulkan`, `Error::Validation`, ...).
pub fn directional_albedos(
    renderer: &mut Renderer,
    brdf: &Brdf,
    theta_o: &[f64],
    tolerance: f64,
) -> Result<Vec<Albedo>> {
    let jobs: Vec<AlbedoJob> = theta_o
        .iter()
        .map(|&theta| AlbedoJob { brdf: brdf.clone(), wo: Vec3::new(theta.sin() as f32, 0.0, theta.cos() as f32) })
        .collect();
    let mut cubature = Cubature::new(theta_o, tolerance);
    while !cubature.pending().is_empty() {
        crate::interrupt::check()?;
        let estimates = integrate(renderer, &jobs, cubature.pending())?;
        cubature.take(&estimates).expect("the probe returns one integral per cell");
    }
    Ok(cubature.albedos())
}

/// The cells' integrals from the GPU, in batches of at most [`CELLS_PER_DISPATCH`].
fn integrate(renderer: &mut Renderer, jobs: &[AlbedoJob], cells: &[Cell]) -> Result<Vec<CellEstimate>> {
    let mut estimates = Vec::with_capacity(cells.len());
    for batch in cells.chunks(CELLS_PER_DISPATCH) {
        estimates.extend(renderer.probe_albedo_cells(jobs, batch)?);
    }
    Ok(estimates)
}
