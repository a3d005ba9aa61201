//! RGL files of our own: a microfacet model (its NDF and its f_r) tabulated into the format as the paper's
//! parameterisation defines it, so that the reader is proven without the database (which is not reachable
//! here): the NDF and the projected area on their squares, per incident direction the density of visible
//! normals, and at each node of the sample square the value the reader must find there, f_r cos(theta_o)
//! 4 sigma(wi) / D(m) (the Jacobian held, as RGL's files do).

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use super::tensor::{Field, Fields};
use super::warp::Grid2D;
use super::{unit_to_phi, unit_to_theta};

/// Rec. 709's luminance of linear RGB: the file's `luminance` field, and a model's retroreflection's.
const LUMINANCE: Vec3 = Vec3::new(0.2126, 0.7152, 0.0722);

/// Where a model is tabulated.
pub struct Tabulation {
    /// The incident elevations, radians, increasing from 0.
    pub theta_i: Vec<f32>,
    /// The incident azimuths, radians: one value for an isotropic model.
    pub phi_i: Vec<f32>,
    /// Nodes a side of the NDF's and the projected area's squares.
    pub ndf_nodes: usize,
    /// Nodes a side of the sample square (the VNDF's and the values').
    pub sample_nodes: usize,
}

/// The direction of the square's point `u` (theta, phi), turned by `phi_offset`.
fn direction(u: Vec2, phi_offset: f32) -> Vec3 {
    let (theta, phi) = (unit_to_theta(u.x), unit_to_phi(u.y) + phi_offset);
    Vec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos())
}

/// dm / du: the solid angle per unit of the square at `u`, 2 pi^2 u_x sin(theta).
fn solid_angle_per_unit(u: Vec2) -> f32 {
    2.0 * PI * PI * u.x * unit_to_theta(u.x).sin()
}

/// The node `k` of `n` along a side.
fn node(k: usize, n: usize) -> f32 {
    k as f32 / (n - 1) as f32
}

/// The projected area of the microsurface seen from an incident direction, integral of D(m) max(0,
/// incident . m) dm, by the midpoint rule on the NDF's square (256 x 256 cells, summed in double precision):
/// the NDF and the solid angle at the cells' midpoints evaluated once, for every incident direction.
struct ProjectedArea {
    /// Each cell's normal, D there and the solid angle per unit of the square.
    cells: Vec<(Vec3, f32, f32)>,
}

impl ProjectedArea {
    const CELLS: usize = 256;

    fn new(ndf: &dyn Fn(Vec3) -> f32) -> Self {
        let n = Self::CELLS;
        let cells = (0..n * n)
            .map(|k| {
                let u = Vec2::new(((k % n) as f32 + 0.5) / n as f32, ((k / n) as f32 + 0.5) / n as f32);
                let m = direction(u, 0.0);
                (m, ndf(m), solid_angle_per_unit(u))
            })
            .collect();
        Self { cells }
    }

    fn at(&self, incident: Vec3) -> f32 {
        let sum: f64 = self.cells.iter().map(|&(m, d, area)| f64::from(d * incident.dot(m).max(0.0) * area)).sum();
        (sum / self.cells.len() as f64) as f32
    }
}

/// The fields of an RGL file of the model whose NDF is `ndf` (of the microfacet normal) and f_r `brdf`
/// (of the light's direction, then the view's, in the surface's frame), at `at`.
///
/// # Errors
/// A model whose visible normals have no density at some incident direction (its NDF zero there).
pub fn tabulate(
    description: &str,
    ndf: &dyn Fn(Vec3) -> f32,
    brdf: &dyn Fn(Vec3, Vec3) -> Vec3,
    at: &Tabulation,
) -> Result<Fields, String> {
    let isotropic = at.phi_i.len() <= 2;
    let (n, s) = (at.ndf_nodes, at.sample_nodes);
    let square = |f: &dyn Fn(Vec2) -> f32| -> Vec<f32> {
        (0..n).flat_map(|y| (0..n).map(move |x| Vec2::new(node(x, n), node(y, n)))).map(f).collect()
    };
    let ndf_values = square(&|u| ndf(direction(u, 0.0)));
    let projected_area = ProjectedArea::new(ndf);
    let sigma_values = square(&|u| projected_area.at(direction(u, 0.0)));
    let (mut vndf, mut luminance, mut rgb) = (Vec::new(), Vec::new(), Vec::new());
    for &phi_i in &at.phi_i {
        for &theta_i in &at.theta_i {
            let incident = Vec3::new(theta_i.sin() * phi_i.cos(), theta_i.sin() * phi_i.sin(), theta_i.cos());
            let offset = if isotropic { phi_i } else { 0.0 };
            let visible: Vec<f32> = (0..s * s)
                .map(|k| {
                    let u = Vec2::new(node(k % s, s), node(k / s, s));
                    let m = direction(u, offset);
                    ndf(m) * incident.dot(m).max(0.0) * solid_angle_per_unit(u)
                })
                .collect();
            let warp = Grid2D::density(visible.clone(), s, s, Vec::new())
                .map_err(|e| format!("theta_i {theta_i}, phi_i {phi_i}: the visible normals' {e}"))?;
            let sigma = projected_area.at(incident);
            let mut channels = [vec![0.0; s * s], vec![0.0; s * s], vec![0.0; s * s]];
            let mut lightness = vec![0.0; s * s];
            for k in 0..s * s {
                let (u_m, _) = warp.sample(Vec2::new(node(k % s, s), node(k / s, s)), &[]);
                let m = direction(u_m, offset);
                let outgoing = 2.0 * incident.dot(m) * m - incident;
                let d = ndf(m);
                if outgoing.z <= 0.0 || d <= 0.0 {
                    continue;
                }
                let value = brdf(outgoing, incident) * outgoing.z * 4.0 * sigma / d;
                for (channel, v) in channels.iter_mut().zip(value.to_array()) {
                    channel[k] = v;
                }
                lightness[k] = LUMINANCE.dot(value);
            }
            vndf.extend(visible);
            luminance.extend(lightness);
            rgb.extend(channels.concat());
        }
    }
    let incident = [at.phi_i.len(), at.theta_i.len()];
    let mut fields = Fields::new();
    fields.insert("description".into(), Field::bytes(description.as_bytes().to_vec()));
    fields.insert("jacobian".into(), Field::bytes(vec![1]));
    fields.insert("theta_i".into(), Field::floats(vec![at.theta_i.len()], at.theta_i.clone()));
    fields.insert("phi_i".into(), Field::floats(vec![at.phi_i.len()], at.phi_i.clone()));
    fields.insert("ndf".into(), Field::floats(vec![n, n], ndf_values));
    fields.insert("sigma".into(), Field::floats(vec![n, n], sigma_values));
    fields.insert("vndf".into(), Field::floats(vec![incident[0], incident[1], s, s], vndf));
    fields.insert("luminance".into(), Field::floats(vec![incident[0], incident[1], s, s], luminance));
    fields.insert("rgb".into(), Field::floats(vec![incident[0], incident[1], 3, s, s], rgb));
    Ok(fields)
}

/// The incident elevations of [`tabulate_model`]'s files: every 10 degrees to 60, then every 5 to 85, where
/// a lobe changes fastest.
pub const MODEL_THETA_I: [f32; 12] = [0.0, 10.0, 20.0, 30.0, 40.0, 50.0, 60.0, 65.0, 70.0, 75.0, 80.0, 85.0];

/// The step of the incident azimuths of [`tabulate_model`]'s files of a `.brdf` model, degrees: over the
/// whole turn, both ends included.
pub const MODEL_PHI_STEP: f32 = 15.0;

/// A model with a Rust mirror as an RGL file's fields (`vk-render tabulate --output NAME.bsdf`): its f_r at
/// [`MODEL_THETA_I`], one phi_i for a built-in (isotropic) model and every [`MODEL_PHI_STEP`] for a `.brdf` file's
/// (which may not be), in the frame of the tangent +x; a 64 x 64 NDF and 48 x 48 samples (40 x 40 over the
/// azimuths). The parameterisation's NDF is Cook-Torrance's GGX (alpha = roughness^2); another model's is
/// its retroreflection, D(m) proportional to f_r(m, m) cos^2(theta_m) (a microfacet model's
/// D G F / (4 cos^2) with G and F taken as even, as Dupuy and Jakob's acquisition reads the NDF from
/// retroreflection; any NDF parameterises any model, and this one puts the samples where the lobe is).
///
/// # Errors
/// A model with no Rust mirror (a measured table, a `.brdf` model without one).
pub fn tabulate_model(brdf: &crate::brdf::Brdf, description: &str) -> Result<Fields, String> {
    use crate::brdf::Brdf;
    if matches!(brdf, Brdf::Measured(_)) || !brdf.has_mirror() {
        return Err(format!(
            "a {} material: an RGL file is written of a built-in model or a .brdf file with a Rust mirror",
            brdf.name()
        ));
    }
    let f = |light: Vec3, view: Vec3| brdf.eval_in_frame(Vec3::Z, Vec3::X, light, view);
    let ndf = |m: Vec3| match brdf {
        Brdf::CookTorrance { roughness, .. } => crate::brdf::cook_torrance::d_ggx(Vec3::Z, m, roughness * roughness),
        // A floor of the cosine's density keeps every direction's visible normals a density.
        _ => (LUMINANCE.dot(f(m, m)) * m.z * m.z).max(1e-6 * m.z),
    };
    // A .brdf model may be anisotropic: its incident azimuths over the whole turn, fewer samples each.
    let anisotropic = matches!(brdf, Brdf::Analytic(_));
    let phi_i = if anisotropic {
        (0..=(360.0 / MODEL_PHI_STEP) as usize).map(|k| (k as f32 * MODEL_PHI_STEP - 180.0).to_radians()).collect()
    } else {
        vec![0.0]
    };
    let at = Tabulation {
        theta_i: MODEL_THETA_I.map(f32::to_radians).to_vec(),
        phi_i,
        ndf_nodes: 64,
        sample_nodes: if anisotropic { 40 } else { 48 },
    };
    tabulate(description, &ndf, &f, &at)
}
