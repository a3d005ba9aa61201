//! The white furnace as a table: for a material and for its model made white over a grid of its main
//! parameter, the largest directional albedo over theta_o and where it occurs. Above 1 the model creates
//! energy; below 1 a white lobe loses some.
//!
//! White means each lobe alone at full strength, so that what a row says belongs to that lobe: Lambert and
//! Oren-Nayar with kd = 1; the course's Phong and Blinn-Phong specular lobes with ks = 1 and kd = 0 (their
//! diffuse part is Lambert's row); Cook-Torrance as a white conductor (metalness 1, f0 = 1: the specular lobe)
//! and as its diffuse lobe (metalness 0, kd = 1).

use glam::Vec3;

use super::albedo::{albedo_angles, directional_albedos, Albedo};
use super::NamedBrdf;
use crate::brdf::{Brdf, DiffuseModel};
use crate::error::Result;
use crate::render::Renderer;

/// One row of the table.
#[derive(Clone, Debug, PartialEq)]
pub struct FurnaceRow {
    /// The material's name for its own row; `white` for the grid's.
    pub material: String,
    /// Its BRDF.
    pub brdf: Brdf,
    /// The largest albedo of any channel over the angles, and the angle (degrees) where it occurs.
    pub max_albedo: f64,
    /// The angle theta_o of `max_albedo`, in degrees from the normal.
    pub theta_o: f64,
    /// A bound on the error of `max_albedo` (the integration's, see [`super::albedo`]).
    pub error_bound: f64,
}

impl FurnaceRow {
    /// What the row says of energy, beyond the error bound: created, lost (only a white lobe can be said to
    /// lose energy: a material reflects less than 1 by its colour), or kept.
    pub fn verdict(&self) -> String {
        let margin = self.error_bound.max(1e-5);
        let percent = (self.max_albedo - 1.0) * 100.0;
        if self.max_albedo > 1.0 + margin {
            format!("creates energy: {percent:+.2}% at {} degrees", self.theta_o)
        } else if self.material == WHITE && self.max_albedo < 1.0 - margin {
            format!("loses energy: {percent:+.2}% at best")
        } else {
            "conserves energy".to_string()
        }
    }
}

/// The `material` of the grid's rows.
pub const WHITE: &str = "white";

/// The white grid of a model: the lobe of `brdf`'s model at full strength over its main parameter.
pub fn white_grid(brdf: &Brdf) -> Vec<Brdf> {
    let white = Vec3::ONE;
    match *brdf {
        Brdf::Lambert { .. } => vec![Brdf::Lambert { kd: white }],
        Brdf::OrenNayar { .. } => {
            [0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.8, 1.0].map(|sigma| Brdf::OrenNayar { kd: white, sigma }).to_vec()
        }
        Brdf::Phong { .. } => SHININESS.map(|shininess| Brdf::Phong { kd: Vec3::ZERO, ks: white, shininess }).to_vec(),
        Brdf::BlinnPhong { .. } => {
            SHININESS.map(|shininess| Brdf::BlinnPhong { kd: Vec3::ZERO, ks: white, shininess }).to_vec()
        }
        Brdf::CookTorrance { diffuse, .. } => [1.0, 0.0]
            .iter()
            .flat_map(|&metalness| {
                ROUGHNESS.map(|roughness| Brdf::CookTorrance { kd: white, f0: white, roughness, metalness, diffuse })
            })
            .collect(),
        // A measurement has no parameter to vary; an analytic model, no main parameter known to vk-render.
        Brdf::Measured(_) | Brdf::Analytic(_) => Vec::new(),
    }
}

const SHININESS: [f32; 8] = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0, 128.0];
const ROUGHNESS: [f32; 10] = [0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0];

/// Which white grid a material belongs to: materials of one model share it (Cook-Torrance's per diffuse lobe).
fn grid_kind(brdf: &Brdf) -> (&'static str, Option<DiffuseModel>) {
    match *brdf {
        Brdf::CookTorrance { diffuse, .. } => (brdf.name(), Some(diffuse)),
        _ => (brdf.name(), None),
    }
}

/// The table: each material's own row, then its model's white grid (once per model), each albedo within
/// `tolerance`. `progress` is told how many rows of how many are done.
///
/// # Errors
/// What the albedo probe returns.
pub fn furnace(
    renderer: &mut Renderer,
    materials: &[NamedBrdf],
    tolerance: f64,
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<FurnaceRow>> {
    let mut wanted: Vec<(String, Brdf)> = Vec::new();
    let mut grids_taken = Vec::new();
    for material in materials {
        wanted.push((material.name.clone(), material.brdf.clone()));
        let kind = grid_kind(&material.brdf);
        if !grids_taken.contains(&kind) {
            grids_taken.push(kind);
            wanted.extend(white_grid(&material.brdf).into_iter().map(|brdf| (WHITE.to_string(), brdf)));
        }
    }
    let angles = albedo_angles();
    let radians: Vec<f64> = angles.iter().map(|a| a.to_radians()).collect();
    let mut rows = Vec::with_capacity(wanted.len());
    for (done, (material, brdf)) in wanted.into_iter().enumerate() {
        progress(done, rows.capacity());
        let albedos = directional_albedos(renderer, &brdf, &radians, tolerance)?;
        let (at, largest) = largest(&albedos);
        rows.push(FurnaceRow {
            material,
            brdf,
            max_albedo: largest.rho.iter().copied().fold(f64::MIN, f64::max),
            theta_o: angles[at],
            error_bound: largest.error_bound,
        });
    }
    progress(rows.len(), rows.len());
    Ok(rows)
}

/// The index and value of the albedo whose largest channel is largest (the first of equals).
fn largest(albedos: &[Albedo]) -> (usize, Albedo) {
    let top = |a: &Albedo| a.rho.iter().copied().fold(f64::MIN, f64::max);
    albedos
        .iter()
        .copied()
        .enumerate()
        .fold((0, albedos[0]), |best, (i, a)| if top(&a) > top(&best.1) { (i, a) } else { best })
}
