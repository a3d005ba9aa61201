//! Measured materials of RGL's database (Dupuy and Jakob 2018, "An Adaptive Parameterization for Efficient
//! Material Acquisition and Rendering"): `.bsdf` files, Mitsuba's tensor files ([`tensor`]) holding the
//! material's NDF, its projected area, per incident direction the warp of visible normals and the measured
//! values at the warp's sample points. Evaluated as the paper defines the parameterisation (and Mitsuba 3's
//! `measured` plugin reads it): the half vector's point in the NDF's square, that point's sample under the
//! incident direction's VNDF warp, the values interpolated there, times D(m) / (4 sigma(wi)) when the file
//! says its values hold the warp's Jacobian.
//!
//! Directions: the file's incident direction is Mitsuba's `wi`, which in a camera path is the direction
//! towards the viewer; vk-render's `wo` (the view) is it, and its `wi` (the light) the file's outgoing one,
//! whose cosine the file's values include (Mitsuba's `eval` returns f_r cos(theta_o)): f_r is divided by it.
//!
//! An RGB file's `rgb` values are read as linear sRGB; a spectral file's `spectra` are reduced to them at
//! reading ([`spectrum`]: CIE 1931 under E, adapted to D65, sRGB's primaries).

pub mod spectrum;
pub mod tabulate;
pub mod tensor;
pub mod warp;

use std::f32::consts::PI;

use glam::{Vec2, Vec3};

use tensor::{Field, Fields, Values};
use warp::Grid2D;

/// The largest `.bsdf` file read: RGL's spectral files are about 20 MB.
pub const MAX_RGL_BYTES: u64 = 512 << 20;

/// The floats of [`RglTable::pack`]'s header: 7 of the material, 5 per grid.
pub const PACKED_HEADER: usize = 7 + 4 * 5;

/// An RGL material in memory.
#[derive(Clone, Debug)]
pub struct RglTable {
    /// The file's `description`.
    pub description: String,
    /// D over the NDF's square (x: theta_m as [`theta_to_unit`], y: phi_m as [`phi_to_unit`]).
    ndf: Grid2D,
    /// The projected area sigma(wi) over the same square of incident directions.
    sigma: Grid2D,
    /// Per incident direction (phi_i, theta_i), the density of visible normals over the NDF's square.
    vndf: Grid2D,
    /// Per incident direction and channel (red 0, green 1, blue 2), the values over the sample square.
    rgb: Grid2D,
    /// One or two phi_i: the material's values depend on phi_m - phi_i only.
    isotropic: bool,
    /// How many times the file's phi_i range fits in a turn (2 or 4: the material is that symmetric and the
    /// directions are folded into the range), 1 otherwise.
    reduction: u32,
    /// Whether the values hold the warp's Jacobian (then times D(m) / (4 sigma(wi))).
    jacobian: bool,
}

/// theta in [0, pi/2] to the square's coordinate: sqrt(theta / (pi/2)), finer near the normal.
pub fn theta_to_unit(theta: f32) -> f32 {
    (theta * (2.0 / PI)).max(0.0).sqrt()
}

/// The inverse of [`theta_to_unit`].
pub fn unit_to_theta(u: f32) -> f32 {
    u * u * (PI / 2.0)
}

/// phi in [-pi, pi] to [0, 1].
pub fn phi_to_unit(phi: f32) -> f32 {
    (phi + PI) / (2.0 * PI)
}

/// The inverse of [`phi_to_unit`].
pub fn unit_to_phi(u: f32) -> f32 {
    (2.0 * u - 1.0) * PI
}

/// The angle of a unit vector from the normal (0, 0, 1), accurate near it: 2 asin(|d - n| / 2).
pub fn elevation(d: Vec3) -> f32 {
    2.0 * (0.5 * (d - Vec3::Z).length()).clamp(-1.0, 1.0).asin()
}

/// `x` negated where `s` is positive or zero: a direction folded by the sign of the incident one's
/// coordinate (which itself ends negative).
fn against_sign(x: f32, s: f32) -> f32 {
    if s >= 0.0 {
        -x
    } else {
        x
    }
}

fn floats<'a>(fields: &'a Fields, name: &str, rank: usize) -> Result<(&'a [usize], &'a [f32]), String> {
    match fields.get(name) {
        Some(Field { shape, values: Values::Floats(values) }) if shape.len() == rank => Ok((shape, values)),
        Some(Field { shape, .. }) => {
            Err(format!("field `{name}`: shape {shape:?}, where an RGL file has {rank} dimensions of float32"))
        }
        None => Err(format!("no field `{name}`: not an RGL material file")),
    }
}

/// A spectral file's `spectra` (phi_i, theta_i, wavelength, y, x) as RGB values of the same shape with 3
/// channels ([`spectrum::rgb_weights`]: linear, so reduced at the nodes as between them).
fn spectra_as_rgb(fields: &Fields) -> Result<(Vec<usize>, Vec<f32>), String> {
    let (shape, spectra) = floats(fields, "spectra", 5)?;
    let (_, wavelengths) = floats(fields, "wavelengths", 1)?;
    if shape[2] != wavelengths.len() {
        return Err(format!("field `spectra`: shape {shape:?} for {} wavelengths", wavelengths.len()));
    }
    let weights = spectrum::rgb_weights(wavelengths).map_err(|e| format!("field `wavelengths`: {e}"))?;
    let nodes = shape[3] * shape[4];
    let mut rgb = Vec::with_capacity(spectra.len() / shape[2] * 3);
    for grid in spectra.chunks_exact(shape[2] * nodes) {
        let mut channels = vec![Vec3::ZERO; nodes];
        for (values, weight) in grid.chunks_exact(nodes).zip(&weights) {
            for (channel, &v) in channels.iter_mut().zip(values) {
                *channel += *weight * v;
            }
        }
        for c in 0..3 {
            rgb.extend(channels.iter().map(|v| v[c]));
        }
    }
    Ok((vec![shape[0], shape[1], 3, shape[3], shape[4]], rgb))
}

/// Whether `path` is a regular file that begins as a tensor file does (false when it cannot be read; a
/// FIFO or a device is never opened: the reader that follows refuses it by name).
pub fn is_rgl_file(path: &std::path::Path) -> bool {
    use std::io::Read;
    let mut start = [0u8; 12];
    std::fs::metadata(path).is_ok_and(|m| m.is_file())
        && std::fs::File::open(path).and_then(|mut f| f.read_exact(&mut start)).is_ok()
        && &start == tensor::MAGIC
}

impl RglTable {
    /// Reads the RGL file at `path`.
    ///
    /// # Errors
    /// One line naming the file: what [`tensor::parse`] or [`RglTable::from_fields`] finds wrong.
    pub fn read(path: &std::path::Path) -> Result<Self, String> {
        let shown = path.display();
        let bytes = crate::files::read_regular(path, "RGL file", MAX_RGL_BYTES)?;
        let fields = tensor::parse(&bytes).map_err(|e| format!("the RGL file {shown}: {e}"))?;
        Self::from_fields(&fields).map_err(|e| format!("the RGL file {shown}: {e}"))
    }

    /// The material of a tensor file's fields.
    ///
    /// # Errors
    /// A field missing, of the wrong type or rank, shapes that do not agree, in one line.
    pub fn from_fields(fields: &Fields) -> Result<Self, String> {
        let description = match fields.get("description") {
            Some(Field { values: Values::Bytes(b), .. }) => String::from_utf8_lossy(b).into_owned(),
            _ => return Err("no field `description` of uint8: not an RGL material file".into()),
        };
        let jacobian = match fields.get("jacobian") {
            Some(Field { shape, values: Values::Bytes(b) }) if shape == &[1] => b[0] != 0,
            _ => return Err("no field `jacobian` (one uint8): not an RGL material file".into()),
        };
        let (_, theta_i) = floats(fields, "theta_i", 1)?;
        let (_, phi_i) = floats(fields, "phi_i", 1)?;
        let (ndf_shape, ndf) = floats(fields, "ndf", 2)?;
        let (sigma_shape, sigma) = floats(fields, "sigma", 2)?;
        let (vndf_shape, vndf) = floats(fields, "vndf", 4)?;
        let (rgb_shape, rgb) = if fields.contains_key("rgb") {
            let (shape, values) = floats(fields, "rgb", 5)?;
            (shape.to_vec(), values.to_vec())
        } else {
            spectra_as_rgb(fields)?
        };
        let rgb_shape = rgb_shape.as_slice();
        let incident = [phi_i.len(), theta_i.len()];
        if vndf_shape[..2] != incident || rgb_shape[..2] != incident || rgb_shape[2] != 3 {
            return Err(format!(
                "shapes that do not agree: `vndf` {vndf_shape:?} and `rgb` {rgb_shape:?} for {} phi_i and {} theta_i (rgb: 3 channels)",
                phi_i.len(),
                theta_i.len()
            ));
        }
        let angles = vec![phi_i.to_vec(), theta_i.to_vec()];
        fn named(name: &'static str) -> impl Fn(String) -> String {
            move |message| format!("field `{name}`: {message}")
        }
        let grid = |values: &[f32], shape: &[usize], name: &'static str| {
            Grid2D::function(values.to_vec(), shape[1], shape[0], Vec::new()).map_err(named(name))
        };
        let isotropic = phi_i.len() <= 2;
        let span = phi_i[phi_i.len() - 1] - phi_i[0];
        let reduction = if isotropic || span <= 0.0 { 1 } else { (2.0 * PI / span).round() as u32 };
        Ok(Self {
            description,
            ndf: grid(ndf, ndf_shape, "ndf")?,
            sigma: grid(sigma, sigma_shape, "sigma")?,
            vndf: Grid2D::density(vndf.to_vec(), vndf_shape[3], vndf_shape[2], angles.clone())
                .map_err(named("vndf"))?,
            rgb: Grid2D::function(
                rgb,
                rgb_shape[4],
                rgb_shape[3],
                vec![angles[0].clone(), angles[1].clone(), vec![0.0, 1.0, 2.0]],
            )
            .map_err(named("rgb"))?,
            isotropic,
            reduction,
            jacobian,
        })
    }

    /// The material as one array of floats, as `shaders/brdf/rgl.glsl` reads it from a measured table's place:
    /// a header of [`PACKED_HEADER`] floats (the flags, the incident angles' counts and offsets, then each
    /// grid's width, height and offsets: ndf, sigma, vndf, rgb), then the arrays. Counts and offsets are
    /// whole numbers, exact in a float below 2^24.
    pub fn pack(&self) -> Vec<f32> {
        let mut out = vec![0.0; PACKED_HEADER];
        let [phi_i, theta_i] = [&self.vndf.parameters()[0], &self.vndf.parameters()[1]];
        let phi_offset = out.len();
        out.extend_from_slice(phi_i);
        let theta_offset = out.len();
        out.extend_from_slice(theta_i);
        let mut header = vec![
            u32::from(self.isotropic),
            self.reduction,
            u32::from(self.jacobian),
            phi_i.len() as u32,
            theta_i.len() as u32,
            phi_offset as u32,
            theta_offset as u32,
        ];
        for grid in [&self.ndf, &self.sigma, &self.vndf, &self.rgb] {
            header.extend(grid.pack(&mut out));
        }
        for (slot, value) in out.iter_mut().zip(header) {
            *slot = value as f32;
        }
        out
    }

    /// Whether the material depends on the azimuths' difference only (one or two phi_i in the file).
    pub fn isotropic(&self) -> bool {
        self.isotropic
    }

    /// f_r(wi, wo) about n with the tangent t, in the frame X = t, Y = n x t (which an anisotropic file reads).
    pub fn eval_in_frame(&self, n: Vec3, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        let local = |v: Vec3| Vec3::new(v.dot(t), v.dot(n.cross(t)), v.dot(n));
        self.eval_local(local(wi), local(wo))
    }

    /// f_r for the light's direction `light` and the view `view`, in the surface's frame (the normal +z, the
    /// tangent +x); zero below the horizon.
    pub fn eval_local(&self, light: Vec3, view: Vec3) -> Vec3 {
        if light.z <= 0.0 || view.z <= 0.0 {
            return Vec3::ZERO;
        }
        // The file's incident direction is the view (see the module's text).
        let (mut incident, mut outgoing) = (view, light);
        if self.reduction >= 2 {
            let sy = incident.y;
            let sx = if self.reduction == 4 { incident.x } else { sy };
            for d in [&mut incident, &mut outgoing] {
                d.x = against_sign(d.x, sx);
                d.y = against_sign(d.y, sy);
            }
        }
        let m = (incident + outgoing).normalize();
        let (theta_i, phi_i) = (elevation(incident), incident.y.atan2(incident.x));
        let (theta_m, phi_m) = (elevation(m), m.y.atan2(m.x));
        let u_i = Vec2::new(theta_to_unit(theta_i), phi_to_unit(phi_i));
        let relative = if self.isotropic { phi_m - phi_i } else { phi_m };
        let mut u_m = Vec2::new(theta_to_unit(theta_m), phi_to_unit(relative));
        u_m.y -= u_m.y.floor();
        let (sample, _) = self.vndf.invert(u_m, &[phi_i, theta_i]);
        let mut value = Vec3::from_array([0, 1, 2].map(|c| self.rgb.eval(sample, &[phi_i, theta_i, c as f32])));
        if self.jacobian {
            value *= self.ndf.eval(u_m, &[]) / (4.0 * self.sigma.eval(u_i, &[]));
        }
        value / outgoing.z
    }
}

#[cfg(test)]
mod tests;
