//! Directional albedos by the adaptive cubature of crates/cubature, its cells integrated by the albedo
//! probe (`shaders/brdf_albedo.comp`, `brdf_eval` itself, on the device).

use glam::{DVec3, Vec3};

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
    let in_double = renderer.integrates_in_double(brdf)?;
    let mut cubature = Cubature::new(theta_o, tolerance);
    while !cubature.pending().is_empty() {
        crate::interrupt::check()?;
        let estimates = integrate(renderer, &jobs, cubature.pending(), in_double)?;
        cubature.take(&estimates).expect("the probe returns one integral per cell");
    }
    Ok(cubature.albedos())
}

/// The cells' integrals from the GPU, in batches of at most [`CELLS_PER_DISPATCH`]: `in_double`, evaluated
/// in double precision at the cells' nodes (shaders/brdf_density64.comp, the model's own GLSL made double)
/// and summed here; otherwise by the albedo probe, whose cells are the renderer's own `brdf_eval`.
fn integrate(
    renderer: &mut Renderer,
    jobs: &[AlbedoJob],
    cells: &[Cell],
    in_double: bool,
) -> Result<Vec<CellEstimate>> {
    let mut estimates = Vec::with_capacity(cells.len());
    if in_double {
        for batch in cells.chunks(CELLS_PER_DISPATCH_IN_DOUBLE) {
            match integrate_in_double(renderer, jobs, batch)? {
                Some(batch) => estimates.extend(batch),
                None => estimates.extend(renderer.probe_albedo_cells(jobs, batch)?),
            }
        }
        return Ok(estimates);
    }
    for batch in cells.chunks(CELLS_PER_DISPATCH) {
        estimates.extend(renderer.probe_albedo_cells(jobs, batch)?);
    }
    Ok(estimates)
}

/// The cells a batch in double precision takes: 225 directions each, of 32 bytes in and out.
const CELLS_PER_DISPATCH_IN_DOUBLE: usize = 1 << 12;

/// The cells' integrals from a `.brdf` file evaluated in double precision at their nodes, job by job.
fn integrate_in_double(
    renderer: &mut Renderer,
    jobs: &[AlbedoJob],
    cells: &[Cell],
) -> Result<Option<Vec<CellEstimate>>> {
    let mut estimates = vec![CellEstimate { kronrod: [0.0; 3], gauss: [0.0; 3] }; cells.len()];
    for (index, job) in jobs.iter().enumerate() {
        let mine: Vec<usize> = (0..cells.len()).filter(|&k| cells[k].job == index).collect();
        if mine.is_empty() {
            continue;
        }
        let directions: Vec<DVec3> =
            mine.iter().flat_map(|&k| cells[k].nodes()).map(|[x, y, z]| DVec3::new(x, y, z)).collect();
        let Some(values) = renderer.brdf_sampler_densities_double(&job.brdf, job.wo, &directions)? else {
            return Ok(None);
        };
        let f_cos: Vec<[f64; 3]> = values.iter().map(|v| [v[1], v[2], v[3]]).collect();
        for (&k, f_cos) in mine.iter().zip(f_cos.chunks_exact(15 * 15)) {
            estimates[k] = cells[k].estimate(f_cos);
        }
    }
    Ok(Some(estimates))
}
