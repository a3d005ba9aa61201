//! Testing a material's own sampler, `material_sample` and `material_pdf` of the GLSL the exact mode draws
//! from, as `vk-render sampling` runs it: for each view direction the samples are drawn on the GPU, then
//! - Pearson's χ² of their counts on an equal-area grid against the density integrated over each cell
//!   ([`cell_integrals`]), the samples returned as none (below the surface) one more cell, holding the density's
//!   shortfall: [`crate::analysis::chi2`];
//! - the density's integral over the sphere, at most 1, and nothing below the surface;
//! - the estimator: the mean of f_r cos θi / pdf over the samples against the directional albedo, f_r cos θi
//!   integrated by the same rules (the probe's `brdf_eval` on the GPU), within the mean's noise;
//! - the BRDF: energy (the directional albedo at most 1) and reciprocity ([`reciprocity`]).
//!
//! Every test at one level α for the family (Šidák's correction over the views and the χ² and estimator tests
//! each makes).

pub mod cell_integrals;
pub mod reciprocity;
pub mod report;

use glam::{DVec3, Vec3};

use self::cell_integrals::{integrate_cells, CellIntegrals, Integrand};
use self::reciprocity::Reciprocity;
use super::chi2::{chi_square, coordinates, gamma_q, sidak_level, ChiSquare, SphereGrid};
use crate::brdf::Brdf;
use crate::error::Result;
use crate::render::{BrdfSample, ProbeCase, Renderer};

/// The grid the samples are counted on: 80 bands of cos θ and 160 sectors of φ, pbrt-v4's resolution
/// (its test's 80 × 160 in θ and φ), 78 samples a cell on average of 10⁶ over the sphere.
pub const GRID: SphereGrid = SphereGrid { cos_bins: 80, phi_bins: 160 };

/// The samples drawn per view by default, as Mitsuba's and pbrt's tests draw.
pub const DEFAULT_SAMPLES: u64 = 1_000_000;

/// The level of the whole family of tests.
pub const DEFAULT_LEVEL: f64 = 0.01;

/// The views tested by default: θo in degrees (φo 0).
pub const DEFAULT_THETA_O: [f64; 6] = [0.0, 20.0, 40.0, 60.0, 75.0, 85.0];

/// The azimuths added for an anisotropic model, in degrees.
pub const DEFAULT_PHI_O: [f64; 3] = [0.0, 45.0, 90.0];

/// Samples drawn at once: 32 bytes each come back from the GPU.
const SAMPLES_PER_BATCH: usize = 1 << 20;

/// What to test.
#[derive(Clone, Debug, PartialEq)]
pub struct SamplingOptions {
    /// The views: (θo, φo) in degrees, θo from 0 to below 90.
    pub views: Vec<(f64, f64)>,
    /// Samples drawn per view.
    pub samples: u64,
    /// The random stream (each view draws its own from it).
    pub seed: u32,
    /// The level α of the family of tests.
    pub level: f64,
}

/// A cell of the grid whose count is far from the one expected.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellDeviation {
    /// The cell, in [`GRID`]'s numbering.
    pub cell: usize,
    /// The samples counted in it.
    pub observed: u64,
    /// The samples its density expects.
    pub expected: f64,
}

/// One view's outcome.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewOutcome {
    /// θo in degrees.
    pub theta_o: f64,
    /// φo in degrees.
    pub phi_o: f64,
    /// Samples drawn.
    pub samples: u64,
    /// The samples per cell of [`GRID`] (below the surface none: they are no sample).
    pub histogram: Vec<u64>,
    /// The density's integral over each cell of [`GRID`], and f_r cos θi's.
    pub cells: CellIntegrals,
    /// Whether `cells` integrated the density and f_r evaluated in double precision (a `.brdf` file's on a
    /// device with doubles), rather than in float32 as the samples are drawn.
    pub in_double: bool,
    /// Draws returned as no sample (below the surface).
    pub no_sample: u64,
    /// Whether the no-sample draws were a cell of the χ² test (when the density's integral is known well
    /// enough to expect their count).
    pub no_sample_tested: bool,
    /// Draws whose direction, density or f_r is not a finite number, or whose density is not positive where
    /// the sample was returned: no estimator can weigh them.
    pub invalid: u64,
    /// Pearson's χ², the no-sample count one more cell.
    pub chi_square: ChiSquare,
    /// The cells that weigh most in the statistic, worst first.
    pub worst_cells: Vec<CellDeviation>,
    /// The mean of f_r cos θi / pdf over the draws (no sample 0), RGB.
    pub estimate: [f64; 3],
    /// Its standard error, RGB.
    pub standard_error: [f64; 3],
}

impl ViewOutcome {
    /// The density's integral over the sphere and its bound.
    pub fn density_integral(&self) -> (f64, f64) {
        (self.cells.probability.iter().sum(), self.cells.probability_error.iter().sum())
    }

    /// The density's integral below the surface (cos θ < 0): none where the sampler draws none.
    pub fn density_below(&self) -> f64 {
        let upper = GRID.cells() / 2;
        self.cells.probability[..upper].iter().map(|p| p.abs()).sum()
    }

    /// The directional albedo, RGB: f_r cos θi over the hemisphere.
    pub fn albedo(&self) -> [f64; 3] {
        let mut albedo = [0.0; 3];
        for f in &self.cells.f_cos {
            for (sum, v) in albedo.iter_mut().zip(f) {
                *sum += v;
            }
        }
        albedo
    }
}

/// A test's verdict, with what it measured in words.
#[derive(Clone, Debug, PartialEq)]
pub struct Verdict {
    /// The test's name: "chi-square", "density integral", "density below the surface", "samples",
    /// "estimator", "energy" or "reciprocity".
    pub test: &'static str,
    /// The view it was made at (θo, φo in degrees), none for reciprocity.
    pub view: Option<(f64, f64)>,
    /// Whether it passed.
    pub passed: bool,
    /// What it measured.
    pub detail: String,
}

/// A sampler's whole test.
#[derive(Clone, Debug, PartialEq)]
pub struct SamplingReport {
    /// Each view's outcome.
    pub views: Vec<ViewOutcome>,
    /// The BRDF's reciprocity.
    pub reciprocity: Reciprocity,
    /// The level each χ² and each estimator test is held to (Šidák's, of the family's).
    pub level_each: f64,
    /// Every test's verdict, in the order made.
    pub verdicts: Vec<Verdict>,
}

impl SamplingReport {
    /// Whether every test passed.
    pub fn passed(&self) -> bool {
        self.verdicts.iter().all(|v| v.passed)
    }
}

/// Tests `brdf`'s sampler at each view of `options`.
///
/// # Errors
/// What the sampler and probe passes return.
/// `done` is called after each view.
pub fn test_sampler(
    renderer: &mut Renderer,
    brdf: &Brdf,
    options: &SamplingOptions,
    mut done: impl FnMut(),
) -> Result<SamplingReport> {
    // Per view: the χ² and the estimator's three channels.
    let level_each = sidak_level(options.level, 4 * options.views.len());
    let mut views = Vec::with_capacity(options.views.len());
    for (index, &(theta_o, phi_o)) in options.views.iter().enumerate() {
        crate::interrupt::check()?;
        let seed = options.seed.wrapping_add(0x9e37_79b9u32.wrapping_mul(index as u32 + 1));
        views.push(test_view(renderer, brdf, (theta_o, phi_o), options.samples, seed)?);
        done();
    }
    let reciprocity = reciprocity::measure(renderer, brdf)?;
    let mut verdicts = Vec::new();
    for view in &views {
        verdicts.extend(view_verdicts(view, level_each));
    }
    verdicts.push(reciprocity.verdict());
    Ok(SamplingReport { views, reciprocity, level_each, verdicts })
}

/// Whether `brdf` is isotropic: f_r the same when both directions turn 37° about the normal, at pairs of
/// directions of every elevation (float32's rounding aside).
///
/// # Errors
/// What the probe pass returns.
pub fn is_isotropic(renderer: &mut Renderer, brdf: &Brdf) -> Result<bool> {
    let n = Vec3::Z;
    let mut cases = Vec::new();
    for theta_i in [10.0, 35.0, 60.0, 80.0] {
        for theta_o in [5.0, 30.0, 55.0, 75.0] {
            for phi in [0.0, 60.0, 130.0, 180.0] {
                for turn in [0.0, 37.0] {
                    let (wi, wo) = (view_direction(theta_i, 20.0 + turn), view_direction(theta_o, 20.0 + phi + turn));
                    cases.push(ProbeCase { brdf: brdf.clone(), n, wi, wo });
                }
            }
        }
    }
    let values = renderer.probe_brdfs(&cases)?;
    let scale = values.iter().fold(0.0f32, |m, v| m.max(v.abs().max_element()));
    Ok(values.chunks_exact(2).all(|pair| {
        let difference = (pair[0] - pair[1]).abs().max_element();
        difference <= 1e-3 * pair[0].abs().max(pair[1].abs()).max_element() + 1e-5 * scale
    }))
}

/// The views of `theta_o` by `phi_o` (degrees), θo slowest; without `phi_o`, 0 for an isotropic `brdf` and
/// [`DEFAULT_PHI_O`] for an anisotropic one ([`is_isotropic`]).
///
/// # Errors
/// What the probe pass returns.
pub fn views(renderer: &mut Renderer, brdf: &Brdf, theta_o: &[f64], phi_o: Option<&[f64]>) -> Result<Vec<(f64, f64)>> {
    let phi_o = match phi_o {
        Some(phi_o) => phi_o.to_vec(),
        None if is_isotropic(renderer, brdf)? => vec![0.0],
        None => DEFAULT_PHI_O.to_vec(),
    };
    Ok(theta_o.iter().flat_map(|&t| phi_o.iter().map(move |&p| (t, p))).collect())
}

/// The unit view direction at θo, φo (degrees), in the frame n = +z, X = +x.
pub fn view_direction(theta_o: f64, phi_o: f64) -> Vec3 {
    let (theta, phi) = (theta_o.to_radians(), phi_o.to_radians());
    DVec3::new(theta.sin() * phi.cos(), theta.sin() * phi.sin(), theta.cos()).as_vec3()
}

fn test_view(renderer: &mut Renderer, brdf: &Brdf, view: (f64, f64), samples: u64, seed: u32) -> Result<ViewOutcome> {
    let wo = view_direction(view.0, view.1);
    let mut tally = Tally::new();
    let mut drawn = 0u64;
    while drawn < samples {
        crate::interrupt::check()?;
        let count = SAMPLES_PER_BATCH.min((samples - drawn) as usize);
        for sample in renderer.draw_brdf_samples(brdf, wo, (drawn, count), seed)? {
            tally.add(&sample);
        }
        drawn += count as u64;
    }
    // A .brdf file's density and f_r, and a sharp built-in lobe's, are integrated in double precision where
    // the device has doubles: float32 may round away what a sharp lobe is made of (shaders/brdf_density64.comp).
    let in_double = renderer.integrates_in_double(brdf)?;
    let cells = integrate_cells(&GRID, &tally.coordinates, samples, |directions| {
        if in_double {
            if let Some(values) = renderer.brdf_sampler_densities_double(brdf, wo, directions)? {
                return Ok(values);
            }
        }
        let directions: Vec<Vec3> = directions.iter().map(|d| d.as_vec3()).collect();
        Ok(renderer
            .brdf_sampler_densities(brdf, wo, &directions)?
            .into_iter()
            .map(|d| -> Integrand { [d.pdf as f64, d.f_cos.x as f64, d.f_cos.y as f64, d.f_cos.z as f64] })
            .collect())
    })?;
    let mut histogram = vec![0u64; GRID.cells()];
    for &(cos_theta, phi) in &tally.coordinates {
        histogram[GRID.cell_at(cos_theta, phi)] += 1;
    }
    // The no-sample draws are one more cell, expecting the density's shortfall, when the cells' integration knows it
    // to a tenth of its noise (a sharp lobe's float32 density at a grazing view is too noisy to integrate to
    // one sample in 10⁶: then the shortfall shows in every cell instead).
    let shortfall = (1.0 - cells.probability.iter().sum::<f64>()).max(0.0);
    let shortfall_known = shortfall_is_known(&cells, samples);
    let mut observed: Vec<u64> = histogram.clone();
    let mut probabilities: Vec<f64> = cells.probability.iter().map(|p| p.max(0.0)).collect();
    if shortfall_known {
        observed.push(tally.no_sample);
        probabilities.push(shortfall);
    }
    let chi_square = chi_square(&observed, &probabilities, samples);
    let no_sample_tested = shortfall_known;
    let worst_cells = worst_cells(&histogram, &cells.probability, samples);
    let n = samples as f64;
    let estimate = tally.weight_sum.map(|s| s / n);
    let standard_error =
        std::array::from_fn(|k| ((tally.weight_squares[k] / n - estimate[k] * estimate[k]).max(0.0) / n).sqrt());
    Ok(ViewOutcome {
        theta_o: view.0,
        phi_o: view.1,
        samples,
        histogram,
        cells,
        in_double,
        no_sample: tally.no_sample,
        no_sample_tested,
        invalid: tally.invalid,
        chi_square,
        worst_cells,
        estimate,
        standard_error,
    })
}

/// Whether the cells' integration knows the density's shortfall from 1 to a tenth of the no-sample count's noise.
fn shortfall_is_known(cells: &CellIntegrals, samples: u64) -> bool {
    let n = samples as f64;
    let shortfall = (1.0 - cells.probability.iter().sum::<f64>()).max(0.0) * n;
    let bound: f64 = cells.probability_error.iter().sum::<f64>() * n;
    bound <= (0.1 * shortfall.sqrt()).max(1.0)
}

/// What the draws add up to.
struct Tally {
    /// (cos θ, φ) of each sample returned.
    coordinates: Vec<(f64, f64)>,
    no_sample: u64,
    invalid: u64,
    weight_sum: [f64; 3],
    weight_squares: [f64; 3],
}

impl Tally {
    fn new() -> Self {
        Self { coordinates: Vec::new(), no_sample: 0, invalid: 0, weight_sum: [0.0; 3], weight_squares: [0.0; 3] }
    }

    fn add(&mut self, sample: &BrdfSample) {
        let finite = sample.wi.is_finite() && sample.pdf.is_finite() && sample.f.is_finite();
        if finite && sample.wi.z <= 0.0 {
            self.no_sample += 1;
            return;
        }
        if !finite || sample.pdf <= 0.0 {
            self.invalid += 1;
            return;
        }
        let wi = sample.wi.as_dvec3();
        self.coordinates.push(coordinates(wi));
        let cos_theta = wi.z / wi.length();
        for (k, f) in sample.f.to_array().into_iter().enumerate() {
            let weight = f as f64 * cos_theta / sample.pdf as f64;
            self.weight_sum[k] += weight;
            self.weight_squares[k] += weight * weight;
        }
    }
}

/// The cells weighing most in Pearson's statistic (or holding samples where nothing is expected), worst first.
fn worst_cells(histogram: &[u64], probability: &[f64], samples: u64) -> Vec<CellDeviation> {
    let mut deviations: Vec<(f64, CellDeviation)> = histogram
        .iter()
        .zip(probability)
        .enumerate()
        .map(|(cell, (&observed, &p))| {
            let expected = p.max(0.0) * samples as f64;
            let weight = if expected < 1e-9 {
                if observed > 0 {
                    f64::INFINITY
                } else {
                    0.0
                }
            } else {
                (observed as f64 - expected).powi(2) / expected
            };
            (weight, CellDeviation { cell, observed, expected })
        })
        .filter(|(weight, _)| *weight > 0.0)
        .collect();
    deviations.sort_by(|a, b| b.0.total_cmp(&a.0));
    deviations.into_iter().take(3).map(|(_, cell)| cell).collect()
}

/// The two-sided normal quantile z with P(|Z| > z) = `level`: erfc(z / √2) = Q(1/2, z² / 2), by bisection.
pub fn normal_quantile(level: f64) -> f64 {
    let (mut low, mut high) = (0.0f64, 40.0f64);
    for _ in 0..200 {
        let middle = 0.5 * (low + high);
        if gamma_q(0.5, middle * middle / 2.0) > level {
            low = middle;
        } else {
            high = middle;
        }
    }
    0.5 * (low + high)
}

/// The float evaluations' own error beside the integration's, where f_r and the density are float32: the
/// samples' weights always, the integrals where they were not taken in double precision.
const FLOAT_ERROR: f64 = 1e-4;

/// The same where the integrals were taken in double precision: the rounding of their sums over the pieces and
/// cells, which the integration's bound does not count (a density of exactly 1 sums to a few ulps above it).
const DOUBLE_ERROR: f64 = 1e-12;

/// A view's verdicts: χ², the density's integral and support, the samples, the estimator, energy.
fn view_verdicts(view: &ViewOutcome, level_each: f64) -> Vec<Verdict> {
    let at = Some((view.theta_o, view.phi_o));
    let verdict = |test, passed, detail| Verdict { test, view: at, passed, detail };
    let chi = &view.chi_square;
    let mut detail = format!(
        "χ² {:.1}, {} degrees of freedom, p {:.3e} (level {:.2e}), {} cells pooled",
        chi.statistic, chi.degrees_of_freedom, chi.p_value, level_each, chi.pooled
    );
    if chi.impossible > 0 {
        detail += &format!(", {} samples where the density is 0", chi.impossible);
    }
    if !view.no_sample_tested {
        detail += ", the no-sample count untested (the density's integral not known to one sample)";
    }
    let mut verdicts = vec![verdict("chi-square", chi.passes(level_each), detail)];
    let (integral, bound) = view.density_integral();
    let (integral_float_error, precision) =
        if view.in_double { (DOUBLE_ERROR, ", in double precision") } else { (FLOAT_ERROR, "") };
    verdicts.push(verdict(
        "density integral",
        integral <= 1.0 + bound + integral_float_error,
        format!("{integral:.6} ± {bound:.1e} (at most 1{precision})"),
    ));
    let below = view.density_below();
    verdicts.push(verdict("density below the surface", below == 0.0, format!("{below:.3e} (none)")));
    verdicts.push(verdict(
        "samples",
        view.invalid == 0,
        format!("{} of {} not finite or of density 0, {} no sample", view.invalid, view.samples, view.no_sample),
    ));
    let albedo = view.albedo();
    let z = normal_quantile(level_each);
    let mut worst = 0.0f64;
    for ((estimate, error), albedo) in view.estimate.iter().zip(view.standard_error).zip(albedo) {
        let allowed = z * error + view.cells.f_cos_error + FLOAT_ERROR * albedo.abs() + 1e-7;
        worst = worst.max((estimate - albedo).abs() / allowed);
    }
    let channels = |v: [f64; 3]| format!("{:.4} {:.4} {:.4}", v[0], v[1], v[2]);
    verdicts.push(verdict(
        "estimator",
        worst <= 1.0,
        format!(
            "mean f cos / pdf {} ± {} against the albedo {} ({:.2} of what the noise allows)",
            channels(view.estimate),
            channels(view.standard_error.map(|e| z * e)),
            channels(albedo),
            worst
        ),
    ));
    let largest = albedo.into_iter().fold(f64::MIN, f64::max);
    verdicts.push(verdict(
        "energy",
        largest <= 1.0 + view.cells.f_cos_error + integral_float_error,
        format!("directional albedo {} ± {:.1e} (at most 1)", channels(albedo), view.cells.f_cos_error),
    ));
    verdicts
}
