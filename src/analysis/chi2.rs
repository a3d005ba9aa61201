//! Pearson's χ² test of a sampler of directions against its density, as Mitsuba 3's `ChiSquareTest` and
//! pbrt-v4's `bsdfs_test.cpp` run it: the sphere cut into cells of equal solid angle on a (cos θ, φ) grid,
//! the samples counted per cell, the density integrated over each cell for the count expected, the cells
//! expecting fewer than [`MIN_EXPECTED`] samples pooled into one, and the statistic's p-value from the χ²
//! distribution (the regularized upper incomplete gamma function). A sample in a cell where the density
//! integrates to nothing fails on its own: no χ² can weigh it. The level is corrected for the directions
//! tested together (Šidák: [`sidak_level`]).
//!
//! Pure arithmetic on the counts and the density: `vk-render sampling` draws the samples on the GPU with the
//! exact mode's own GLSL; the statistic is tested here on samplers whose answer is known.

use std::f64::consts::PI;

use glam::DVec3;

/// Cells expecting fewer samples than this are pooled (Cochran's rule, as Mitsuba and pbrt pool).
pub const MIN_EXPECTED: f64 = 5.0;

/// A direction's (cos θ, φ) about +z, cos θ exact near the poles (the sampling test's cells, this grid's
/// cut, share them).
pub fn coordinates(d: DVec3) -> (f64, f64) {
    let d = d.normalize();
    let across = d.x * d.x + d.y * d.y;
    let cos_theta = if d.z.abs() > 0.5 { d.z.signum() * (1.0 - across / (1.0 + d.z.abs())) } else { d.z };
    (cos_theta, d.y.atan2(d.x))
}

/// The sphere cut into `cos_bins` bands of equal height in cos θ (about +z) and `phi_bins` equal sectors of
/// φ: every cell has the solid angle 4π / (cos_bins × phi_bins).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct SphereGrid {
    /// Bands of cos θ, from -1 (cell row 0) to 1.
    pub cos_bins: usize,
    /// Sectors of φ, from -π (cell column 0) to π.
    pub phi_bins: usize,
}

impl SphereGrid {
    /// How many cells.
    pub fn cells(&self) -> usize {
        self.cos_bins * self.phi_bins
    }

    /// The cell of unit direction `d`: row (cos θ) times `phi_bins` plus column (φ).
    pub fn cell(&self, d: DVec3) -> usize {
        let (cos_theta, phi) = coordinates(d);
        self.cell_at(cos_theta, phi)
    }

    /// The cell of the direction at (cos θ, φ), φ from -π to π.
    pub fn cell_at(&self, cos_theta: f64, phi: f64) -> usize {
        let row = (((cos_theta.clamp(-1.0, 1.0) + 1.0) * 0.5 * self.cos_bins as f64) as usize).min(self.cos_bins - 1);
        let column = (((phi + PI) / (2.0 * PI) * self.phi_bins as f64) as usize).min(self.phi_bins - 1);
        row * self.phi_bins + column
    }

    /// The cell's bounds: cos θ from `.0` to `.1`, φ from `.2` to `.3`.
    pub fn bounds(&self, cell: usize) -> (f64, f64, f64, f64) {
        let (row, column) = (cell / self.phi_bins, cell % self.phi_bins);
        let cos_step = 2.0 / self.cos_bins as f64;
        let phi_step = 2.0 * PI / self.phi_bins as f64;
        let (cos, phi) = (-1.0 + row as f64 * cos_step, -PI + column as f64 * phi_step);
        (cos, cos + cos_step, phi, phi + phi_step)
    }
}

/// A χ² test's outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct ChiSquare {
    /// Pearson's statistic, Σ (observed - expected)² / expected over the cells kept and the pooled one.
    pub statistic: f64,
    /// Its degrees of freedom: the cells kept (with the pooled one) less one.
    pub degrees_of_freedom: usize,
    /// The probability of a statistic at least this large if the samples follow the density.
    pub p_value: f64,
    /// The cells pooled, expecting fewer than [`MIN_EXPECTED`] samples each.
    pub pooled: usize,
    /// Samples in cells where the density integrates to nothing (each fails the test on its own).
    pub impossible: u64,
}

impl ChiSquare {
    /// Whether the samples may follow the density at `level` (the p-value at least `level`, and no sample
    /// where the density has none).
    pub fn passes(&self, level: f64) -> bool {
        self.impossible == 0 && self.p_value >= level
    }
}

/// Pearson's χ² of `observed` counts per cell against `probabilities` per cell (what the density gives each),
/// of `samples` drawn in all. A sampler that sometimes returns no sample has a density that integrates to less
/// than one over the sphere, and its counts are held to that density as they are (a shortfall shows in every
/// cell): Mitsuba's test too counts the samples returned against `samples`.
pub fn chi_square(observed: &[u64], probabilities: &[f64], samples: u64) -> ChiSquare {
    assert_eq!(observed.len(), probabilities.len(), "one count a cell");
    let total = samples as f64;
    let mut impossible = 0;
    let (mut statistic, mut kept) = (0.0, 0usize);
    let (mut pooled_expected, mut pooled_observed, mut pooled) = (0.0, 0.0, 0);
    for (&count, &p) in observed.iter().zip(probabilities) {
        let expected = p * total;
        if expected < 1e-9 {
            impossible += count;
        } else if expected < MIN_EXPECTED {
            pooled_expected += expected;
            pooled_observed += count as f64;
            pooled += 1;
        } else {
            statistic += (count as f64 - expected).powi(2) / expected;
            kept += 1;
        }
    }
    if pooled > 0 {
        statistic += (pooled_observed - pooled_expected).powi(2) / pooled_expected;
        kept += 1;
    }
    let degrees_of_freedom = kept.saturating_sub(1).max(1);
    ChiSquare {
        statistic,
        degrees_of_freedom,
        p_value: gamma_q(degrees_of_freedom as f64 / 2.0, statistic / 2.0),
        pooled,
        impossible,
    }
}

/// The level each of `tests` independent tests must pass at for all of them together to fail at `level`
/// when every sampler is right (Šidák 1967): 1 - (1 - level)^(1 / tests).
pub fn sidak_level(level: f64, tests: usize) -> f64 {
    1.0 - (1.0 - level).powf(1.0 / tests.max(1) as f64)
}

/// The regularized upper incomplete gamma function Q(a, x) = Γ(a, x) / Γ(a): the series below a + 1, the
/// continued fraction (Lentz) above it, as Numerical Recipes computes it; to about 1e-14 relative.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let log_prefactor = a * x.ln() - x - ln_gamma(a);
    if x < a + 1.0 {
        // P(a, x) by its series.
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-16 {
                break;
            }
        }
        (1.0 - sum * log_prefactor.exp()).clamp(0.0, 1.0)
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let step = d * c;
            h *= step;
            if (step - 1.0).abs() < 1e-16 {
                break;
            }
        }
        (log_prefactor.exp() * h).clamp(0.0, 1.0)
    }
}

/// ln Γ(x) for x > 0 (Lanczos' approximation, g = 7, 9 terms: about 1e-15 relative).
pub fn ln_gamma(x: f64) -> f64 {
    const G: f64 = 7.0;
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    if x < 0.5 {
        // The reflection formula.
        return (PI / (PI * x).sin()).ln() - ln_gamma(1.0 - x);
    }
    let x = x - 1.0;
    let t = x + G + 0.5;
    let series = C[1..].iter().enumerate().fold(C[0], |sum, (k, c)| sum + c / (x + k as f64 + 1.0));
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + series.ln()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::sampling::cell_integrals::integrate_cells;
    // The reference tracer's generator: uniform numbers in [0, 1), deterministic.
    use crate::reference::SplitMix64 as Uniform;

    /// Cosine-weighted directions about +z with exponent `power` (cos^power θ / normalization).
    fn power_cosine_sample(power: f64, u: f64, v: f64) -> DVec3 {
        let cos_theta = u.powf(1.0 / (power + 1.0));
        let sin_theta = (1.0 - cos_theta * cos_theta).max(0.0).sqrt();
        let phi = 2.0 * PI * v;
        DVec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
    }

    fn power_cosine_pdf(power: f64, d: DVec3) -> f64 {
        if d.z <= 0.0 {
            0.0
        } else {
            (power + 1.0) / (2.0 * PI) * d.z.powf(power)
        }
    }

    const GRID: SphereGrid = SphereGrid { cos_bins: 20, phi_bins: 40 };

    /// Each cell's probability under `pdf`, by the command's own adaptive rules ([`integrate_cells`]).
    fn probabilities(pdf: impl Fn(DVec3) -> f64) -> Vec<f64> {
        let density = |ds: &[DVec3]| Ok(ds.iter().map(|&d| [pdf(d), 0.0, 0.0, 0.0]).collect());
        integrate_cells(&GRID, &[], 1_000_000, density).unwrap().probability
    }

    fn counts(samples: u64, seed: u64, sample: impl Fn(f64, f64) -> Option<DVec3>) -> Vec<u64> {
        let mut uniform = Uniform(seed);
        let mut observed = vec![0u64; GRID.cells()];
        for _ in 0..samples {
            let (u, v) = (uniform.next(), uniform.next());
            if let Some(d) = sample(u, v) {
                observed[GRID.cell(d)] += 1;
            }
        }
        observed
    }

    #[test]
    fn the_incomplete_gamma_function_has_its_known_values() {
        // Q(1, x) = exp(-x); Q(1/2, x) = erfc(sqrt(x)); the χ² table's 1% points.
        for x in [0.1, 1.0, 3.0, 20.0] {
            assert!((gamma_q(1.0, x) - (-x).exp()).abs() < 1e-13, "{x}");
        }
        assert!((gamma_q(0.5, 1.0) - 0.157_299_207_050_285_13).abs() < 1e-12);
        for (dof, point) in
            [(1.0, 6.634_896_601_021_214), (10.0, 23.209_251_158_954_36), (100.0, 135.806_722_353_241_74)]
        {
            let p = gamma_q(dof / 2.0, point / 2.0);
            assert!((p - 0.01).abs() < 1e-8, "{dof} degrees of freedom: {p}");
        }
        assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-13 && (ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-13);
    }

    #[test]
    fn a_direction_falls_in_the_cell_whose_bounds_hold_it() {
        let d = DVec3::new(0.3, -0.5, 0.2).normalize();
        let (c0, c1, p0, p1) = GRID.bounds(GRID.cell(d));
        let phi = d.y.atan2(d.x);
        assert!(c0 <= d.z && d.z < c1 && p0 <= phi && phi < p1);
    }

    #[test]
    fn a_right_sampler_fails_at_the_level_and_no_more() {
        // 200 seeds of a sampler drawn exactly from its density: at the 1% level about 2 fail (binomial:
        // at most 7 with probability 0.999), and the p-values are uniform on [0, 1] (their mean 1/2, within
        // 4 standard deviations of a mean of 200: 0.082), which a wrong count of degrees of freedom is not.
        let expected = probabilities(|d| power_cosine_pdf(4.0, d));
        let tests: Vec<ChiSquare> = (0..200)
            .map(|seed| {
                let observed = counts(20_000, seed, |u, v| Some(power_cosine_sample(4.0, u, v)));
                chi_square(&observed, &expected, 20_000)
            })
            .collect();
        let failed = tests.iter().filter(|t| !t.passes(0.01)).count();
        assert!(failed <= 7, "{failed} of 200 right samplers failed at the 1% level");
        let mean = tests.iter().map(|t| t.p_value).sum::<f64>() / tests.len() as f64;
        assert!((mean - 0.5).abs() < 0.082, "the p-values' mean {mean}");
        assert!(tests.iter().all(|t| t.impossible == 0 && t.pooled > 0));
    }

    #[test]
    fn a_slightly_wrong_sampler_is_caught() {
        // Samples of cos^4.2 tested against cos^4's density: a shift of the lobe's width by 2%.
        let expected = probabilities(|d| power_cosine_pdf(4.0, d));
        let observed = counts(1_000_000, 7, |u, v| Some(power_cosine_sample(4.2, u, v)));
        let test = chi_square(&observed, &expected, 1_000_000);
        assert!(!test.passes(0.01), "{test:?}");
        assert_eq!(test.impossible, 0);
    }

    #[test]
    fn samples_where_the_density_is_nothing_fail_on_their_own() {
        // A sampler that sends one sample in ten below the horizon, against a density with none there.
        let expected = probabilities(|d| power_cosine_pdf(1.0, d));
        let observed = counts(100_000, 3, |u, v| {
            let d = power_cosine_sample(1.0, (u * 10.0).fract(), v);
            Some(if u < 0.1 { DVec3::new(d.x, d.y, -d.z) } else { d })
        });
        let test = chi_square(&observed, &expected, 100_000);
        assert!(test.impossible > 9_000 && !test.passes(0.01), "{test:?}");
    }

    #[test]
    fn samples_not_returned_are_the_densitys_shortfall() {
        // A sampler returning nothing half the time, against a density integrating to a half: it passes.
        let expected = probabilities(|d| 0.5 * power_cosine_pdf(2.0, d));
        let observed = counts(200_000, 11, |u, v| (u < 0.5).then(|| power_cosine_sample(2.0, 2.0 * u, v)));
        let test = chi_square(&observed, &expected, 200_000);
        assert!(test.passes(0.01), "{test:?}");
        // The same samples against the whole density: the missing half is caught.
        let whole = probabilities(|d| power_cosine_pdf(2.0, d));
        assert!(!chi_square(&observed, &whole, 200_000).passes(0.01));
    }

    #[test]
    fn sidaks_level_keeps_the_familys() {
        let each = sidak_level(0.01, 10);
        // The family fails at the level; each test a little less strictly than Bonferroni's level / tests.
        assert!((1.0 - (1.0 - each).powi(10) - 0.01).abs() < 1e-12, "{each}");
        assert!(each > 0.01 / 10.0 && each < 0.0011, "{each}");
    }
}
