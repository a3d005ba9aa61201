//! The one solver every fit goes through: variable projection (Golub and Pereyra 1973) with bounded
//! Levenberg-Marquardt. At each point x of the searched parameters the colours a model is linear in come from
//! weighted linear least squares ([`least_squares`]), so the search runs over the nonlinear parameters alone;
//! that search is CMPFIT's bounded Levenberg-Marquardt (Markwardt 2009, MINPACK-1's algorithm with box
//! constraints) as the `rmpfit` crate has it, its Jacobian by forward differences of the probe's values.
//!
//! A model is not convex in its parameters: the search starts from several points (a scan of a one-parameter
//! model's range; an analytic model's own values and a Halton sequence over its box), and Levenberg-Marquardt
//! refines the best of them (the second best too, unless the best already reproduces the target). A point
//! where the model gives NaN or an infinity is a bad point, not an error: its residual is made large, and the
//! search steps back from it.

use glam::Vec3;
use rmpfit::{MPConfig, MPError, MPFitter, MPPar, MPResult, MPSide};

use super::family::{Bound, Family};
use super::{parameters, with_parameter, Determined, Fit, Values};
use crate::brdf::Brdf;
use crate::error::{Error, Result};

/// How many points of a one-parameter model's range are tried first (the best of them refined: 25 points leave
/// it one basin), and how many of an analytic model's best starts are refined.
const SCAN: usize = 24;
/// A built-in model's second parameter (the base colour model's metalness) is tried at `SCAN_SECOND + 1`
/// points of its range with each of the first's.
const SCAN_SECOND: usize = 4;
const REFINED: usize = 2;

/// A residual at most this fraction of the target's own size is the target reproduced to float32's precision
/// (a model fitted to its own tabulated copy ends at 2e-8 to 4e-6 of it): least squares' minimum, zero, is
/// reached, so no further start is refined.
const REPRODUCED: f64 = 1e-5;

/// Levenberg-Marquardt stops when a step changes the parameters by less than this fraction of their size. They
/// reach the GPU as float32, whose resolution is 6e-8 of a value: smaller steps cannot change what it
/// evaluates. With 1e-12 a search at an exact fit spent about 40% of its evaluations on such steps (a Ward
/// copy's two searches 28 and 31 evaluations, 15 and 18 at 1e-8, to the same chi-square).
const STEP_TOLERANCE: f64 = 1e-8;

/// The values of a fit: what is wanted at each sample, and the samples' weights (normalized to sum 1).
pub(super) struct Problem<'a> {
    pub family: &'a Family,
    pub wanted: &'a [[f64; 3]],
    pub weights: Vec<f64>,
}

impl<'a> Problem<'a> {
    pub fn new(family: &'a Family, wanted: &'a [[f64; 3]], weights: &[f64]) -> Self {
        let total: f64 = weights.iter().sum::<f64>().max(f64::MIN_POSITIVE);
        Self { family, wanted, weights: weights.iter().map(|w| w / total).collect() }
    }

    /// The residual entries: three a sample, one a channel.
    fn entries(&self) -> usize {
        3 * self.wanted.len()
    }

    /// The weighted root mean square of `fitted` - `wanted` over the samples and channels.
    pub fn rms(&self, fitted: &[[f64; 3]]) -> f64 {
        let mut deviates = vec![0.0; self.entries()];
        self.deviates(fitted, &mut deviates);
        deviates.iter().map(|d| d * d).sum::<f64>().sqrt()
    }

    /// sqrt(w) (fitted - wanted) per channel, over sqrt(3), so that their squares add up to the mean square
    /// over the three channels; a value that is not finite counts as a large difference. Each channel apart,
    /// not their luminance: a model searched in its colours would otherwise be free to trade one channel for
    /// another.
    fn deviates(&self, fitted: &[[f64; 3]], deviates: &mut [f64]) {
        const BAD: f64 = 1e6;
        for (s, (f, w)) in fitted.iter().zip(self.wanted).enumerate() {
            let root = self.weights[s].sqrt();
            for c in 0..3 {
                let d = f[c] - w[c];
                deviates[3 * s + c] = if d.is_finite() { root * d / 3f64.sqrt() } else { root * BAD };
            }
        }
    }

    /// The model at `x`, its colours by least squares, and its values at every sample.
    fn at(&self, x: &[f64], values: &mut Values) -> Result<(Brdf, Vec<[f64; 3]>)> {
        let projection = self.family.projection(x);
        let brdfs: Vec<Brdf> = projection.offset.iter().cloned().chain(projection.basis.iter().cloned()).collect();
        let mut evaluated = values(&brdfs)?;
        let offset = projection.offset.is_some().then(|| evaluated.remove(0));
        if let Some(offset) = &offset {
            for basis in &mut evaluated {
                for (b, o) in basis.iter_mut().zip(offset) {
                    *b = std::array::from_fn(|c| b[c] - o[c]);
                }
            }
        }
        let target: Vec<[f64; 3]> = match &offset {
            Some(o) => self.wanted.iter().zip(o).map(|(w, o)| std::array::from_fn(|c| w[c] - o[c])).collect(),
            None => self.wanted.to_vec(),
        };
        let coefficients = least_squares(&evaluated, &target, &self.weights);
        let brdf = self.family.assemble(x, &coefficients);
        // The model is linear in those colours: its values are the basis's, combined by its own coefficients
        // (those of the least squares, within the model's ranges).
        let own = self.family.coefficients(&brdf);
        let fitted = (0..self.wanted.len())
            .map(|s| {
                std::array::from_fn(|c| {
                    let base = offset.as_ref().map_or(0.0, |o| o[s][c]);
                    base + own.iter().zip(&evaluated).map(|(k, b)| f64::from(k[c]) * b[s][c]).sum::<f64>()
                })
            })
            .collect();
        Ok((brdf, fitted))
    }
}

/// The problem evaluated, each model counted for `progress`.
struct Evaluator<'e> {
    problem: &'e Problem<'e>,
    values: &'e mut Values<'e>,
    progress: &'e mut dyn FnMut(usize),
    evaluated: usize,
}

impl Evaluator<'_> {
    /// The model at `x`, its colours by least squares, and its values at every sample.
    fn at(&mut self, x: &[f64]) -> Result<(Brdf, Vec<[f64; 3]>)> {
        self.evaluated += 1;
        (self.progress)(self.evaluated);
        self.problem.at(x, self.values)
    }

    /// The residual at `x`: infinite where the model gives a value that is not finite.
    fn residual(&mut self, x: &[f64]) -> Result<f64> {
        let (_, fitted) = self.at(x)?;
        let residual = self.problem.rms(&fitted);
        Ok(if residual.is_finite() { residual } else { f64::INFINITY })
    }
}

/// Fits the problem's family, telling `progress` how many models it has evaluated.
///
/// # Errors
/// What `values` returns.
pub(super) fn solve(problem: &Problem, values: &mut Values, progress: &mut dyn FnMut(usize)) -> Result<Fit> {
    let bounds = problem.family.bounds();
    let mut evaluator = Evaluator { problem, values, progress, evaluated: 0 };
    let zero = vec![[0.0; 3]; problem.wanted.len()];
    let target_rms = problem.rms(&zero);
    let mut x = Vec::new();
    if !bounds.is_empty() {
        let mut scored = Vec::new();
        for start in starts(problem.family, &bounds) {
            scored.push((evaluator.residual(&start)?, start));
        }
        scored.sort_by(|a, b| a.0.total_cmp(&b.0));
        let mut best = (f64::INFINITY, scored[0].1.clone());
        let refined = if problem.family.start().is_none() { 1 } else { REFINED };
        for (_, start) in scored.into_iter().take(refined) {
            let refined = refine(&mut evaluator, &bounds, &start)?;
            if refined.0 < best.0 {
                best = refined;
            }
            if best.0 <= REPRODUCED * target_rms {
                break;
            }
        }
        x = best.1;
    }
    let (brdf, fitted) = evaluator.at(&x)?;
    let parameters = determination(problem, &brdf, &fitted, evaluator.values)?;
    Ok(Fit { residual: problem.rms(&fitted), target_rms, brdf, parameters })
}

/// Where the search starts: a built-in model's range scanned at `SCAN + 1` points (by `SCAN_SECOND + 1` of a
/// second parameter's each); an analytic model's own values, then a Halton sequence over its box (eight
/// points a parameter, at most 48).
fn starts(family: &Family, bounds: &[Bound]) -> Vec<Vec<f64>> {
    let within = |k: usize, u: f64| {
        let (low, high) = bounds[k].scaled();
        bounds[k].unscaled(low + (high - low) * u).clamp(bounds[k].low, bounds[k].high)
    };
    match family.start() {
        None => {
            let points = |k: usize, steps: usize| (0..=steps).map(move |i| within(k, i as f64 / steps as f64));
            let mut starts: Vec<Vec<f64>> = points(0, SCAN).map(|a| vec![a]).collect();
            if bounds.len() > 1 {
                starts = starts.iter().flat_map(|s| points(1, SCAN_SECOND).map(move |b| vec![s[0], b])).collect();
            }
            starts
        }
        Some(own) => {
            let count = (8 * bounds.len()).min(48);
            let mut starts = vec![own];
            starts.extend(
                (1..=count)
                    .map(|i| (0..bounds.len()).map(|k| within(k, halton(i, PRIMES[k % PRIMES.len()]))).collect()),
            );
            starts
        }
    }
}

/// The Halton sequence's bases, one a searched parameter (the Disney BRDF searches 13).
const PRIMES: [usize; 16] = [2, 3, 5, 7, 11, 13, 17, 19, 23, 29, 31, 37, 41, 43, 47, 53];

/// Point `index` of the van der Corput sequence in `base` (Halton 1960, one coordinate of his sequence).
fn halton(mut index: usize, base: usize) -> f64 {
    let (mut value, mut scale) = (0.0, 1.0);
    while index > 0 {
        scale /= base as f64;
        value += scale * (index % base) as f64;
        index /= base;
    }
    value
}

/// Levenberg-Marquardt from `start` within `bounds`, on their scales, its Jacobian by forward differences of
/// 1e-4 of each range (backward at the upper bound): the best point it evaluated, and its residual.
fn refine(evaluator: &mut Evaluator, bounds: &[Bound], start: &[f64]) -> Result<(f64, Vec<f64>)> {
    let parameters: Vec<MPPar> = bounds
        .iter()
        .map(|bound| {
            let (low, high) = bound.scaled();
            MPPar {
                limited_low: true,
                limited_up: true,
                limit_low: low,
                limit_up: high,
                step: 1e-4 * (high - low),
                side: MPSide::Auto,
                ..MPPar::new()
            }
        })
        .collect();
    let config = MPConfig { ftol: 1e-12, xtol: STEP_TOLERANCE, gtol: 1e-14, max_iter: 200, ..MPConfig::new() };
    let mut search = Search { evaluator, bounds, parameters, config, failure: None, best: None };
    let mut t: Vec<f64> = start.iter().zip(bounds).map(|(&x, b)| b.to_scale(x)).collect();
    let outcome = search.mpfit(&mut t);
    if let Some(error) = search.failure.take() {
        return Err(error);
    }
    // A search that could not step (every step a bad point) keeps the best point it saw.
    match outcome {
        Ok(status) => log::debug!(
            "the search from {start:?}: {:?} (chi-square {:e} from {:e}) after {} iterations, {} evaluations",
            status.success,
            status.best_norm,
            status.orig_norm,
            status.n_iter,
            status.n_fev
        ),
        Err(e) => log::debug!("the search from {start:?} stopped: {}", mp_error(&e)),
    }
    Ok(match search.best.take() {
        Some((residual, t)) => (residual, search.unscaled(&t)),
        None => (f64::INFINITY, start.to_vec()),
    })
}

fn mp_error(e: &MPError) -> &'static str {
    match e {
        MPError::Input => "input",
        MPError::Nan => "not finite values",
        MPError::Empty => "no data",
        MPError::NoFree => "no free parameter",
        MPError::InitBounds => "a start outside the bounds",
        MPError::Bounds => "bounds inconsistent",
        MPError::DoF => "too few data",
        MPError::Eval => "the evaluation failed",
    }
}

/// One Levenberg-Marquardt search: rmpfit's user of the problem, on the parameters' scales.
struct Search<'s, 'e> {
    evaluator: &'s mut Evaluator<'e>,
    bounds: &'s [Bound],
    parameters: Vec<MPPar>,
    config: MPConfig,
    /// The error that stopped an evaluation, returned once the search does.
    failure: Option<Error>,
    /// The best point evaluated: its residual and its parameters on their scales.
    best: Option<(f64, Vec<f64>)>,
}

impl Search<'_, '_> {
    /// The parameters at `t` on their scales, within their bounds.
    fn unscaled(&self, t: &[f64]) -> Vec<f64> {
        t.iter().zip(self.bounds).map(|(&t, b)| b.unscaled(t).clamp(b.low, b.high)).collect()
    }
}

impl MPFitter for Search<'_, '_> {
    fn eval(&mut self, t: &[f64], deviates: &mut [f64]) -> MPResult<()> {
        let x = self.unscaled(t);
        match self.evaluator.at(&x) {
            Ok((_, fitted)) => {
                self.evaluator.problem.deviates(&fitted, deviates);
                let residual = deviates.iter().map(|d| d * d).sum::<f64>().sqrt();
                if self.best.as_ref().is_none_or(|b| residual < b.0) {
                    self.best = Some((residual, t.to_vec()));
                }
                Ok(())
            }
            Err(e) => {
                self.failure = Some(e);
                Err(MPError::Eval)
            }
        }
    }

    fn number_of_points(&self) -> usize {
        self.evaluator.problem.entries()
    }

    fn config(&self) -> &MPConfig {
        &self.config
    }

    fn parameters(&self) -> &[MPPar] {
        &self.parameters
    }
}

/// Per channel, the coefficients c minimising sum of w (sum_k c_k basis_k - wanted)^2 (normal equations,
/// solved by Gauss-Jordan elimination on the diagonal, which the symmetric positive semi-definite matrix
/// allows). A basis function the samples cannot tell from the ones before it (its pivot under 1e-9 of the
/// largest diagonal entry: Cook-Torrance's S0, f0 = 0, where the Fresnel term does not vary over the samples)
/// is left out: its coefficient is 0.
pub(super) fn least_squares(basis: &[Vec<[f64; 3]>], wanted: &[[f64; 3]], weights: &[f64]) -> Vec<Vec3> {
    let k = basis.len();
    let mut coefficients = vec![Vec3::ZERO; k];
    for channel in 0..3 {
        let mut a = vec![vec![0.0f64; k + 1]; k];
        for (i, row) in a.iter_mut().enumerate() {
            for j in 0..k {
                row[j] = (0..wanted.len()).map(|s| weights[s] * basis[i][s][channel] * basis[j][s][channel]).sum();
            }
            row[k] = (0..wanted.len()).map(|s| weights[s] * basis[i][s][channel] * wanted[s][channel]).sum();
        }
        let negligible = 1e-9 * (0..k).map(|i| a[i][i]).fold(1e-300, f64::max);
        for column in 0..k {
            if a[column][column].is_nan() || a[column][column].abs() < negligible {
                a[column].iter_mut().for_each(|v| *v = 0.0);
                a.iter_mut().for_each(|row| row[column] = 0.0);
                continue;
            }
            let pivot_row = a[column].clone();
            for (row, values) in a.iter_mut().enumerate() {
                if row != column {
                    let factor = values[column] / pivot_row[column];
                    for (value, pivot) in values.iter_mut().zip(&pivot_row).skip(column) {
                        *value -= factor * pivot;
                    }
                }
            }
        }
        for (i, c) in coefficients.iter_mut().enumerate() {
            if a[i][i].abs() >= negligible {
                c[channel] = (a[i][k] / a[i][i]) as f32;
            }
        }
    }
    coefficients
}

/// Each free parameter of `brdf` (the family's, every one of a built-in model's) with its standard error per
/// component: the Gauss-Newton estimate sqrt(s^2 (J^T W J)^-1), J the change of the model's values with each
/// component (central differences of the probe's values, one-sided at a bound), W the samples' weights (their
/// mean 1) and s^2 the weighted residuals' variance; `None` for a component the samples do not determine.
/// `fitted` is the model's values.
///
/// # Errors
/// What `values` returns.
pub(super) fn determination(
    problem: &Problem,
    brdf: &Brdf,
    fitted: &[[f64; 3]],
    values: &mut Values,
) -> Result<Vec<Determined>> {
    let free = problem.family.free_parameters();
    let tied = problem.family.tied();
    let follower = |name: &str| tied.is_some_and(|(_, follower)| follower == name);
    let parameters: Vec<(String, Vec<f32>)> = parameters(brdf)
        .into_iter()
        .filter(|(name, _)| free.as_ref().is_none_or(|f| f.contains(name)) && !follower(name))
        .collect();
    // A leader's follower moves with it.
    let with_parameter = |brdf: &Brdf, name: &str, c: usize, value: f32| match tied {
        Some((leader, follower)) if leader == name => {
            with_parameter(&with_parameter(brdf, name, c, value), follower, c, value)
        }
        _ => with_parameter(brdf, name, c, value),
    };
    // One scalar per parameter component: (parameter, component); each moved up and down by a step, the
    // value it then has read back (an analytic model's stays within its range).
    let scalars: Vec<(usize, usize)> =
        parameters.iter().enumerate().flat_map(|(p, (_, v))| (0..v.len()).map(move |c| (p, c))).collect();
    let mut perturbed = Vec::new();
    let mut steps = Vec::new();
    for &(p, c) in &scalars {
        let (name, value) = (&parameters[p].0, parameters[p].1[c]);
        let step = 1e-3 * value.abs().max(0.05);
        let (up, down) = (with_parameter(brdf, name, c, value + step), with_parameter(brdf, name, c, value - step));
        let moved = |b: &Brdf| self::parameters(b).into_iter().find(|(n, _)| n == name).map_or(value, |(_, v)| v[c]);
        steps.push(f64::from(moved(&up)) - f64::from(moved(&down)));
        perturbed.extend([up, down]);
    }
    let evaluated = values(&perturbed)?;
    let mut rows = vec![0.0; problem.entries()];
    let mut deviates = |at: &[[f64; 3]]| {
        problem.deviates(at, &mut rows);
        rows.clone()
    };
    let at = deviates(fitted);
    let columns: Vec<Vec<f64>> = steps
        .iter()
        .enumerate()
        .map(|(k, &step)| {
            let (up, down) = (deviates(&evaluated[2 * k]), deviates(&evaluated[2 * k + 1]));
            up.iter().zip(&down).map(|(u, d)| if step == 0.0 { 0.0 } else { (u - d) / step }).collect()
        })
        .collect();
    // The deviates weigh each entry by sqrt(w), the weights summing to 1: the sum of squares is the mean
    // square, which over the degrees of freedom per entry is the variance.
    let entries = problem.entries() as f64;
    let freedom = (entries - scalars.len() as f64).max(1.0);
    let variance = at.iter().map(|d| d * d).sum::<f64>() * entries / freedom;
    let scaled: Vec<Vec<f64>> = columns.iter().map(|c| c.iter().map(|v| v * entries.sqrt()).collect()).collect();
    let errors = standard_errors(&scaled, variance);
    let mut determined: Vec<Determined> = parameters
        .iter()
        .map(|(name, values)| Determined {
            name: name.clone(),
            values: values.clone(),
            errors: vec![None; values.len()],
        })
        .collect();
    for (&(p, c), error) in scalars.iter().zip(errors) {
        determined[p].errors[c] = error;
    }
    if let Some((leader, follower)) = tied {
        if let Some(lead) = determined.iter().find(|d| d.name == leader) {
            determined.push(Determined { name: follower.into(), ..lead.clone() });
        }
    }
    Ok(determined)
}

/// sqrt(variance (J^T J)^-1) on the diagonal, J given by its columns; None for a column the others (or
/// nothing) account for: the matrix is inverted over the columns that keep it well conditioned.
pub(super) fn standard_errors(columns: &[Vec<f64>], variance: f64) -> Vec<Option<f64>> {
    let n = columns.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let gram: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| dot(&columns[i], &columns[j])).collect()).collect();
    // Gauss-Jordan with the columns as pivots in turn; a pivot below 1e-10 of its diagonal is a parameter
    // the samples do not determine (its column lies in the others' span): left out.
    let mut a: Vec<Vec<f64>> = gram.clone();
    let mut inverse: Vec<Vec<f64>> = (0..n).map(|i| (0..n).map(|j| f64::from(u8::from(i == j))).collect()).collect();
    let mut kept = vec![false; n];
    for p in 0..n {
        if a[p][p].is_nan() || a[p][p] <= 1e-10 * gram[p][p] || gram[p][p] <= 0.0 {
            continue;
        }
        kept[p] = true;
        let pivot = a[p][p];
        for j in 0..n {
            a[p][j] /= pivot;
            inverse[p][j] /= pivot;
        }
        for i in 0..n {
            if i != p {
                let factor = a[i][p];
                for j in 0..n {
                    a[i][j] -= factor * a[p][j];
                    inverse[i][j] -= factor * inverse[p][j];
                }
            }
        }
    }
    (0..n).map(|i| kept[i].then(|| (variance * inverse[i][i]).max(0.0).sqrt())).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn standard_errors_of_a_line_by_hand() {
        // y = a + b x at x = 0, 1, 2 with variance 1: (J^T J)^-1 = [[5, -3], [-3, 3]] / 6.
        let columns = vec![vec![1.0, 1.0, 1.0], vec![0.0, 1.0, 2.0]];
        let errors = standard_errors(&columns, 1.0);
        assert!((errors[0].unwrap() - (5.0f64 / 6.0).sqrt()).abs() < 1e-12, "{errors:?}");
        assert!((errors[1].unwrap() - 0.5f64.sqrt()).abs() < 1e-12, "{errors:?}");
        // A second column twice the first is not determined.
        let errors = standard_errors(&[vec![1.0, 2.0], vec![2.0, 4.0]], 1.0);
        assert!(errors[0].is_some() && errors[1].is_none(), "{errors:?}");
    }

    /// The evaluations of a fit of a one-parameter analytic model to `wanted`, its values a Gaussian bump
    /// centred at the parameter `a` over 64 samples (made by `bump`, not by the GPU): the values of `a` the
    /// solver asked for, in order.
    fn searched_points(wanted: &[[f64; 3]], bump: &dyn Fn(f64, usize) -> f64) -> Vec<f32> {
        let text = "analytic\n::begin parameters\nfloat a 0 1 0.9\n::end parameters\n::begin shader\n\
                    vec3 BRDF(vec3 L, vec3 V, vec3 N, vec3 X, vec3 Y) { return vec3(a); }\n::end shader\n";
        let model = crate::brdf::AnalyticModel::from_text(std::path::Path::new("bump.brdf"), text.into()).unwrap();
        let family = super::super::family::analytic_family(
            crate::brdf::Analytic::defaults(std::sync::Arc::new(model)),
            &[],
            true,
        );
        let problem = Problem::new(&family, wanted, &vec![1.0; wanted.len()]);
        let mut asked = Vec::new();
        let mut values = |brdfs: &[Brdf]| {
            Ok(brdfs
                .iter()
                .map(|b| {
                    let a = parameters(b)[0].1[0];
                    asked.push(a);
                    (0..wanted.len()).map(|s| [bump(f64::from(a), s); 3]).collect()
                })
                .collect())
        };
        solve(&problem, &mut values, &mut |_| {}).unwrap();
        asked
    }

    #[test]
    fn the_second_start_is_refined_unless_the_best_reproduces_the_target() {
        let bump = |a: f64, s: usize| (-((s as f64 / 63.0 - a).powi(2)) / 0.02).exp();
        // The starts: the model's own a = 0.9, then Halton's 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875,
        // 0.0625. For a bump at 0.3 the best is 0.25 and the second 0.375, where a second search would start
        // (Levenberg-Marquardt evaluates its start first).
        let second = |asked: &[f32]| asked.iter().filter(|&&a| (a - 0.375).abs() < 1e-6).count();
        // Its centre between two float32 values: reproduced to their resolution, not to zero.
        let exact: Vec<[f64; 3]> = (0..64).map(|s| [bump(0.300_000_01, s); 3]).collect();
        let asked = searched_points(&exact, &bump);
        assert_eq!(asked[..9], [0.9, 0.5, 0.25, 0.75, 0.125, 0.625, 0.375, 0.875, 0.0625]);
        assert_eq!(second(&asked), 1, "the target was reproduced, yet the second start was refined: {asked:?}");
        // A target no bump reproduces (a ripple over it): both starts refined.
        let rippled: Vec<[f64; 3]> =
            exact.iter().enumerate().map(|(s, v)| [v[0] + 0.01 * (s as f64).sin(); 3]).collect();
        let asked = searched_points(&rippled, &bump);
        assert_eq!(second(&asked), 2, "the second start was not refined: {asked:?}");
    }

    #[test]
    fn halton_points_are_the_radical_inverses() {
        assert_eq!([1, 2, 3, 4].map(|i| halton(i, 2)), [0.5, 0.25, 0.75, 0.125]);
        assert!((halton(1, 3) - 1.0 / 3.0).abs() < 1e-15 && (halton(4, 3) - 4.0 / 9.0).abs() < 1e-15);
    }
}
