//! A sampler's density and f_r cos θi integrated over each cell of the χ² grid, by adaptive rules: each
//! piece of a cell is integrated by Gauss-Legendre's six-point rule in cos θ and φ (the solid angle is
//! dcos θ dφ, so the rule needs no Jacobian), whole and in halves along either axis, whose disagreement
//! bounds the error. While a cell's bounds add up to more than its count's tolerance (a tenth of its noise),
//! or all the cells' to more than the no-sample count's, or f_r cos θi's to more than the albedo's, the
//! pieces of largest bound are cut in two along the axis where the halves disagree most, their halves'
//! integrals becoming the new pieces' wholes: global adaptive integration, as QUADPACK's QAG refines. (The
//! directional albedo's cubature, crates/cubature, is another integrator: Gauss-Kronrod cells of the
//! hemisphere cut in four.)
//!
//! A lobe narrower than the rule's nodes is invisible to both estimates, which then agree on nothing (GGX of
//! α = 10⁻⁴ seen head-on spans 10⁻⁸ of cos θ below the pole, in a cell 0.025 high). The samples show where
//! such a lobe is: a piece holding more than [`SPLIT_SAMPLES`] samples, or far more than its estimate expects,
//! is cut too, along the axis that divides them most unevenly, until the rule resolves what they fell in. Where the pieces are cut changes
//! how exact the integral is, never what it converges to, so the samples bias nothing.
//!
//! Near the poles cos θ is taken from x and y, 1 - cos θ = (x² + y²) / (1 + |z|), not from z, whose float
//! loses what such a lobe is made of.

use glam::DVec3;

use crate::analysis::chi2::SphereGrid;
use crate::error::Result;

/// What is integrated at a direction: the sampler's density, then f_r cos θi's three channels.
pub type Integrand = [f64; 4];

/// A piece holding more samples than this is cut, whatever its rule's estimates say (the lobe may lie
/// between their nodes).
pub const SPLIT_SAMPLES: usize = 1000;

/// A piece holding this many samples more than its estimate expects (and five standard deviations) is cut:
/// a lobe its rule's nodes miss holds samples and no estimate. Fewer samples than [`SPLIT_SAMPLES`] leave such
/// a lobe to this test alone (GGX of α = 10⁻⁴ seen head-on, 2¹⁸ samples: the crowded pieces stopped being cut
/// before the rule saw the lobe, and its half of the density was missed, bound and all).
const UNEXPLAINED_SAMPLES: f64 = 20.0;

/// How many times a cell may be cut in two along one line of descent: 2⁻²⁴ of its side on each axis.
const MAX_DEPTH: u32 = 48;

/// The most directions evaluated for one view direction: past them, the integral is what was reached, with
/// its bound.
const MAX_EVALUATIONS: usize = 1 << 25;

/// The tolerance on a count expected, as a share of its noise √E: the integral's error is a tenth of what the
/// samples can tell, and never need be below [`COUNT_FLOOR`] samples.
const COUNT_TOLERANCE: f64 = 0.1;

/// The smallest tolerance on a count expected, in samples: float32 densities sum to about this at 10⁶.
const COUNT_FLOOR: f64 = 1.0;

/// The tolerance on the directional albedo's integral over the whole hemisphere.
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

    /// The disagreement of each axis's halves with the whole: the density's, f_r cos θi's largest channel's.
    fn differences(&self) -> [(f64, f64); 2] {
        let difference = |axis: usize| {
            let [a, b] = self.halves[axis];
            let d: Integrand = std::array::from_fn(|k| (a[k] + b[k] - self.whole[k]).abs());
            (d[0], d[1].max(d[2]).max(d[3]))
        };
        [difference(0), difference(1)]
    }

    /// The axis whose halves disagree most with the whole, the density's disagreement weighed against
    /// `density_scale` and f_r cos θi's against `f_scale`.
    fn worst_axis(&self, (density_scale, f_scale): (f64, f64)) -> usize {
        let weigh = |(p, f): (f64, f64)| p / density_scale + f / f_scale;
        let [a, b] = self.differences();
        usize::from(weigh(b) > weigh(a))
    }

    /// The piece's estimate, the mean of its two pairs of halves, and its bounds (the larger disagreement),
    /// the density's and f_r cos θi's.
    fn estimate(&self) -> (Integrand, (f64, f64)) {
        let [[a, b], [c, d]] = self.halves;
        let estimate = std::array::from_fn(|k| 0.5 * ((a[k] + b[k]) + (c[k] + d[k])));
        let [x, y] = self.differences();
        (estimate, (x.0.max(y.0), x.1.max(y.1)))
    }

    /// The piece cut in two along `axis`, each half's whole its rule's half, its samples shared out.
    fn cut(self, axis: usize, samples: &[(f64, f64)]) -> [Piece; 2] {
        let halves = Piece::split_bounds(self.bounds, axis);
        let middle = if axis == 0 { halves[0].1 } else { halves[0].3 };
        let (low, high): (Vec<u32>, Vec<u32>) =
            self.samples.iter().partition(|&&i| along(samples[i as usize], axis) < middle);
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

    /// Whether the piece's samples say its rule has not found what they fell in: more than [`SPLIT_SAMPLES`]
    /// of them, or far more than the `expected` count its estimate makes (a lobe between the nodes, which
    /// both estimates miss alike; five standard deviations and [`UNEXPLAINED_SAMPLES`] over it).
    fn shown_by_samples(&self, expected: f64) -> bool {
        let count = self.samples.len() as f64;
        self.samples.len() > SPLIT_SAMPLES || count > expected + 5.0 * expected.max(0.0).sqrt() + UNEXPLAINED_SAMPLES
    }

    /// The axis whose halves divide the piece's samples most unevenly.
    fn uneven_axis(&self, samples: &[(f64, f64)]) -> usize {
        let imbalance = |axis: usize| {
            let (c0, c1, p0, p1) = self.bounds;
            let middle = if axis == 0 { 0.5 * (c0 + c1) } else { 0.5 * (p0 + p1) };
            let below = self.samples.iter().filter(|&&i| along(samples[i as usize], axis) < middle).count();
            below.abs_diff(self.samples.len() - below)
        };
        usize::from(imbalance(1) > imbalance(0))
    }
}

/// A sample's coordinate along `axis`.
fn along((cos_theta, phi): (f64, f64), axis: usize) -> f64 {
    if axis == 0 {
        cos_theta
    } else {
        phi
    }
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

/// Evaluates the halves along both axes of each piece.
fn evaluate_halves(
    pieces: &mut [Piece],
    evaluate: &mut impl FnMut(&[DVec3]) -> Result<Vec<Integrand>>,
) -> Result<usize> {
    let directions: Vec<DVec3> = pieces
        .iter()
        .flat_map(|p| (0..2).flat_map(move |axis| Piece::split_bounds(p.bounds, axis)))
        .flat_map(nodes)
        .collect();
    let values = evaluate(&directions)?;
    for (piece, values) in pieces.iter_mut().zip(values.chunks_exact(4 * 36)) {
        for axis in 0..2 {
            for (half, bounds) in Piece::split_bounds(piece.bounds, axis).into_iter().enumerate() {
                let at = (2 * axis + half) * 36;
                piece.halves[axis][half] = rule(bounds, &values[at..at + 36]);
            }
        }
    }
    Ok(directions.len())
}

/// Takes from `candidates` (piece index, bound) the largest bounds until what is left adds up to at most
/// half of `tolerance`, when all add up to more than it.
fn largest_bounds(mut candidates: Vec<(usize, f64)>, tolerance: f64, chosen: &mut [bool]) {
    let mut total: f64 = candidates.iter().map(|c| c.1).sum();
    if total <= tolerance {
        return;
    }
    candidates.sort_by(|a, b| b.1.total_cmp(&a.1));
    for (index, bound) in candidates {
        if total <= 0.5 * tolerance {
            break;
        }
        chosen[index] = true;
        total -= bound;
    }
}

/// Integrates the density and f_r cos θi over every cell of `grid`, `evaluate` giving both at a batch of
/// directions; `samples` are the (cos θ, φ) of the samples drawn (by [`coordinates`](crate::analysis::chi2::coordinates)), `total` how many were
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
    let counted: Vec<usize> = in_cell.iter().map(Vec::len).collect();
    // The first pieces, the cells, with their wholes and halves.
    let mut pieces: Vec<Piece> = in_cell
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
    let wholes: Vec<DVec3> = pieces.iter().flat_map(|p| nodes(p.bounds)).collect();
    let mut evaluations = wholes.len();
    for (piece, values) in pieces.iter_mut().zip(evaluate(&wholes)?.chunks_exact(36)) {
        piece.whole = rule(piece.bounds, values);
    }
    evaluations += evaluate_halves(&mut pieces, &mut evaluate)?;
    let n = total.max(1) as f64;
    let count_tolerance = |expected: f64| (COUNT_TOLERANCE * expected.max(0.0).sqrt()).max(COUNT_FLOOR) / n;
    let mut converged = false;
    while evaluations < MAX_EVALUATIONS {
        crate::interrupt::check()?;
        let estimates: Vec<(Integrand, (f64, f64))> = pieces.iter().map(Piece::estimate).collect();
        // Each cell's count tolerance from the larger of its estimate and what fell in it; all the cells'
        // together from the no-sample count's, which is 1 less their sum.
        let mut expected = vec![0.0; cells];
        for (piece, (estimate, _)) in pieces.iter().zip(&estimates) {
            expected[piece.cell] += estimate[0] * n;
        }
        let cell_tolerance: Vec<f64> =
            expected.iter().zip(&counted).map(|(&e, &c)| count_tolerance(e.max(c as f64))).collect();
        let shortfall = n - expected.iter().sum::<f64>();
        let total_tolerance = count_tolerance(shortfall);
        let scales = (total_tolerance, ALBEDO_TOLERANCE);
        let bounds: Vec<(f64, f64)> = estimates.iter().map(|e| e.1).collect();
        let mut chosen = vec![false; pieces.len()];
        let mut by_cell: Vec<Vec<(usize, f64)>> = vec![Vec::new(); cells];
        let shown_by_samples: Vec<bool> = pieces
            .iter()
            .zip(&estimates)
            .map(|(piece, (estimate, _))| piece.shown_by_samples(estimate[0] * n))
            .collect();
        for (index, piece) in pieces.iter().enumerate() {
            by_cell[piece.cell].push((index, bounds[index].0));
            chosen[index] = shown_by_samples[index];
        }
        for (cell, candidates) in by_cell.into_iter().enumerate() {
            largest_bounds(candidates, cell_tolerance[cell], &mut chosen);
        }
        largest_bounds(bounds.iter().map(|b| b.0).enumerate().collect(), total_tolerance, &mut chosen);
        largest_bounds(bounds.iter().map(|b| b.1).enumerate().collect(), ALBEDO_TOLERANCE, &mut chosen);
        let mut kept = Vec::with_capacity(pieces.len());
        let mut cut = Vec::new();
        for ((piece, chosen), shown) in pieces.into_iter().zip(chosen).zip(shown_by_samples) {
            if !chosen || piece.depth >= MAX_DEPTH {
                kept.push(piece);
                continue;
            }
            let samples_only = shown && piece.estimate().1 .0 <= cell_tolerance[piece.cell] * 1e-3;
            let axis = if samples_only { piece.uneven_axis(samples) } else { piece.worst_axis(scales) };
            cut.extend(piece.cut(axis, samples));
        }
        pieces = kept;
        if cut.is_empty() {
            converged = true;
            break;
        }
        evaluations += evaluate_halves(&mut cut, &mut evaluate)?;
        pieces.extend(cut);
    }
    let mut integrals = CellIntegrals {
        probability: vec![0.0; cells],
        probability_error: vec![0.0; cells],
        f_cos: vec![[0.0; 3]; cells],
        f_cos_error: 0.0,
        converged,
        evaluations,
    };
    for piece in &pieces {
        let (estimate, (density_bound, f_bound)) = piece.estimate();
        integrals.probability[piece.cell] += estimate[0];
        integrals.probability_error[piece.cell] += density_bound;
        for k in 0..3 {
            integrals.f_cos[piece.cell][k] += estimate[k + 1];
        }
        integrals.f_cos_error += f_bound;
    }
    Ok(integrals)
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;
    use crate::analysis::chi2::coordinates;

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
        // Fewer samples: the pieces at the pole hold fewer than SPLIT_SAMPLES long before the rule sees the
        // lobe, and are cut because they hold far more than their estimate expects.
        let few = &pole[..20_000];
        let found = integrate_cells(&GRID, few, 20_000, density(&lobe)).unwrap();
        let total: f64 = found.probability.iter().sum();
        assert!((total - 1.0).abs() < 1e-4, "{total} from {} samples", few.len());
    }

    #[test]
    fn the_albedo_of_a_lambertian_surface_is_its_reflectance() {
        let lambert = |ds: &[DVec3]| Ok(ds.iter().map(|d| [0.0, 0.5 * d.z.max(0.0) / PI, 0.0, 0.0]).collect());
        let cells = integrate_cells(&GRID, &[], 1_000_000, lambert).unwrap();
        let albedo: f64 = cells.f_cos.iter().map(|f| f[0]).sum();
        assert!((albedo - 0.5).abs() < 1e-9 && cells.f_cos_error < ALBEDO_TOLERANCE, "{albedo}");
    }
}
