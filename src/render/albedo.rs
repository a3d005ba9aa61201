//! Directional albedo, rho(theta_o) = integral over the hemisphere of f_r(wi, wo) cos(theta_i) dwi, computed
//! by the albedo probe (`shaders/brdf_albedo.comp`, `brdf_eval` itself) with adaptive Gauss-Kronrod cubature:
//! deterministic, and with a bound on its error rather than a noisy estimate.
//!
//! The hemisphere of wi is cut into cells in (theta_i, phi_i). On each the GPU returns the 15-point Kronrod
//! estimate and the 7-point Gauss estimate embedded in it; their difference bounds the error of the Gauss
//! one, and so (far more than) the Kronrod one's, which is what is summed. While an albedo's bounds add up
//! to more than the tolerance, its cells of largest bound are cut in four and integrated again (global
//! adaptive cubature, as QUADPACK's QAG in two dimensions), up to [`MAX_REFINEMENTS`] rounds; the bound
//! stated is the sum over the cells kept, so it holds whichever way the loop ended. The first cells have edges where the models have kinks: theta_i = theta_o (Oren-Nayar's
//! max and min of the angles) and phi_i = 90 degrees (its max(0, cos(phi_i - phi_o))).
//!
//! Every model here is symmetric about the plane of incidence, so phi_i runs over [0, pi] and counts twice.

use std::f64::consts::{FRAC_PI_2, PI};

use glam::Vec3;

use super::{AlbedoCell, AlbedoJob, CellIntegral, Renderer};
use crate::brdf::Brdf;
use crate::error::Result;

/// The error bound asked of each albedo: 1e-5, two orders below an 8-bit level.
pub const ALBEDO_TOLERANCE: f64 = 1e-5;

/// How many rounds of cutting cells in four an albedo may take: at most 6 degrees / 2^16 on a side.
pub const MAX_REFINEMENTS: u32 = 16;

/// The most cells one albedo is cut into: past it, the bound reached is the one stated.
const MAX_CELLS_PER_ANGLE: usize = 100_000;

/// The widest first cell, in radians (6 degrees).
const FIRST_CELL: f64 = 6.0 * PI / 180.0;

/// The most cells sent to the GPU at once (32 bytes in and out each).
const CELLS_PER_DISPATCH: usize = 1 << 20;

/// The angles a directional albedo is taken at (degrees): every degree from 0 to 89, then 89.9 (at 90 itself
/// wo grazes the surface and every model here reflects nothing).
pub fn albedo_angles() -> Vec<f64> {
    (0..90).map(f64::from).chain([89.9]).collect()
}

/// One directional albedo: rho per channel and a bound on its error (the largest channel's).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Albedo {
    /// The directional albedo per channel (RGB): f_r cos(theta_i) integrated over the hemisphere of wi.
    pub rho: [f64; 3],
    /// A bound on the integration's error, the largest channel's.
    pub error_bound: f64,
}

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
    let mut integrated: Vec<Vec<Integrated>> = vec![Vec::new(); jobs.len()];
    let mut pending: Vec<Cell> = theta_o.iter().enumerate().flat_map(|(job, &theta)| first_cells(job, theta)).collect();
    for _ in 0..=MAX_REFINEMENTS {
        crate::interrupt::check()?;
        if pending.is_empty() {
            break;
        }
        for (cell, integral) in pending.iter().zip(integrate(renderer, &jobs, &pending)?) {
            integrated[cell.job].push(Integrated::new(*cell, integral));
        }
        pending =
            integrated.iter_mut().flat_map(|cells| worst_cells(cells, tolerance)).flat_map(|c| c.quarters()).collect();
    }
    Ok(integrated
        .iter()
        .map(|cells| {
            let mut rho = [0.0; 3];
            for cell in cells {
                for (sum, v) in rho.iter_mut().zip(cell.value) {
                    *sum += v;
                }
            }
            Albedo { rho, error_bound: cells.iter().map(|c| c.bound).sum() }
        })
        .collect())
}

/// A cell with its integral (both halves of the hemisphere) and the bound on its error.
#[derive(Clone, Copy, Debug)]
struct Integrated {
    cell: Cell,
    value: [f64; 3],
    bound: f64,
}

impl Integrated {
    fn new(cell: Cell, integral: CellIntegral) -> Self {
        // Twice: phi_i in [-pi, 0] mirrors [0, pi].
        Self {
            cell,
            value: (2.0 * integral.kronrod.as_dvec3()).to_array(),
            bound: 2.0 * f64::from((integral.kronrod - integral.gauss).abs().max_element()),
        }
    }
}

/// When a job's bounds add up to more than `tolerance`: takes out its cells of largest bound, as many as
/// leave the rest within half the tolerance, to be cut in four (each quarter's rule is far more accurate).
fn worst_cells(cells: &mut Vec<Integrated>, tolerance: f64) -> Vec<Cell> {
    let total: f64 = cells.iter().map(|c| c.bound).sum();
    if total <= tolerance || cells.len() >= MAX_CELLS_PER_ANGLE {
        return Vec::new();
    }
    cells.sort_by(|a, b| b.bound.total_cmp(&a.bound));
    let mut left = total;
    let split = cells.iter().take_while(|c| {
        let taken = left > tolerance / 2.0;
        left -= c.bound;
        taken
    });
    let count = split.count();
    cells.drain(..count).map(|c| c.cell).collect()
}

/// A cell of the (theta_i, phi_i) rectangle of one job, in radians.
#[derive(Clone, Copy, Debug)]
struct Cell {
    job: usize,
    theta: (f64, f64),
    phi: (f64, f64),
}

impl Cell {
    fn quarters(&self) -> [Cell; 4] {
        let theta = (self.theta.0 + self.theta.1) / 2.0;
        let phi = (self.phi.0 + self.phi.1) / 2.0;
        let cell = |theta, phi| Cell { job: self.job, theta, phi };
        [
            cell((self.theta.0, theta), (self.phi.0, phi)),
            cell((theta, self.theta.1), (self.phi.0, phi)),
            cell((self.theta.0, theta), (phi, self.phi.1)),
            cell((theta, self.theta.1), (phi, self.phi.1)),
        ]
    }
}

/// The first cells of a job: at most [`FIRST_CELL`] on a side, with edges at theta_o and phi = pi/2.
fn first_cells(job: usize, theta_o: f64) -> Vec<Cell> {
    let theta_edges =
        if theta_o > 0.0 && theta_o < FRAC_PI_2 { vec![0.0, theta_o, FRAC_PI_2] } else { vec![0.0, FRAC_PI_2] };
    let thetas = split(&theta_edges);
    let phis = split(&[0.0, FRAC_PI_2, PI]);
    thetas.iter().flat_map(|&theta| phis.iter().map(move |&phi| Cell { job, theta, phi })).collect()
}

/// Each interval between successive edges cut into equal parts of at most [`FIRST_CELL`].
fn split(edges: &[f64]) -> Vec<(f64, f64)> {
    edges
        .windows(2)
        .flat_map(|pair| {
            let parts = ((pair[1] - pair[0]) / FIRST_CELL).ceil().max(1.0) as usize;
            let step = (pair[1] - pair[0]) / parts as f64;
            (0..parts).map(move |k| {
                (pair[0] + k as f64 * step, if k + 1 == parts { pair[1] } else { pair[0] + (k + 1) as f64 * step })
            })
        })
        .collect()
}

/// The cells' integrals from the GPU, in batches of at most [`CELLS_PER_DISPATCH`].
fn integrate(renderer: &mut Renderer, jobs: &[AlbedoJob], cells: &[Cell]) -> Result<Vec<CellIntegral>> {
    let mut integrals = Vec::with_capacity(cells.len());
    for batch in cells.chunks(CELLS_PER_DISPATCH) {
        let gpu_cells: Vec<AlbedoCell> = batch
            .iter()
            .map(|cell| AlbedoCell {
                job: cell.job as u32,
                theta: (cell.theta.0 as f32, cell.theta.1 as f32),
                phi: (cell.phi.0 as f32, cell.phi.1 as f32),
            })
            .collect();
        integrals.extend(renderer.probe_albedo_cells(jobs, &gpu_cells)?);
    }
    Ok(integrals)
}
