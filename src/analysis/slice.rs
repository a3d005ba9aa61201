//! BRDF Explorer's image slice: f_r over the half angle theta_h and the difference angle theta_d
//! (Rusinkiewicz 1998, "A new change of variables for efficient BRDF representation") at a fixed phi_d, from
//! the probe pass.
//!
//! For isotropic models phi_h does not matter (it is 0 here): h = (sin theta_h, 0, cos theta_h), wi is the
//! difference vector d = (sin theta_d cos phi_d, sin theta_d sin phi_d, cos theta_d) turned by theta_h about
//! the y axis (as h is from n), and wo is wi mirrored about h.

use glam::{Quat, Vec3};

use crate::brdf::Brdf;
use crate::error::Result;
use crate::render::{ProbeCase, Renderer};

/// (wi, wo) for half and difference angles in radians.
pub fn rusinkiewicz_directions(theta_h: f64, theta_d: f64, phi_d: f64) -> (Vec3, Vec3) {
    let d = Vec3::new((theta_d.sin() * phi_d.cos()) as f32, (theta_d.sin() * phi_d.sin()) as f32, theta_d.cos() as f32);
    let turn = Quat::from_rotation_y(theta_h as f32);
    let h = turn * Vec3::Z;
    let wi = turn * d;
    (wi, 2.0 * h.dot(wi) * h - wi)
}

/// A slice: `cells` x `cells` values of f_r, rows of theta_d (from 0) of columns of theta_h (from 0), each
/// at its cell's centre over [0, 90] degrees; `None` where wi or wo is below the horizon (no reflection).
#[derive(Clone, Debug)]
pub struct Slice {
    /// The grid's side: `cells` x `cells` values.
    pub cells: usize,
    /// `cells * cells` values of f_r (RGB), row by row: value `theta_d * cells + theta_h` in cells.
    pub values: Vec<Option<Vec3>>,
}

impl Slice {
    /// The angle in degrees at the centre of cell `k`.
    pub fn angle(&self, k: usize) -> f64 {
        (k as f64 + 0.5) * 90.0 / self.cells as f64
    }
}

/// The slice of each material at `phi_d` (degrees), `cells` on a side.
///
/// # Errors
/// What the probe pass returns.
pub fn slices(renderer: &mut Renderer, brdfs: &[Brdf], phi_d: f64, cells: usize) -> Result<Vec<Slice>> {
    let angle = |k: usize| ((k as f64 + 0.5) * 90.0 / cells as f64).to_radians();
    let directions: Vec<(Vec3, Vec3)> = (0..cells)
        .flat_map(|row| {
            (0..cells).map(move |column| rusinkiewicz_directions(angle(column), angle(row), phi_d.to_radians()))
        })
        .collect();
    let cases: Vec<ProbeCase> = brdfs
        .iter()
        .flat_map(|brdf| directions.iter().map(move |&(wi, wo)| ProbeCase { brdf: brdf.clone(), n: Vec3::Z, wi, wo }))
        .collect();
    let values = renderer.probe_brdfs(&cases)?;
    Ok(values
        .chunks_exact(directions.len())
        .map(|slice| Slice {
            cells,
            values: slice
                .iter()
                .zip(&directions)
                .map(|(&f, (wi, wo))| (wi.z > 0.0 && wo.z > 0.0).then_some(f))
                .collect(),
        })
        .collect())
}
