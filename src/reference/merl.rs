//! The reference's own reading of a measured material, apart from the GPU path's (`brdf::measured`) on
//! purpose: its own file reader, its own angles (`std_coords_to_half_diff_coords` of the database's reader,
//! BRDFRead.cpp, followed step by step with its `rotate_vector`), all in double precision. Only the
//! interpolation is the same by definition: trilinear between the entries' centres in the reader's index
//! space, measured corners only, per channel.

use std::f64::consts::PI;
use std::path::Path;

use glam::{DVec3, Vec3};

/// BRDFRead.cpp's resolutions and scales.
const RES_THETA_H: usize = 90;
const RES_THETA_D: usize = 90;
const RES_PHI_D: usize = 180;
const SCALES: [f64; 3] = [1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0];

/// A MERL file as the reference holds it: f_r per channel block, in double precision.
pub struct MerlFile {
    blocks: [Vec<f64>; 3],
}

impl MerlFile {
    /// Reads the file.
    ///
    /// # Errors
    /// One line when it is not a MERL file of 90 x 90 x 180 entries (the scene's loading checked it
    /// already, fully; this guards against it changing since).
    pub fn read(path: &Path) -> Result<Self, String> {
        let bytes = std::fs::read(path).map_err(|e| format!("{}: {e}", path.display()))?;
        let n = RES_THETA_H * RES_THETA_D * RES_PHI_D;
        let header: Vec<i32> =
            bytes.chunks_exact(4).take(3).map(|b| i32::from_le_bytes([b[0], b[1], b[2], b[3]])).collect();
        if header != [90, 90, 180] || bytes.len() != 12 + 24 * n {
            return Err(format!("{}: not a MERL file of 90 x 90 x 180 entries", path.display()));
        }
        let block = |c: usize| -> Vec<f64> {
            bytes[12 + 8 * n * c..12 + 8 * n * (c + 1)]
                .chunks_exact(8)
                .map(|b| f64::from_le_bytes([b[0], b[1], b[2], b[3], b[4], b[5], b[6], b[7]]) * SCALES[c])
                .collect()
        };
        Ok(Self { blocks: [block(0), block(1), block(2)] })
    }

    /// f_r(wi, wo) about n.
    pub fn eval(&self, n: Vec3, wi: Vec3, wo: Vec3) -> Vec3 {
        let (n, wi, wo) = (n.as_dvec3(), wi.as_dvec3(), wo.as_dvec3());
        // Spherical coordinates in a frame about n (any tangent: the BRDF is isotropic).
        let t = n.any_orthonormal_vector();
        let b = n.cross(t);
        let spherical = |v: DVec3| (v.dot(n).clamp(-1.0, 1.0).acos(), v.dot(b).atan2(v.dot(t)));
        let ((theta_in, fi_in), (theta_out, fi_out)) = (spherical(wi), spherical(wo));
        let (theta_half, theta_diff, phi_diff) = std_coords_to_half_diff_coords(theta_in, fi_in, theta_out, fi_out);
        self.interpolate(theta_half, theta_diff, phi_diff).as_vec3()
    }

    /// The trilinear interpolation at continuous indices (entry centres at whole numbers).
    fn interpolate(&self, theta_half: f64, theta_diff: f64, phi_diff: f64) -> DVec3 {
        let phi_diff = if phi_diff < 0.0 { phi_diff + PI } else { phi_diff };
        let last = |bins: usize| (bins - 1) as f64;
        let x = ((theta_half.max(0.0) / (PI / 2.0)).sqrt() * RES_THETA_H as f64 - 0.5).clamp(0.0, last(RES_THETA_H));
        let y = (theta_diff / (PI / 2.0) * RES_THETA_D as f64 - 0.5).clamp(0.0, last(RES_THETA_D));
        let z = phi_diff / PI * RES_PHI_D as f64 - 0.5;
        let mut total = [0.0f64; 3];
        let mut weights = [0.0f64; 3];
        for corner in 0..8 {
            let pick = |axis: usize, v: f64| -> (i64, f64) {
                let below = v.floor();
                if corner >> axis & 1 == 0 {
                    (below as i64, 1.0 - (v - below))
                } else {
                    (below as i64 + 1, v - below)
                }
            };
            let ((i, wx), (j, wy), (k, wz)) = (pick(0, x), pick(1, y), pick(2, z));
            let i = i.min(RES_THETA_H as i64 - 1) as usize;
            let j = j.min(RES_THETA_D as i64 - 1) as usize;
            let k = k.rem_euclid(RES_PHI_D as i64) as usize;
            let index = k + j * RES_PHI_D + i * RES_PHI_D * RES_THETA_D;
            for c in 0..3 {
                let value = self.blocks[c][index];
                if value >= 0.0 {
                    total[c] += wx * wy * wz * value;
                    weights[c] += wx * wy * wz;
                }
            }
        }
        DVec3::from_array(std::array::from_fn(|c| if weights[c] > 0.0 { total[c] / weights[c] } else { 0.0 }))
    }
}

/// `rotate_vector` of BRDFRead.cpp: `vector` turned by `angle` about unit `axis` (Rodrigues).
fn rotate_vector(vector: DVec3, axis: DVec3, angle: f64) -> DVec3 {
    let (sin, cos) = angle.sin_cos();
    vector * cos + axis * axis.dot(vector) * (1.0 - cos) + axis.cross(vector) * sin
}

/// `std_coords_to_half_diff_coords` of BRDFRead.cpp: the half vector from the two directions, then the
/// difference vector as wi turned by -phi_half about the normal and by -theta_half about the binormal.
fn std_coords_to_half_diff_coords(theta_in: f64, fi_in: f64, theta_out: f64, fi_out: f64) -> (f64, f64, f64) {
    let direction = |theta: f64, fi: f64| DVec3::new(theta.sin() * fi.cos(), theta.sin() * fi.sin(), theta.cos());
    let (wi, wo) = (direction(theta_in, fi_in), direction(theta_out, fi_out));
    let half = ((wi + wo) / 2.0).normalize();
    let theta_half = half.z.clamp(-1.0, 1.0).acos();
    let fi_half = half.y.atan2(half.x);
    let (normal, binormal) = (DVec3::Z, DVec3::Y);
    let temp = rotate_vector(wi, normal, -fi_half);
    let diff = rotate_vector(temp, binormal, -theta_half);
    (theta_half, diff.z.clamp(-1.0, 1.0).acos(), diff.y.atan2(diff.x))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::brdf::measured::tests::{at, table_of};

    /// The hand-worked values of the GPU path's tests (brdf/measured.rs), by the reference's own reading.
    #[test]
    fn the_reference_reads_the_conventions_the_same_way() {
        let dir = tempfile::tempdir().unwrap();
        let read = |red: &dyn Fn(usize, usize, usize) -> f32, name: &str| {
            let path = dir.path().join(name);
            std::fs::write(&path, table_of(red).to_bytes()).unwrap();
            MerlFile::read(&path).unwrap()
        };
        let red = |file: &MerlFile, (wi, wo): (Vec3, Vec3)| file.eval(Vec3::Z, wi, wo).x;
        let theta_h = read(&|h, _, _| h as f32, "h.binary");
        assert!((red(&theta_h, at(20.0, 0.0, 0.0)) - 41.926).abs() < 1e-3);
        let theta_d = read(&|_, d, _| d as f32, "d.binary");
        assert!((red(&theta_d, at(0.0, 30.0, 0.0)) - 29.5).abs() < 1e-3);
        let phi_d = read(&|_, _, p| p as f32, "p.binary");
        assert!((red(&phi_d, at(30.0, 40.0, -60.0)) - 119.5).abs() < 1e-2);
        assert!((red(&phi_d, at(30.0, 40.0, 60.0)) - 59.5).abs() < 1e-2);
        assert!((red(&phi_d, at(30.0, 40.0, 180.0)) - 89.5).abs() < 1e-2);
        let sparse = read(&|_, d, _| if d % 2 == 0 { 2.0 } else { -1.0 }, "s.binary");
        assert!((red(&sparse, at(0.0, 10.8, 0.0)) - 2.0).abs() < 1e-5);
    }
}
