//! Directional albedo, rho(theta_o) = integral over the hemisphere of f_r(wi, wo) cos(theta_i) dwi, by
//! adaptive Gauss-Kronrod cubature: deterministic, and with a bound on its error rather than a noisy
//! estimate. This crate holds the decisions (which cells, which to cut, when to stop, the sums) and needs no
//! device: the renderer's albedo probe (`shaders/brdf_albedo.comp`) integrates its cells in vk-render, the
//! browser's (`shaders/web/albedo.frag`, the same cell integral) in the explore page, which runs this crate
//! as WebAssembly (`crates/web/`), so that both state the same albedo within the same bound.
//!
//! The hemisphere of wi is cut into cells in (theta_i, phi_i). On each the probe returns the 15-point
//! Kronrod estimate and the 7-point Gauss estimate embedded in it; their difference bounds the error of the
//! Gauss one, and so (far more than) the Kronrod one's, which is what is summed. While an albedo's bounds add
//! up to more than the tolerance, its cells of largest bound are cut in four and integrated again (global
//! adaptive cubature, as QUADPACK's QAG in two dimensions), up to [`MAX_REFINEMENTS`] rounds; the bound
//! stated is the sum over the cells kept, so it holds whichever way the loop ended. The first cells have
//! edges where the models have kinks: theta_i = theta_o (Oren-Nayar's max and min of the angles) and
//! phi_i = 90 degrees (its max(0, cos(phi_i - phi_o))).
//!
//! Every model here is symmetric about the plane of incidence, so phi_i runs over [0, pi] and counts twice.

use std::f64::consts::{FRAC_PI_2, PI};

/// The error bound asked of each albedo: 1e-5, two orders below an 8-bit level.
pub const ALBEDO_TOLERANCE: f64 = 1e-5;

/// How many rounds of cutting cells in four an albedo may take: at most 6 degrees / 2^16 on a side.
pub const MAX_REFINEMENTS: u32 = 16;

/// The most cells one albedo is cut into: past it, the bound reached is the one stated.
pub const MAX_CELLS_PER_ANGLE: usize = 100_000;

/// The widest first cell, in radians (6 degrees).
const FIRST_CELL: f64 = 6.0 * PI / 180.0;

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

/// A cell of the (theta_i, phi_i) rectangle of one job (one outgoing angle), in radians.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cell {
    /// The index of its outgoing angle in those the cubature was started with.
    pub job: usize,
    /// theta_i's bounds, from the normal.
    pub theta: (f64, f64),
    /// phi_i's bounds, from the tangent (wo has phi 0).
    pub phi: (f64, f64),
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

/// The 15 Kronrod nodes on [-1, 1], their weights, and the weights of the 7-point Gauss rule on the same nodes
/// (zero where a Kronrod node is not a Gauss node): those of `shaders/common/albedo_cell.glsl`.
const NODES: [f64; 15] = [
    -0.991_455_371_120_812_6,
    -0.949_107_912_342_758_5,
    -0.864_864_423_359_769_1,
    -0.741_531_185_599_394_5,
    -0.586_087_235_467_691_1,
    -0.405_845_151_377_397_2,
    -0.207_784_955_007_898_48,
    0.0,
    0.207_784_955_007_898_48,
    0.405_845_151_377_397_2,
    0.586_087_235_467_691_1,
    0.741_531_185_599_394_5,
    0.864_864_423_359_769_1,
    0.949_107_912_342_758_5,
    0.991_455_371_120_812_6,
];
const KRONROD: [f64; 15] = [
    0.022935322010529225,
    0.063_092_092_629_978_56,
    0.104_790_010_322_250_19,
    0.140_653_259_715_525_92,
    0.169_004_726_639_267_9,
    0.190_350_578_064_785_42,
    0.204_432_940_075_298_89,
    0.209_482_141_084_727_82,
    0.204_432_940_075_298_89,
    0.190_350_578_064_785_42,
    0.169_004_726_639_267_9,
    0.140_653_259_715_525_92,
    0.104_790_010_322_250_19,
    0.063_092_092_629_978_56,
    0.022935322010529225,
];
const GAUSS: [f64; 15] = [
    0.0,
    0.129_484_966_168_869_7,
    0.0,
    0.279_705_391_489_276_64,
    0.0,
    0.381_830_050_505_118_9,
    0.0,
    0.417_959_183_673_469_4,
    0.0,
    0.381_830_050_505_118_9,
    0.0,
    0.279_705_391_489_276_64,
    0.0,
    0.129_484_966_168_869_7,
    0.0,
];

// A cell's rule from the model's values at its nodes, for a probe that evaluates the model at points rather
// than over cells (a .brdf file in double precision), the sums made here.
impl Cell {
    /// The 225 directions wi (x, y, z) of the cell's 15 x 15-point rule, theta_i's slowest, in the frame of
    /// `shaders/common/albedo_cell.glsl` (n = +z, wo in the xz-plane).
    pub fn nodes(&self) -> Vec<[f64; 3]> {
        let (theta_mid, theta_half) = (0.5 * (self.theta.0 + self.theta.1), 0.5 * (self.theta.1 - self.theta.0));
        let (phi_mid, phi_half) = (0.5 * (self.phi.0 + self.phi.1), 0.5 * (self.phi.1 - self.phi.0));
        NODES
            .iter()
            .flat_map(|a| {
                let (sin_theta, cos_theta) = (theta_mid + theta_half * a).sin_cos();
                NODES.iter().map(move |b| {
                    let (sin_phi, cos_phi) = (phi_mid + phi_half * b).sin_cos();
                    [sin_theta * cos_phi, sin_theta * sin_phi, cos_theta]
                })
            })
            .collect()
    }

    /// The cell's two estimates from f_r cos(theta_i) at each of [`Cell::nodes`], in double precision
    /// (returned as a probe's, in single).
    pub fn estimate(&self, f_cos: &[[f64; 3]]) -> CellEstimate {
        let (theta_mid, theta_half) = (0.5 * (self.theta.0 + self.theta.1), 0.5 * (self.theta.1 - self.theta.0));
        let phi_half = 0.5 * (self.phi.1 - self.phi.0);
        let mut kronrod = [0.0; 3];
        let mut gauss = [0.0; 3];
        for (a, ring) in f_cos.chunks_exact(15).enumerate() {
            // The solid angle's sin(theta).
            let sin_theta = (theta_mid + theta_half * NODES[a]).sin();
            for (b, f) in ring.iter().enumerate() {
                for c in 0..3 {
                    kronrod[c] += KRONROD[a] * KRONROD[b] * sin_theta * f[c];
                    gauss[c] += GAUSS[a] * GAUSS[b] * sin_theta * f[c];
                }
            }
        }
        let scale = theta_half * phi_half;
        CellEstimate { kronrod: kronrod.map(|v| (scale * v) as f32), gauss: gauss.map(|v| (scale * v) as f32) }
    }
}

/// What a probe returns for a cell (f_r cos(theta_i) over its half of the hemisphere, in the probe's single
/// precision): the 15-point Gauss-Kronrod estimate and the embedded 7-point Gauss one, RGB.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellEstimate {
    /// The 15 x 15-point Kronrod estimate.
    pub kronrod: [f32; 3],
    /// The 7 x 7-point Gauss estimate.
    pub gauss: [f32; 3],
}

/// The directional albedos at some outgoing angles, as they are refined: [`Cubature::pending`] cells are
/// integrated by a probe and given back with [`Cubature::take`] until none is pending; then
/// [`Cubature::albedos`].
#[derive(Clone, Debug)]
pub struct Cubature {
    tolerance: f64,
    integrated: Vec<Vec<Integrated>>,
    pending: Vec<Cell>,
    rounds: u32,
}

impl Cubature {
    /// The cubature of the albedos seen from each of `theta_o` (radians from the normal, below pi/2), each
    /// within `tolerance` where the rounds allow: its first cells pending.
    pub fn new(theta_o: &[f64], tolerance: f64) -> Self {
        Self {
            tolerance,
            integrated: vec![Vec::new(); theta_o.len()],
            pending: theta_o.iter().enumerate().flat_map(|(job, &theta)| first_cells(job, theta)).collect(),
            rounds: 0,
        }
    }

    /// The cells to integrate next (none once the albedos are known).
    pub fn pending(&self) -> &[Cell] {
        &self.pending
    }

    /// Takes the estimates of the pending cells, in their order, and makes the next round's cells pending.
    ///
    /// # Errors
    /// When `estimates` is not one per pending cell (its length, and how many were pending).
    pub fn take(&mut self, estimates: &[CellEstimate]) -> Result<(), (usize, usize)> {
        if estimates.len() != self.pending.len() {
            return Err((estimates.len(), self.pending.len()));
        }
        for (cell, estimate) in self.pending.iter().zip(estimates) {
            self.integrated[cell.job].push(Integrated::new(*cell, estimate));
        }
        self.rounds += 1;
        self.pending = if self.rounds > MAX_REFINEMENTS {
            Vec::new()
        } else {
            let tolerance = self.tolerance;
            self.integrated
                .iter_mut()
                .flat_map(|cells| worst_cells(cells, tolerance))
                .flat_map(|c| c.quarters())
                .collect()
        };
        Ok(())
    }

    /// The rounds of integration taken so far.
    pub fn rounds(&self) -> u32 {
        self.rounds
    }

    /// Each angle's albedo from the cells integrated so far: the cells' sums in double precision, and their
    /// bounds' (final once nothing is pending).
    pub fn albedos(&self) -> Vec<Albedo> {
        self.integrated
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
            .collect()
    }
}

/// A cell with its integral (both halves of the hemisphere) and the bound on its error.
#[derive(Clone, Copy, Debug)]
struct Integrated {
    cell: Cell,
    value: [f64; 3],
    bound: f64,
}

impl Integrated {
    fn new(cell: Cell, estimate: &CellEstimate) -> Self {
        // Twice: phi_i in [-pi, 0] mirrors [0, pi]. The difference is taken in the probe's precision.
        let difference = (0..3).map(|c| (estimate.kronrod[c] - estimate.gauss[c]).abs()).fold(0.0f32, f32::max);
        Self { cell, value: estimate.kronrod.map(|v| 2.0 * f64::from(v)), bound: 2.0 * f64::from(difference) }
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

#[cfg(test)]
mod tests {
    use super::*;

    /// A cell's estimates of f_r cos(theta_i) = cos(theta_i) / pi (Lambert of albedo 1), as a probe would
    /// make them, and a Gauss estimate off by `error` in the green channel.
    fn lambert_estimate(cell: &Cell, error: f32) -> CellEstimate {
        // The integral of cos t sin t / pi over the cell: (sin^2 t1 - sin^2 t0) / 2 / pi * (p1 - p0).
        let exact =
            ((cell.theta.1.sin().powi(2) - cell.theta.0.sin().powi(2)) / 2.0 / PI * (cell.phi.1 - cell.phi.0)) as f32;
        CellEstimate { kronrod: [exact; 3], gauss: [exact, exact + error, exact] }
    }

    #[test]
    fn the_first_cells_tile_the_half_hemisphere_with_edges_at_the_kinks() {
        let cells = first_cells(0, 30f64.to_radians());
        // theta: 0..30 and 30..90 in 6 and 10 cells (30 degrees in radians over 6 is a hair past 5); phi:
        // 0..90 and 90..180 in 15 each.
        assert_eq!(cells.len(), 16 * 30);
        let area: f64 = cells.iter().map(|c| (c.theta.1 - c.theta.0) * (c.phi.1 - c.phi.0)).sum();
        assert!((area - FRAC_PI_2 * PI).abs() < 1e-12);
        assert!(cells.iter().any(|c| c.theta.1 == 30f64.to_radians()));
        assert!(cells.iter().all(|c| c.theta.1 - c.theta.0 <= FIRST_CELL + 1e-12));
        assert_eq!(first_cells(0, 0.0).len(), 15 * 30);
        assert_eq!(first_cells(0, FRAC_PI_2).len(), 15 * 30);
    }

    #[test]
    fn exact_estimates_end_after_one_round_with_the_sum_of_the_cells() {
        let mut cubature = Cubature::new(&[0.0, 1.0], ALBEDO_TOLERANCE);
        let estimates: Vec<_> = cubature.pending().iter().map(|c| lambert_estimate(c, 0.0)).collect();
        cubature.take(&estimates).unwrap();
        assert!(cubature.pending().is_empty());
        assert_eq!(cubature.rounds(), 1);
        for albedo in cubature.albedos() {
            assert!(albedo.rho.iter().all(|&r| (r - 1.0).abs() < 1e-5), "{albedo:?}");
            assert_eq!(albedo.error_bound, 0.0);
        }
    }

    #[test]
    fn cells_whose_rules_disagree_are_quartered_until_the_bounds_fit_the_tolerance() {
        let mut cubature = Cubature::new(&[0.5], 1e-3);
        let first = cubature.pending().len();
        // Every cell's Gauss estimate 1e-4 off: 2e-4 a cell, far past the tolerance in all.
        let estimates: Vec<_> = cubature.pending().iter().map(|c| lambert_estimate(c, 1e-4)).collect();
        cubature.take(&estimates).unwrap();
        let cut = cubature.pending().len();
        assert_eq!(cut % 4, 0);
        // As many cells cut as leave the rest within half the tolerance: all but 2 (2 x 2e-4 <= 5e-4).
        assert_eq!(cut / 4, first - 2);
        // The quarters agree: the bound is that of the 2 cells kept.
        let estimates: Vec<_> = cubature.pending().iter().map(|c| lambert_estimate(c, 0.0)).collect();
        cubature.take(&estimates).unwrap();
        assert!(cubature.pending().is_empty());
        let albedo = cubature.albedos()[0];
        assert!((albedo.error_bound - 4e-4).abs() < 1e-9, "{albedo:?}");
        assert!((albedo.rho[1] - 1.0).abs() < 1e-5, "{albedo:?}");
    }

    #[test]
    fn the_rounds_end_at_the_most_refinements_whatever_the_estimates() {
        let mut cubature = Cubature::new(&[0.2], 1e-9);
        while !cubature.pending().is_empty() {
            // Never converging, but only the worst cells cut (a few per round, not all).
            let estimates: Vec<_> = cubature
                .pending()
                .iter()
                .enumerate()
                .map(|(k, c)| lambert_estimate(c, if k == 0 { 1e-3 } else { 0.0 }))
                .collect();
            cubature.take(&estimates).unwrap();
        }
        assert_eq!(cubature.rounds(), MAX_REFINEMENTS + 1);
        assert!(cubature.albedos()[0].error_bound > 1e-9);
    }

    #[test]
    fn estimates_not_one_per_pending_cell_are_refused() {
        let mut cubature = Cubature::new(&[0.2], 1e-5);
        let pending = cubature.pending().len();
        assert_eq!(cubature.take(&[]), Err((0, pending)));
    }
}
