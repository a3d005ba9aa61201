//! A sampler's density and f_r cos θi integrated over each cell of the χ² grid, by adaptive cubature: each
//! piece of a cell is integrated by Gauss-Legendre's six-point rule in cos θ and φ (the solid angle is
//! dcos θ dφ, so the rule needs no Jacobian), whole and in halves along either axis; where the halves
//! disagree with the whole by more than the tolerance, the piece is cut in two along the axis where they
//! disagree most, its halves' integrals becoming the new pieces' wholes, as QUADPACK refines an interval.
//!
//! A lobe narrower than the rule's nodes is invisible to both estimates, which then agree on nothing (GGX of
//! α = 10⁻⁴ seen head-on spans 10⁻⁸ of cos θ below the pole, in a cell 0.025 high). The samples show where
//! such a lobe is: a piece holding more than [`SPLIT_SAMPLES`] samples is cut too, along the axis that
//! divides them most unevenly, until the rule resolves what they fell in. Where the pieces are cut changes
//! how exact the integral is, never what it converges to, so the samples bias nothing.
//!
//! Near the poles cos θ is taken from x and y, 1 - cos θ = (x² + y²) / (1 + |z|), not from z, whose float
//! loses what such a lobe is made of.

use std::f64::consts::PI;

use glam::DVec3;

use crate::analysis::chi2::SphereGrid;
use crate::error::Result;

/// What is integrated at a direction: the sampler's density, then f_r cos θi's three channels.
pub type Integrand = [f64; 4];

/// A piece holding more samples than this is cut, whatever its rule's estimates say (the lobe may lie
/// between their nodes).
pub const SPLIT_SAMPLES: usize = 1000;

/// How many times a cell may be cut in two along one line of descent: 2⁻²⁴ of its side on each axis.
const MAX_DEPTH: u32 = 48;

/// The most directions evaluated for one view direction: past them, the integral is what was reached, with
/// its bound.
const MAX_EVALUATIONS: usize = 1 << 25;

/// The tolerance on a cell's expected count, as a share of its noise √E: the integral's error is a tenth of
/// what the samples can tell.
const COUNT_TOLERANCE: f64 = 0.1;

/// The tolerance on the directional albedo's integral over the whole hemisphere, shared by solid angle.
const ALBEDO_TOLERANCE: f64 = 1e-4;

/// The six-point Gauss-Legendre rule on [-1, 1]: nodes and weights.
const NODES: [f64; 6] = [
    -0.932_469_514_203_152,
    -0.661_209_386_466_264_5,
    -0.238_619_186_083_196_9,
    0.238_619_186_083_196_9,
    0.661_209_386_466_264_5,
    0.932_469_514_203_152,
];
const WEIGHTS: [f64; 6] = [
    0.171_324_492_379_170_3,
    0.360_761_573_048_138_6,
    0.467_913_934_572_691,
    0.467_913_934_572_691,
    0.360_761_573_048_138_6,
    0.171_324_492_379_170_3,
];

/// A direction's (cos θ, φ) about +z, cos θ exact near the poles (see the module's notes).
pub fn coordinates(d: DVec3) -> (f64, f64) {
    let d = d.normalize();
    let across = d.x * d.x + d.y * d.y;
    let cos_theta = if d.z.abs() > 0.5 { d.z.signum() * (1.0 - across / (1.0 + d.z.abs())) } else { d.z };
    (cos_theta, d.y.atan2(d.x))
}

/// The unit direction at (cos θ, φ), sin θ exact near the poles.
fn direction(cos_theta: f64, phi: f64) -> DVec3 {
    let sin_theta = ((1.0 - cos_theta) * (1.0 + cos_theta)).max(0.0).sqrt();
    DVec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// A cell's integrals.
#[derive(Clone, Debug, PartialEq)]
pub struct CellIntegrals {
    /// The probability of each cell: its density's integral.
    pub probability: Vec<f64>,
    /// The bound on each cell's probability's error.
    pub probability_error: Vec<f64>,
    /// f_r cos θi integrated over each cell, RGB.
    pub f_cos: Vec<[f64; 3]>,
    /// The bound on the error of f_r cos θi's integral over the sphere (the largest channel's).
    pub f_cos_error: f64,
    /// Whether every piece met its tolerance (else the bounds are what was reached).
    pub converged: bool,
    /// The directions evaluated.
    pub evaluations: usize,
}

/// A rectangle of (cos θ, φ) within a cell, with its rule's estimates.
#[derive(Clone, Debug)]
struct Piece {
    cell: usize,
    /// cos θ from `.0` to `.1`, φ from `.2` to `.3`.
    bounds: (f64, f64, f64, f64),
    depth: u32,
    whole: Integrand,
    /// The rule on the two halves along cos θ (`[0]`) and along φ (`[1]`).
    halves: [[Integrand; 2]; 2],
    /// The samples inside, by index.
    samples: Vec<u32>,
}

impl Piece {
    /// The halves of `bounds` along `axis` (0: cos θ, 1: φ).
    fn split_bounds(bounds: (f64, f64, f64, f64), axis: usize) -> [(f64, f64, f64, f64); 2] {
        let (c0, c1, p0, p1) = bounds;
        if axis == 0 {
            let middle = 0.5 * (c0 + c1);
            [(c0, middle, p0, p1), (middle, c1, p0, p1)]
        } else {
            let middle = 0.5 * (p0 + p1);
            [(c0, c1, p0, middle), (c0, c1, middle, p1)]
        }
    }

    /// The difference between each axis's halves and the whole, per component.
    fn differences(&self) -> [Integrand; 2] {
        let difference = |axis: usize| {
            let [a, b] = self.halves[axis];
            std::array::from_fn(|k| (a[k] + b[k] - self.whole[k]).abs())
        };
        [difference(0), difference(1)]
    }

    /// The piece's estimate (the halves along the axis they disagree most with the whole) and its bound
    /// (the larger disagreement), per component.
    fn estimate(&self, tolerances: (f64, f64)) -> (usize, Integrand, Integrand) {
        let differences = self.differences();
        let axis = usize::from(normalized(&differences[1], tolerances) > normalized(&differences[0], tolerances));
        let [a, b] = self.halves[axis];
        let bound = std::array::from_fn(|k| differences[0][k].max(differences[1][k]));
        (axis, std::array::from_fn(|k| a[k] + b[k]), bound)
    }

    fn area(&self) -> f64 {
        (self.bounds.1 - self.bounds.0) * (self.bounds.3 - self.bounds.2)
    }
}

/// An error measured against its tolerances: the density's, and f_r cos θi's largest channel's.
fn normalized(error: &Integrand, (density, f_cos): (f64, f64)) -> f64 {
    let f = error[1].max(error[2]).max(error[3]);
    (error[0] / density.max(f64::MIN_POSITIVE)).max(f / f_cos.max(f64::MIN_POSITIVE))
}

/// The six-point rule's 36 directions on `bounds`.
fn nodes(bounds: (f64, f64, f64, f64)) -> impl Iterator<Item = DVec3> {
    let (c0, c1, p0, p1) = bounds;
    NODES.iter().flat_map(move |x| {
        let cos_theta = 0.5 * (c0 + c1) + 0.5 * (c1 - c0) * x;
        NODES.iter().map(move |y| direction(cos_theta, 0.5 * (p0 + p1) + 0.5 * (p1 - p0) * y))
    })
}

/// The six-point rule's integral on `bounds` from the values at its [`nodes`].
fn rule(bounds: (f64, f64, f64, f64), values: &[Integrand]) -> Integrand {
    let (c0, c1, p0, p1) = bounds;
    let scale = 0.25 * (c1 - c0) * (p1 - p0);
    let mut sum = [0.0; 4];
    for (i, wx) in WEIGHTS.iter().enumerate() {
        for (j, wy) in WEIGHTS.iter().enumerate() {
            for (s, v) in sum.iter_mut().zip(values[6 * i + j]) {
                *s += wx * wy * scale * v;
            }
        }
    }
    sum
}

/// Integrates the density and f_r cos θi over every cell of `grid`, `evaluate` giving both at a batch of
/// directions; `samples` are the (cos θ, φ) of the samples drawn (by [`coordinates`]), `total` how many were
/// drawn (no sample included), which set the tolerances on the counts expected.
///
/// # Errors
/// What `evaluate` returns.
pub fn integrate_cells(
    grid: &SphereGrid,
    samples: &[(f64, f64)],
    total: u64,
    mut evaluate: impl FnMut(&[DVec3]) -> Result<Vec<Integrand>>,
) -> Result<CellIntegrals> {
    let cells = grid.cells();
    let mut in_cell: Vec<Vec<u32>> = vec![Vec::new(); cells];
    for (index, &(cos_theta, phi)) in samples.iter().enumerate() {
        in_cell[grid.cell_at(cos_theta, phi)].push(index as u32);
    }
    // The first pieces, the cells, with their wholes.
    let mut pending: Vec<Piece> = in_cell
        .into_iter()
        .enumerate()
        .map(|(cell, samples)| Piece {
            cell,
            bounds: grid.bounds(cell),
            depth: 0,
            whole: [0.0; 4],
            halves: [[[0.0; 4]; 2]; 2],
            samples,
        })
        .collect();
    let wholes: Vec<DVec3> = pending.iter().flat_map(|p| nodes(p.bounds)).collect();
    let mut evaluations = wholes.len();
    for (piece, values) in pending.iter_mut().zip(evaluate(&wholes)?.chunks_exact(36)) {
        piece.whole = rule(piece.bounds, values);
    }
    let cell_area = 4.0 * PI / cells as f64;
    // Each cell's count tolerance from the larger of its first estimate and what fell in it.
    let count_tolerance: Vec<f64> = pending
        .iter()
        .map(|p| (COUNT_TOLERANCE * (p.whole[0] * total as f64).max(p.samples.len() as f64).sqrt()).max(0.01))
        .collect();
    let mut integrals = CellIntegrals {
        probability: vec![0.0; cells],
        probability_error: vec![0.0; cells],
        f_cos: vec![[0.0; 3]; cells],
        f_cos_error: 0.0,
        converged: true,
        evaluations: 0,
    };
    while !pending.is_empty() {
        crate::interrupt::check()?;
        // Each pending piece's halves along both axes.
        let directions: Vec<DVec3> = pending
            .iter()
            .flat_map(|p| (0..2).flat_map(move |axis| Piece::split_bounds(p.bounds, axis)))
            .flat_map(nodes)
            .collect();
        evaluations += directions.len();
        let values = evaluate(&directions)?;
        let mut next = Vec::new();
        for (mut piece, values) in pending.into_iter().zip(values.chunks_exact(4 * 36)) {
            for axis in 0..2 {
                for (half, bounds) in Piece::split_bounds(piece.bounds, axis).into_iter().enumerate() {
                    let at = (2 * axis + half) * 36;
                    piece.halves[axis][half] = rule(bounds, &values[at..at + 36]);
                }
            }
            let share = piece.area() / cell_area;
            let tolerances = (
                share * count_tolerance[piece.cell] / total.max(1) as f64,
                share * ALBEDO_TOLERANCE * cell_area / (2.0 * PI),
            );
            let (axis, estimate, bound) = piece.estimate(tolerances);
            let crowded = piece.samples.len() > SPLIT_SAMPLES;
            let unresolved = normalized(&bound, tolerances) > 1.0;
            if (crowded || unresolved) && piece.depth < MAX_DEPTH && evaluations < MAX_EVALUATIONS {
                let axis = if crowded && !unresolved { uneven_axis(&piece, samples) } else { axis };
                next.extend(piece.cut(axis, samples));
                continue;
            }
            integrals.converged &= !unresolved;
            integrals.probability[piece.cell] += estimate[0];
            integrals.probability_error[piece.cell] += bound[0];
            for k in 0..3 {
                integrals.f_cos[piece.cell][k] += estimate[k + 1];
            }
            integrals.f_cos_error += bound[1].max(bound[2]).max(bound[3]);
        }
        pending = next;
    }
    integrals.evaluations = evaluations;
    Ok(integrals)
}

/// The axis whose halves divide the piece's samples most unevenly.
fn uneven_axis(piece: &Piece, samples: &[(f64, f64)]) -> usize {
    let imbalance = |axis: usize| {
        let (c0, c1, p0, p1) = piece.bounds;
        let middle = if axis == 0 { 0.5 * (c0 + c1) } else { 0.5 * (p0 + p1) };
        let below = piece
            .samples
            .iter()
            .filter(|&&i| {
                let (cos_theta, phi) = samples[i as usize];
                (if axis == 0 { cos_theta } else { phi }) < middle
            })
            .count();
        below.abs_diff(piece.samples.len() - below)
    };
    usize::from(imbalance(1) > imbalance(0))
}

impl Piece {
    /// The piece cut in two along `axis`, each half's whole its rule's half, its samples shared out.
    fn cut(self, axis: usize, samples: &[(f64, f64)]) -> [Piece; 2] {
        let halves = Piece::split_bounds(self.bounds, axis);
        let middle = if axis == 0 { halves[0].1 } else { halves[0].3 };
        let (low, high): (Vec<u32>, Vec<u32>) = self.samples.iter().partition(|&&i| {
            let (cos_theta, phi) = samples[i as usize];
            (if axis == 0 { cos_theta } else { phi }) < middle
        });
        let child = |half: usize, samples: Vec<u32>| Piece {
            cell: self.cell,
            bounds: halves[half],
            depth: self.depth + 1,
            whole: self.halves[axis][half],
            halves: [[[0.0; 4]; 2]; 2],
            samples,
        };
        [child(0, low), child(1, high)]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const GRID: SphereGrid = SphereGrid { cos_bins: 20, phi_bins: 40 };

    fn cosine_power(power: f64) -> impl Fn(DVec3) -> f64 {
        move |d: DVec3| if d.z > 0.0 { (power + 1.0) / (2.0 * PI) * d.z.powf(power) } else { 0.0 }
    }

    /// The density alone, as an integrand.
    fn density(pdf: impl Fn(DVec3) -> f64) -> impl FnMut(&[DVec3]) -> Result<Vec<Integrand>> {
        move |ds: &[DVec3]| Ok(ds.iter().map(|&d| [pdf(d), 0.0, 0.0, 0.0]).collect())
    }

    #[test]
    fn a_density_integrates_to_one_within_its_bound() {
        let uniform = integrate_cells(&GRID, &[], 1_000_000, density(|_| 1.0 / (4.0 * PI))).unwrap();
        assert!(uniform.probability.iter().all(|p| (p - 1.0 / GRID.cells() as f64).abs() < 1e-14));
        for power in [1.0, 10.0, 1000.0] {
            let cells = integrate_cells(&GRID, &[], 1_000_000, density(cosine_power(power))).unwrap();
            let total: f64 = cells.probability.iter().sum();
            let bound: f64 = cells.probability_error.iter().sum();
            assert!(cells.converged && (total - 1.0).abs() <= bound.max(1e-9), "cos^{power}: {total} ± {bound}");
        }
    }

    #[test]
    fn a_lobe_between_the_nodes_is_found_by_its_samples() {
        // cos^(2·10^8) θ: 1 - cos θ ~ 5e-9, far inside the top row's first node. Without samples the rule
        // sees nothing; with samples at the pole the pieces there are cut until it is resolved.
        let lobe = cosine_power(2e8);
        let blind = integrate_cells(&GRID, &[], 1_000_000, density(&lobe)).unwrap();
        assert!(blind.probability.iter().sum::<f64>() < 1e-6);
        // The lobe's own samples (1 - cos θ = -ln(u) / (s + 1) to first order), 5000 a column of cells.
        let mut uniform = crate::reference::SplitMix64(5);
        let pole: Vec<(f64, f64)> = (0..200_000)
            .map(|_| (1.0 - (-uniform.next().max(1e-300).ln()) / (2e8 + 1.0), PI * (2.0 * uniform.next() - 1.0)))
            .collect();
        // coordinates() keeps such a direction's cos θ, which its z alone rounds to 1.
        let (cos_theta, _) = coordinates(DVec3::new(1e-5, 1e-5, 1.0));
        assert!(cos_theta < 1.0 && (1.0 - cos_theta - 1e-10).abs() < 1e-16, "{cos_theta}");
        let found = integrate_cells(&GRID, &pole, 1_000_000, density(&lobe)).unwrap();
        let total: f64 = found.probability.iter().sum();
        assert!((total - 1.0).abs() < 1e-6, "{total}");
    }

    #[test]
    fn the_albedo_of_a_lambertian_surface_is_its_reflectance() {
        let lambert = |ds: &[DVec3]| Ok(ds.iter().map(|d| [0.0, 0.5 * d.z.max(0.0) / PI, 0.0, 0.0]).collect());
        let cells = integrate_cells(&GRID, &[], 1_000_000, lambert).unwrap();
        let albedo: f64 = cells.f_cos.iter().map(|f| f[0]).sum();
        assert!((albedo - 0.5).abs() < 1e-9 && cells.f_cos_error < ALBEDO_TOLERANCE, "{albedo}");
    }
}
