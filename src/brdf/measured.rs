//! Measured materials: a MERL BRDF file (Matusik, Pfister, Brand and McMillan 2003, "A Data-Driven
//! Reflectance Model"), read into a table and looked up as `shaders/brdf/measured.glsl` looks it up.
//!
//! The file's conventions are those of the database's own reader, `BRDFRead.cpp` (distributed with the
//! database; cited below where each is used): three int32 dimensions (90 theta_h, 90 theta_d, 180 phi_d),
//! then three blocks of 1,458,000 doubles, red, green and blue, each scaled by its own constant. A negative
//! entry was not measured.
//!
//! The lookup interpolates trilinearly between the entries' centres in the reader's index space (where
//! theta_h's index is non-linear), weighing each channel's measured corners only. `BRDFRead.cpp` takes the
//! nearest entry instead; a table read that way changes by a whole entry's step where a bin ends, which a
//! render shows as contours (measured on the tests' Cook-Torrance copy, a sphere of 240 x 160: mean 0.17,
//! p99 6 levels from the model with the nearest entry; 0.017 and 1 interpolated).

use std::collections::BTreeMap;
use std::f32::consts::{FRAC_PI_2, PI};
use std::fmt;
use std::path::{Path, PathBuf};
use std::sync::{Arc, Mutex, OnceLock, Weak};
use std::time::SystemTime;

use glam::Vec3;

use super::rgl::RglTable;

/// `BRDF_SAMPLING_RES_THETA_H`, `BRDF_SAMPLING_RES_THETA_D` and `BRDF_SAMPLING_RES_PHI_D / 2` of
/// `BRDFRead.cpp`: the table's dimensions, in the file's header order.
pub const THETA_H_BINS: usize = 90;
/// `BRDF_SAMPLING_RES_THETA_D`: bins of the difference angle theta_d over 0 to 90 degrees.
pub const THETA_D_BINS: usize = 90;
/// `BRDF_SAMPLING_RES_PHI_D / 2`: bins of phi_d over 0 to 180 degrees (reciprocity gives the other half).
pub const PHI_D_BINS: usize = 180;
/// Entries per channel.
pub const ENTRIES: usize = THETA_H_BINS * THETA_D_BINS * PHI_D_BINS;
/// The size of a MERL file: the header and three blocks of doubles.
pub const FILE_BYTES: u64 = 12 + 3 * 8 * ENTRIES as u64;
/// `RED_SCALE`, `GREEN_SCALE` and `BLUE_SCALE` of `BRDFRead.cpp`: a stored value times its channel's scale
/// is f_r.
pub const CHANNEL_SCALE: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];

/// A MERL table in memory.
#[derive(Clone)]
pub struct MeasuredTable {
    /// The file it was read from (or is to be written to).
    pub path: PathBuf,
    /// f_r of every entry, red, green and blue interleaved, in the file's order ([`entry_index`]); a
    /// negative value was not measured.
    pub rgb: Vec<f32>,
    /// Its sampler ([`super::measured_sampler`]), made when first asked for.
    sampler: OnceLock<Vec<f32>>,
    /// An anisotropic RGL material, evaluated as its file defines it: `rgb` then holds it packed
    /// ([`RglTable::pack`]) for the GPU, not entries.
    anisotropic: Option<Arc<RglTable>>,
}

impl PartialEq for MeasuredTable {
    fn eq(&self, other: &Self) -> bool {
        self.path == other.path && self.rgb == other.rgb
    }
}

/// A measured material: a shared table. Every object and scene that names the same unchanged file shares
/// one table ([`Measured::load`]); two are equal when they name the same file and both draw from its
/// sampler or neither does.
#[derive(Clone)]
pub struct Measured {
    table: Arc<MeasuredTable>,
    sampled: bool,
}

impl PartialEq for Measured {
    fn eq(&self, other: &Self) -> bool {
        (Arc::ptr_eq(&self.table, &other.table) || self.table.path == other.table.path)
            && self.sampled() == other.sampled()
    }
}

impl fmt::Debug for Measured {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "Measured({:?}{})", self.table.path, if self.sampled() { "" } else { ", no sampler" })
    }
}

/// The index of entry (theta_h, theta_d, phi_d) in each channel's block: `phi_diff_index + theta_diff_index *
/// 180 + theta_half_index * 180 * 90` (`lookup_brdf_val` in `BRDFRead.cpp`).
pub fn entry_index(theta_h: usize, theta_d: usize, phi_d: usize) -> usize {
    phi_d + PHI_D_BINS * (theta_d + THETA_D_BINS * theta_h)
}

/// The angles (theta_h, theta_d, phi_d) of Rusinkiewicz's half and difference vectors (1998, "A new change
/// of variables for efficient BRDF representation") for unit wi, wo about n, as `std_coords_to_half_diff_coords`
/// of `BRDFRead.cpp` computes them: wi in the frame where h lies in the xz-plane (phi_h = 0), turned by
/// -theta_h about y. phi_d is in (-pi, pi]. Mirrors `half_diff_angles` in `shaders/brdf/measured.glsl`.
pub fn half_diff_angles(n: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
    let h = (wi + wo).normalize();
    let n_o_h = n.dot(h).clamp(-1.0, 1.0);
    // The tangent toward h; when h is n (theta_h = 0, where phi_h is undefined and the reader takes 0) any
    // tangent is one: the one from the least of n's components.
    let toward_h = h - n * n_o_h;
    let t = if toward_h.length_squared() > 1e-12 { toward_h.normalize() } else { any_tangent(n) };
    let b = n.cross(t);
    let sin_theta_h = n.cross(h).length();
    // wi turned by -theta_h about b: x' = cos(theta_h) t - sin(theta_h) n, y' = b, z' = h.
    let x = wi.dot(t * n_o_h - n * sin_theta_h);
    let y = wi.dot(b);
    let theta_h = sin_theta_h.atan2(n_o_h);
    let theta_d = wi.dot(h).clamp(-1.0, 1.0).acos();
    Vec3::new(theta_h, theta_d, y.atan2(x))
}

/// A unit vector perpendicular to unit n. Mirrors `any_tangent` in `shaders/brdf/measured.glsl`.
pub fn any_tangent(n: Vec3) -> Vec3 {
    let axis = if n.x.abs() < 0.5 { Vec3::X } else { Vec3::Y };
    (axis - n * n.dot(axis)).normalize()
}

/// The table's continuous coordinates of (theta_h, theta_d, phi_d), each in units of its bins with entry k's
/// centre at k: theta_h's index is `sqrt(theta_h / 90 degrees) * 90` (`theta_half_index`), theta_d's
/// `theta_d / 90 degrees * 90` and phi_d's `phi_d / 180 degrees * 180`, phi_d first folded to [0, 180)
/// degrees by reciprocity (`phi_diff_index`: phi_d + 180 degrees when negative). Mirrors
/// `measured_coordinates` in `shaders/brdf/measured.glsl`.
pub fn measured_coordinates(angles: Vec3) -> Vec3 {
    let phi_d = if angles.z < 0.0 { angles.z + PI } else { angles.z };
    Vec3::new(
        (angles.x.max(0.0) / FRAC_PI_2).sqrt() * THETA_H_BINS as f32 - 0.5,
        angles.y / FRAC_PI_2 * THETA_D_BINS as f32 - 0.5,
        phi_d / PI * PHI_D_BINS as f32 - 0.5,
    )
}

/// The directions (wi, wo) about n = +z at the centre of every entry, in the order of [`entry_index`].
pub fn entry_directions() -> Vec<(Vec3, Vec3)> {
    let mut directions = vec![(Vec3::ZERO, Vec3::ZERO); ENTRIES];
    for theta_h in 0..THETA_H_BINS {
        for theta_d in 0..THETA_D_BINS {
            for phi_d in 0..PHI_D_BINS {
                directions[entry_index(theta_h, theta_d, phi_d)] = directions_at(entry_angles(theta_h, theta_d, phi_d));
            }
        }
    }
    directions
}

/// The angles at entry (theta_h, theta_d, phi_d)'s centre: the inverse of [`measured_coordinates`].
pub fn entry_angles(theta_h: usize, theta_d: usize, phi_d: usize) -> Vec3 {
    let u = (theta_h as f32 + 0.5) / THETA_H_BINS as f32;
    Vec3::new(
        u * u * FRAC_PI_2,
        (theta_d as f32 + 0.5) / THETA_D_BINS as f32 * FRAC_PI_2,
        (phi_d as f32 + 0.5) / PHI_D_BINS as f32 * PI,
    )
}

/// Unit wi and wo about n = +z at the given half and difference angles, h in the xz-plane
/// (`half_diff_coords_to_std_coords` of `BRDFRead.cpp` with phi_h = 0).
pub fn directions_at(angles: Vec3) -> (Vec3, Vec3) {
    let (theta_h, theta_d, phi_d) = (angles.x, angles.y, angles.z);
    let d = Vec3::new(theta_d.sin() * phi_d.cos(), theta_d.sin() * phi_d.sin(), theta_d.cos());
    // d turned by theta_h about y.
    let (s, c) = theta_h.sin_cos();
    let wi = Vec3::new(c * d.x + s * d.z, d.y, -s * d.x + c * d.z).normalize();
    let h = Vec3::new(s, 0.0, c);
    let wo = (2.0 * wi.dot(h) * h - wi).normalize();
    (wi, wo)
}

impl MeasuredTable {
    /// The table of `rgb` (f_r of every entry, as [`MeasuredTable::rgb`]) for `path`.
    pub fn new(path: PathBuf, rgb: Vec<f32>) -> Self {
        Self { path, rgb, sampler: OnceLock::new(), anisotropic: None }
    }

    /// The floats of the table's own sampler ([`super::measured_sampler::sampler`]), made once; zeros for an
    /// anisotropic RGL material, which has none (its place in the GPU's buffer has the sampler's floats all
    /// the same).
    pub fn sampler(&self) -> &[f32] {
        self.sampler.get_or_init(|| match self.anisotropic {
            Some(_) => vec![0.0; super::measured_sampler::SAMPLER_FLOATS],
            None => super::measured_sampler::sampler(|wi, wo| self.eval(Vec3::Z, wi, wo)),
        })
    }

    /// The anisotropic RGL material the table stands for, if it does.
    pub fn anisotropic(&self) -> Option<&RglTable> {
        self.anisotropic.as_deref()
    }

    /// f_r(wi, wo) about n with the tangent t (the frame X = t, Y = n x t, which only an anisotropic RGL
    /// material reads). Mirrors `measured` in `shaders/brdf/measured.glsl`.
    pub fn eval_in_frame(&self, n: Vec3, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        match &self.anisotropic {
            Some(material) => material.eval_in_frame(n, t, wi, wo),
            None => self.eval(n, wi, wo),
        }
    }

    /// The value a fit takes for entry (theta_h, theta_d, phi_d) turned to the directions wi and wo about
    /// +z: the entry itself, or an anisotropic RGL material's f_r at the directions (tangent +x).
    pub fn measurement(&self, index: usize, wi: Vec3, wo: Vec3) -> Vec3 {
        match &self.anisotropic {
            Some(material) => material.eval_local(wi, wo),
            None => self.entry(index),
        }
    }

    /// f_r at the continuous coordinates `c` ([`measured_coordinates`]): trilinear between the eight entries
    /// around them, theta_h and theta_d held at their first and last entries' centres, phi_d wrapping
    /// round (180 degrees is 0 again); per channel, the measured corners only, their weights renormalised,
    /// and 0 where none is. Mirrors `measured_lookup` in `shaders/brdf/measured.glsl`.
    pub fn lookup(&self, c: Vec3) -> Vec3 {
        let th = c.x.clamp(0.0, (THETA_H_BINS - 1) as f32);
        let td = c.y.clamp(0.0, (THETA_D_BINS - 1) as f32);
        let (h0, d0, p0) = (th.floor(), td.floor(), c.z.floor());
        let (fh, fd, fp) = (th - h0, td - d0, c.z - p0);
        let h = [h0 as usize, (h0 as usize + 1).min(THETA_H_BINS - 1)];
        let d = [d0 as usize, (d0 as usize + 1).min(THETA_D_BINS - 1)];
        let p0 = (p0 as i32).rem_euclid(PHI_D_BINS as i32) as usize;
        let p = [p0, (p0 + 1) % PHI_D_BINS];
        let (mut sum, mut weight) = (Vec3::ZERO, Vec3::ZERO);
        for (i, wh) in [1.0 - fh, fh].into_iter().enumerate() {
            for (j, wd) in [1.0 - fd, fd].into_iter().enumerate() {
                for (k, wp) in [1.0 - fp, fp].into_iter().enumerate() {
                    let v = self.entry(entry_index(h[i], d[j], p[k]));
                    let measured = Vec3::select(v.cmpge(Vec3::ZERO), Vec3::ONE, Vec3::ZERO);
                    let w = wh * wd * wp;
                    sum += w * measured * v;
                    weight += w * measured;
                }
            }
        }
        Vec3::select(weight.cmpgt(Vec3::ZERO), sum / weight, Vec3::ZERO)
    }

    /// Entry `index`'s f_r, red, green and blue.
    pub fn entry(&self, index: usize) -> Vec3 {
        Vec3::from_slice(&self.rgb[3 * index..3 * index + 3])
    }

    /// f_r(wi, wo) about n, both above the horizon, of a MERL table (isotropic). Mirrors `measured_lookup` in
    /// `shaders/brdf/measured.glsl`.
    pub fn eval(&self, n: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        self.lookup(measured_coordinates(half_diff_angles(n, wi, wo)))
    }

    /// A table of `f` at every entry's centre (wi and wo about +z from [`directions_at`]), to be written
    /// to `path`: an analytic model as if measured.
    pub fn tabulate(path: PathBuf, f: impl Fn(Vec3, Vec3) -> Vec3) -> Self {
        let values: Vec<Vec3> = entry_directions().into_iter().map(|(wi, wo)| f(wi, wo)).collect();
        Self::from_entries(path, &values)
    }

    /// The table whose entry of index i ([`entry_index`]) is `values[i]` (f_r at [`entry_directions`]`[i]`).
    pub fn from_entries(path: PathBuf, values: &[Vec3]) -> Self {
        Self::new(path, values.iter().flat_map(|v| v.to_array()).collect())
    }

    /// The table as a MERL file's bytes, every value divided by its channel's scale.
    pub fn to_bytes(&self) -> Vec<u8> {
        let mut bytes = Vec::with_capacity(FILE_BYTES as usize);
        for dimension in [THETA_H_BINS, THETA_D_BINS, PHI_D_BINS] {
            bytes.extend_from_slice(&(dimension as i32).to_le_bytes());
        }
        for (channel, scale) in CHANNEL_SCALE.iter().enumerate() {
            for index in 0..ENTRIES {
                bytes.extend_from_slice(&(f64::from(self.rgb[3 * index + channel]) / scale).to_le_bytes());
            }
        }
        bytes
    }

    /// Reads and checks a MERL file, or an RGL `.bsdf` file (told by its first bytes, `tensor_file`: see
    /// [`MeasuredTable::from_rgl`]); the error is one line naming the file and saying what is wrong with it.
    ///
    /// # Errors
    /// The file is missing, not a regular file, of the wrong size or dimensions, holds a NaN or an infinity,
    /// or measures nothing; for an RGL file, what [`super::rgl`] finds wrong, or an anisotropic material too
    /// large for a table's place.
    pub fn read(path: &Path) -> Result<Self, String> {
        if super::rgl::is_rgl_file(path) {
            return Self::from_rgl(path);
        }
        let bytes = crate::files::read_regular(path, "MERL file", FILE_BYTES)?;
        let shown = path.display();
        if bytes.len() < 12 {
            return Err(format!("the MERL file {shown} is {} bytes, too short for its header", bytes.len()));
        }
        let dimension =
            |k: usize| i32::from_le_bytes([bytes[4 * k], bytes[4 * k + 1], bytes[4 * k + 2], bytes[4 * k + 3]]);
        let dimensions = [dimension(0), dimension(1), dimension(2)];
        if dimensions != [THETA_H_BINS as i32, THETA_D_BINS as i32, PHI_D_BINS as i32] {
            return Err(format!(
                "the MERL file {shown} says it has {} x {} x {} entries; a MERL file has {THETA_H_BINS} x {THETA_D_BINS} x {PHI_D_BINS} \
                 (theta_h, theta_d, phi_d)",
                dimensions[0], dimensions[1], dimensions[2]
            ));
        }
        if bytes.len() as u64 != FILE_BYTES {
            return Err(format!(
                "the MERL file {shown} is {} bytes; a MERL file of {THETA_H_BINS} x {THETA_D_BINS} x {PHI_D_BINS} entries is {FILE_BYTES} \
                 bytes{}",
                bytes.len(),
                if (bytes.len() as u64) < FILE_BYTES { " (truncated?)" } else { "" }
            ));
        }
        let mut rgb = vec![0.0f32; 3 * ENTRIES];
        let mut measured = false;
        for (channel, (block, scale)) in bytes[12..].chunks_exact(8 * ENTRIES).zip(CHANNEL_SCALE).enumerate() {
            for (index, value) in block.chunks_exact(8).enumerate() {
                let value = f64::from_le_bytes(value.try_into().unwrap_or_default());
                if !value.is_finite() {
                    let (theta_h, rest) = (index / (THETA_D_BINS * PHI_D_BINS), index % (THETA_D_BINS * PHI_D_BINS));
                    return Err(format!(
                        "the MERL file {shown}: entry {index} of the {} block (theta_h bin {theta_h}, theta_d bin {}, phi_d bin {}) is {value}",
                        ["red", "green", "blue"][channel],
                        rest / PHI_D_BINS,
                        rest % PHI_D_BINS
                    ));
                }
                measured |= value >= 0.0;
                rgb[3 * index + channel] = (value * scale) as f32;
            }
        }
        if !measured {
            return Err(format!("the MERL file {shown} measures nothing: every value is negative"));
        }
        Ok(Self::new(path.to_path_buf(), rgb))
    }
}

impl MeasuredTable {
    /// An RGL material as a table. An isotropic one is resampled: the reader's f_r
    /// ([`super::rgl::RglTable`]) at the centre of every entry, as [`MeasuredTable::tabulate`] tabulates a
    /// model, so that every command that takes a measured table takes it, its sampler included. An anisotropic
    /// one (the table's half and difference angles have no azimuth of the half vector) is kept as the file
    /// defines it, and packed for the GPU into the place of a table's entries; it has no sampler.
    ///
    /// # Errors
    /// What [`super::rgl::RglTable::read`] finds wrong, in one line naming the file; an anisotropic material
    /// larger than a table's place.
    pub fn from_rgl(path: &Path) -> Result<Self, String> {
        let material = super::rgl::RglTable::read(path)?;
        if material.isotropic() {
            return Ok(Self::tabulate(path.to_path_buf(), |wi, wo| material.eval_local(wi, wo)));
        }
        let mut packed = material.pack();
        if packed.len() > 3 * ENTRIES {
            return Err(format!(
                "the RGL file {} is anisotropic and holds {} floats, more than the {} of a measured table's place \
                 on the GPU",
                path.display(),
                packed.len(),
                3 * ENTRIES
            ));
        }
        packed.resize(3 * ENTRIES, 0.0);
        Ok(Self { anisotropic: Some(Arc::new(material)), ..Self::new(path.to_path_buf(), packed) })
    }
}

/// The tables read so far, by file, with the size and time of the file they were read from: a table is
/// read once while anything holds it.
type TableCache = BTreeMap<PathBuf, (u64, Option<SystemTime>, Weak<MeasuredTable>)>;
static TABLES: Mutex<TableCache> = Mutex::new(BTreeMap::new());

impl Measured {
    /// The table of the MERL file at `path`, read and checked ([`MeasuredTable::read`]) unless a table of
    /// the same unchanged file is still held.
    ///
    /// # Errors
    /// What [`MeasuredTable::read`] finds wrong, as one line.
    pub fn load(path: &Path) -> Result<Self, String> {
        let key = std::fs::canonicalize(path).unwrap_or_else(|_| path.to_path_buf());
        let stamp = std::fs::metadata(&key).ok().map(|m| (m.len(), m.modified().ok()));
        let mut tables = TABLES.lock().unwrap_or_else(std::sync::PoisonError::into_inner);
        if let (Some((len, modified)), Some((held_len, held_modified, table))) = (stamp, tables.get(&key)) {
            if (len, modified) == (*held_len, *held_modified) {
                if let Some(table) = table.upgrade() {
                    return Ok(Self::sharing(table));
                }
            }
        }
        let table = Arc::new(MeasuredTable::read(path)?);
        tables.retain(|_, (_, _, held)| held.strong_count() > 0);
        if let Some((len, modified)) = stamp {
            tables.insert(key, (len, modified, Arc::downgrade(&table)));
        }
        Ok(Self::sharing(table))
    }

    fn sharing(table: Arc<MeasuredTable>) -> Self {
        Self { table, sampled: true }
    }

    /// A material of a table in memory.
    pub fn from_table(table: MeasuredTable) -> Self {
        Self::sharing(Arc::new(table))
    }

    /// The same table, the exact mode drawing from its sampler ([`super::measured_sampler`]) or not (the
    /// scene's `sampler = false`: the cosine and the environment alone, as before tables had samplers). An
    /// anisotropic RGL material has no sampler: never drawn from.
    #[must_use]
    pub fn with_sampler(self, sampled: bool) -> Self {
        Self { sampled, ..self }
    }

    /// Whether the exact mode draws from the table's sampler: as the scene asks, and never for an anisotropic
    /// RGL material.
    pub fn sampled(&self) -> bool {
        self.sampled && self.table.anisotropic.is_none()
    }

    /// The table.
    pub fn table(&self) -> &MeasuredTable {
        &self.table
    }

    /// The file it was read from.
    pub fn path(&self) -> &Path {
        &self.table.path
    }

    /// Whether `self` and `other` are the same table in memory (not only the same file).
    pub fn same_table(&self, other: &Measured) -> bool {
        Arc::ptr_eq(&self.table, &other.table)
    }

    /// f_r(wi, wo) about n with the tangent t ([`MeasuredTable::eval_in_frame`]).
    pub fn eval(&self, n: Vec3, t: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        self.table.eval_in_frame(n, t, wi, wo)
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// Unit wi and wo about +z with the half vector at theta_h in the xz-plane and the difference vector at
    /// (theta_d, phi_d) about it, built by hand in h's frame (x' = (cos theta_h, 0, -sin theta_h), y' = y).
    pub(crate) fn at(theta_h: f32, theta_d: f32, phi_d: f32) -> (Vec3, Vec3) {
        let (h_angle, d_angle, phi) = (theta_h.to_radians(), theta_d.to_radians(), phi_d.to_radians());
        let h = Vec3::new(h_angle.sin(), 0.0, h_angle.cos());
        let x = Vec3::new(h_angle.cos(), 0.0, -h_angle.sin());
        let wi = d_angle.sin() * phi.cos() * x + d_angle.sin() * phi.sin() * Vec3::Y + d_angle.cos() * h;
        (wi, 2.0 * wi.dot(h) * h - wi)
    }

    /// A table whose red channel is `red(theta_h bin, theta_d bin, phi_d bin)`, green and blue 0.5.
    pub(crate) fn table_of(red: impl Fn(usize, usize, usize) -> f32) -> MeasuredTable {
        let mut rgb = vec![0.5; 3 * ENTRIES];
        for h in 0..THETA_H_BINS {
            for d in 0..THETA_D_BINS {
                for p in 0..PHI_D_BINS {
                    rgb[3 * entry_index(h, d, p)] = red(h, d, p);
                }
            }
        }
        MeasuredTable::new("by-hand".into(), rgb)
    }

    fn red(table: &MeasuredTable, (wi, wo): (Vec3, Vec3)) -> f32 {
        table.eval(Vec3::Z, wi, wo).x
    }

    #[test]
    fn the_angles_of_directions_built_by_hand() {
        for (theta_h, theta_d, phi_d) in [(20.0, 0.0, 0.0), (0.0, 30.0, 0.0), (30.0, 40.0, -60.0), (50.0, 70.0, 150.0)]
        {
            let (wi, wo) = at(theta_h, theta_d, phi_d);
            let angles = half_diff_angles(Vec3::Z, wi, wo) * 180.0 / PI;
            assert!((angles.x - theta_h).abs() < 1e-3 && (angles.y - theta_d).abs() < 1e-3, "{angles}");
            if theta_h > 0.0 && theta_d > 0.0 {
                assert!((angles.z - phi_d).abs() < 1e-3, "{angles}");
            }
            let (wi2, wo2) = directions_at(angles * PI / 180.0);
            assert!((wi2 - wi).length() < 1e-5 && (wo2 - wo).length() < 1e-5, "{wi} {wi2} {wo} {wo2}");
        }
    }

    #[test]
    fn theta_h_is_indexed_by_its_square_root() {
        // Red = the theta_h bin: at theta_h = 20 degrees the coordinate is sqrt(20 / 90) * 90 - 0.5 = 41.926
        // (linear indexing would give 19.5).
        let table = table_of(|h, _, _| h as f32);
        assert!((red(&table, at(20.0, 0.0, 0.0)) - 41.926).abs() < 1e-3);
        // Held at the first and last entries' centres.
        assert!(red(&table, at(0.0, 10.0, 0.0)).abs() < 1e-6);
        assert!((red(&table, at(89.9, 0.0, 0.0)) - 89.0).abs() < 1e-6);
    }

    #[test]
    fn theta_d_is_indexed_linearly() {
        // theta_h = 0 (wo the mirror of wi), theta_d = 30: 30 - 0.5 = 29.5.
        let table = table_of(|_, d, _| d as f32);
        assert!((red(&table, at(0.0, 30.0, 0.0)) - 29.5).abs() < 1e-3);
    }

    #[test]
    fn phi_d_is_folded_by_reciprocity_and_wraps_round() {
        let table = table_of(|_, _, p| p as f32);
        // phi_d = -60 degrees is read at 120: 119.5 (unfolded, or folded by its absolute value, 59.5).
        assert!((red(&table, at(30.0, 40.0, -60.0)) - 119.5).abs() < 1e-2);
        assert!((red(&table, at(30.0, 40.0, 60.0)) - 59.5).abs() < 1e-2);
        // Swapping wi and wo turns phi_d by 180 degrees: the same entry.
        let (wi, wo) = at(30.0, 40.0, 60.0);
        assert!((red(&table, (wo, wi)) - 59.5).abs() < 1e-2);
        // Between the last entry (179.5 degrees) and the first (0.5 = 180.5): halfway, (179 + 0) / 2.
        assert!((red(&table, at(30.0, 40.0, 180.0)) - 89.5).abs() < 1e-2);
    }

    #[test]
    fn unmeasured_corners_are_left_out() {
        // Every other theta_d bin unmeasured: between bins 10 (measured, 2) and 11 (not), the value is 2.
        let table = table_of(|_, d, _| if d % 2 == 0 { 2.0 } else { -1.0 });
        let value = table.eval(Vec3::Z, at(0.0, 10.8, 0.0).0, at(0.0, 10.8, 0.0).1);
        assert!((value.x - 2.0).abs() < 1e-6 && (value.y - 0.5).abs() < 1e-6, "{value}");
        let nothing = table_of(|_, _, _| -1.0);
        assert_eq!(nothing.eval(Vec3::Z, at(20.0, 20.0, 20.0).0, at(20.0, 20.0, 20.0).1).x, 0.0);
    }

    #[test]
    fn a_table_survives_its_file() {
        let dir = tempfile::tempdir().unwrap();
        let mut table = table_of(|h, d, p| (h + d + p) as f32 / 360.0);
        table.path = dir.path().join("t.binary");
        let bytes = table.to_bytes();
        assert_eq!(bytes.len() as u64, FILE_BYTES);
        std::fs::write(&table.path, &bytes).unwrap();
        let read = MeasuredTable::read(&table.path).unwrap();
        // The scales' round trip through double precision.
        assert!(read.rgb.iter().zip(&table.rgb).all(|(a, b)| (a - b).abs() <= 1e-6 * b.abs()));
        // Held once while anything holds it.
        let (a, b) = (Measured::load(&table.path).unwrap(), Measured::load(&table.path).unwrap());
        assert!(a.same_table(&b));
    }
}
