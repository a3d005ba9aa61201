//! What a fit varies of a model: its nonlinear parameters, each within bounds (the solver's), and the colours
//! it solves by linear least squares at every point of the search (variable projection).
//!
//! The course's models are linear in their colours: f = sum over k of c_k b_k, the b_k the model with unit
//! colours, so only their one shape parameter is searched (and the metalness of Cook-Torrance with one base
//! colour, [`BASE_COLOUR_MODEL`], where the colour multiplies both lobes but for the metal's S0). An analytic
//! model (a `.brdf` file) is searched over every float parameter not held, within the file's range; its
//! colours are solved linearly when the model is linear in them (found by evaluating it, [`linear_colours`]),
//! and searched as three parameters each in [0, 1] otherwise; bools and held parameters keep their values.

use glam::Vec3;

use super::{Values, BASE_COLOUR_MODEL};
use crate::brdf::{Analytic, Brdf, DiffuseModel, ParameterKind, ParameterValue};
use crate::error::Result;

/// A nonlinear parameter's bounds, and whether it is searched on a log scale (a shininess from 0.5 to 20000).
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct Bound {
    pub low: f64,
    pub high: f64,
    pub log: bool,
}

impl Bound {
    /// The bounds on the scale the solver searches on.
    pub fn scaled(self) -> (f64, f64) {
        (self.to_scale(self.low), self.to_scale(self.high))
    }

    pub fn to_scale(self, x: f64) -> f64 {
        if self.log {
            x.ln()
        } else {
            x
        }
    }

    pub fn unscaled(self, t: f64) -> f64 {
        if self.log {
            t.exp()
        } else {
            t
        }
    }
}

/// What one point of the search evaluates: the model is `offset` (zero when `None`) plus the per-channel
/// combination of the `basis` brdfs' values, each taken less the offset's when there is one (a basis brdf is
/// then the offset with one colour made white).
pub(super) struct Projection {
    pub offset: Option<Brdf>,
    pub basis: Vec<Brdf>,
}

/// A model as a fit varies it.
pub(super) enum Family {
    /// One of the course's models (or [`BASE_COLOUR_MODEL`]), its shape parameters searched (Lambert has
    /// none).
    BuiltIn { name: &'static str, shape: Vec<(&'static str, Bound)>, diffuse: DiffuseModel },
    /// A `.brdf` file.
    Analytic(AnalyticFamily),
}

/// What a fit varies of an analytic model.
pub(super) struct AnalyticFamily {
    /// The starting values, which held parameters keep.
    start: Analytic,
    /// The parameters searched: a float, or one component of a colour.
    searched: Vec<(String, Option<usize>, Bound)>,
    /// The colours solved by least squares.
    linear: Vec<String>,
}

/// The shape parameters of each built-in model fitted, their bounds and scales.
pub(super) fn built_in_shape(name: &str) -> Option<Vec<(&'static str, Bound)>> {
    let bound = |low, high, log| Bound { low, high, log };
    let roughness = ("roughness", bound(0.02, 1.0, true));
    Some(match name {
        "lambert" => vec![],
        "oren-nayar" => vec![("sigma", bound(0.0, 1.5, false))],
        "phong" | "blinn-phong" => vec![("shininess", bound(0.5, 20000.0, true))],
        "cook-torrance" => vec![roughness],
        BASE_COLOUR_MODEL => vec![roughness, ("metalness", bound(0.0, 1.0, false))],
        _ => return None,
    })
}

impl Family {
    /// The built-in model `name` (its Cook-Torrance diffuse lobe `diffuse`).
    pub fn built_in(name: &'static str, diffuse: DiffuseModel) -> Option<Self> {
        built_in_shape(name).map(|shape| Family::BuiltIn { name, shape, diffuse })
    }

    /// The bounds of the parameters searched, in order.
    pub fn bounds(&self) -> Vec<Bound> {
        match self {
            Family::BuiltIn { shape, .. } => shape.iter().map(|(_, bound)| *bound).collect(),
            Family::Analytic(family) => family.searched.iter().map(|(_, _, bound)| *bound).collect(),
        }
    }

    /// The parameters searched at the starting values (an analytic model's own; none for a built-in model,
    /// whose search starts from a scan of its range).
    pub fn start(&self) -> Option<Vec<f64>> {
        match self {
            Family::BuiltIn { .. } => None,
            Family::Analytic(family) => Some(
                family
                    .searched
                    .iter()
                    .map(|(name, component, bound)| {
                        let value = match (family.start.value(name), component) {
                            (Some(ParameterValue::Float(v)), _) => f64::from(v),
                            (Some(ParameterValue::Color(c)), Some(k)) => f64::from(c[*k]),
                            _ => bound.low,
                        };
                        value.clamp(bound.low, bound.high)
                    })
                    .collect(),
            ),
        }
    }

    /// What the search evaluates at `x` (the searched parameters' values).
    pub fn projection(&self, x: &[f64]) -> Projection {
        match self {
            Family::BuiltIn { name, diffuse, .. } => built_in_projection(name, x, *diffuse),
            Family::Analytic(family) => {
                let at = family.at(x);
                if family.linear.is_empty() {
                    return Projection { offset: Some(at), basis: Vec::new() };
                }
                let dark = family.linear.iter().fold(at, |m, name| with_colour(&m, name, Vec3::ZERO));
                let basis = family.linear.iter().map(|name| with_colour(&dark, name, Vec3::ONE)).collect();
                Projection { offset: Some(dark), basis }
            }
        }
    }

    /// The model at `x` with the per-channel coefficients `c` of [`Family::projection`]'s basis, within the
    /// model's ranges.
    pub fn assemble(&self, x: &[f64], c: &[Vec3]) -> Brdf {
        match self {
            Family::BuiltIn { name, diffuse, .. } => built_in_assemble(name, x, *diffuse, c),
            Family::Analytic(family) => {
                let at = family.at(x);
                family.linear.iter().zip(c).fold(at, |m, (name, colour)| with_colour(&m, name, colour.max(Vec3::ZERO)))
            }
        }
    }

    /// The coefficients of the basis that make `brdf` (of this family, assembled): [`Family::assemble`]
    /// undone, so that the model's values are the basis's combined.
    pub fn coefficients(&self, brdf: &Brdf) -> Vec<Vec3> {
        match (self, brdf) {
            (Family::Analytic(family), Brdf::Analytic(material)) => family
                .linear
                .iter()
                .map(|name| match material.value(name) {
                    Some(ParameterValue::Color(c)) => c,
                    _ => Vec3::ZERO,
                })
                .collect(),
            (Family::BuiltIn { name: BASE_COLOUR_MODEL, .. }, Brdf::CookTorrance { f0, .. }) => vec![*f0],
            (_, brdf) => built_in_coefficients(brdf),
        }
    }

    /// A parameter that follows another, as (leader, follower): the base colour model's kd is its f0. The
    /// fit's standard errors move them together, and give the follower the leader's.
    pub fn tied(&self) -> Option<(&'static str, &'static str)> {
        matches!(self, Family::BuiltIn { name: BASE_COLOUR_MODEL, .. }).then_some(("f0", "kd"))
    }

    /// The parameters a fit determines, by [`super::parameters`]'s names: a built-in model's every one, an
    /// analytic model's searched and solved ones.
    pub fn free_parameters(&self) -> Option<Vec<String>> {
        match self {
            Family::BuiltIn { .. } => None,
            Family::Analytic(family) => {
                let mut names: Vec<String> = family.searched.iter().map(|(name, _, _)| name.clone()).collect();
                names.extend(family.linear.iter().cloned());
                names.dedup();
                Some(names)
            }
        }
    }
}

impl AnalyticFamily {
    /// The starting material with the searched parameters at `x`.
    fn at(&self, x: &[f64]) -> Brdf {
        let mut material = self.start.clone();
        for ((name, component, _), &value) in self.searched.iter().zip(x) {
            let value = match (component, material.value(name)) {
                (Some(k), Some(ParameterValue::Color(mut c))) => {
                    c[*k] = value as f32;
                    ParameterValue::Color(c)
                }
                _ => ParameterValue::Float(value as f32),
            };
            // Within its bounds, every value is one the material takes.
            material = material.clone().with(name, value).unwrap_or(material);
        }
        Brdf::Analytic(material)
    }
}

/// An analytic material with colour `name` set to `colour`.
fn with_colour(brdf: &Brdf, name: &str, colour: Vec3) -> Brdf {
    match brdf {
        Brdf::Analytic(m) => Brdf::Analytic(m.clone().with(name, ParameterValue::Color(colour)).unwrap_or(m.clone())),
        other => other.clone(),
    }
}

/// The family of an analytic model started from `start`, `held` parameters kept: its float parameters of a
/// range searched (on a log scale where the range spans a factor of 100 or more above 0), its colours solved
/// linearly where `linear` (see [`linear_colours`]) says the model is linear in them, searched in [0, 1]
/// otherwise.
pub(super) fn analytic_family(start: Analytic, held: &[String], linear: bool) -> Family {
    let mut searched = Vec::new();
    let mut colours = Vec::new();
    for (parameter, _) in start.values() {
        if held.contains(&parameter.name) {
            continue;
        }
        match parameter.kind {
            ParameterKind::Float { min, max, .. } if max > min => {
                let (low, high) = (f64::from(min), f64::from(max));
                let log = low > 0.0 && high / low >= 100.0;
                searched.push((parameter.name.clone(), None, Bound { low, high, log }));
            }
            ParameterKind::Color { .. } => colours.push(parameter.name.clone()),
            _ => {}
        }
    }
    if !linear {
        for name in &colours {
            for k in 0..3 {
                searched.push((name.clone(), Some(k), Bound { low: 0.0, high: 1.0, log: false }));
            }
        }
    }
    let linear_colours = if linear { colours } else { Vec::new() };
    Family::Analytic(AnalyticFamily { start, searched, linear: linear_colours })
}

/// Whether the analytic material `start` is linear in its colours not `held`, channel by channel, wherever
/// its other parameters are: tried at `start` and at its floats not held a third and two thirds of the way
/// through their ranges (at the file's defaults the Disney BRDF's tints are 0 and it is linear in its base
/// colour; with them it is not). `values` evaluates brdfs at some samples.
///
/// # Errors
/// What `values` returns.
pub(super) fn linear_colours(start: &Analytic, held: &[String], values: &mut Values) -> Result<bool> {
    let colours: Vec<String> = start
        .values()
        .filter(|(p, _)| matches!(p.kind, ParameterKind::Color { .. }) && !held.contains(&p.name))
        .map(|(p, _)| p.name.clone())
        .collect();
    if colours.is_empty() {
        return Ok(true);
    }
    let within = |fraction: f32| {
        let mut point = start.clone();
        for (parameter, _) in start.values() {
            if let ParameterKind::Float { min, max, .. } = parameter.kind {
                if !held.contains(&parameter.name) {
                    let value = ParameterValue::Float(min + fraction * (max - min));
                    point = point.clone().with(&parameter.name, value).unwrap_or(point);
                }
            }
        }
        point
    };
    for point in [start.clone(), within(1.0 / 3.0), within(2.0 / 3.0)] {
        if !linear_at(&point, &colours, values)? {
            return Ok(false);
        }
    }
    Ok(true)
}

/// Whether `start` is linear in `colours`: the model with those colours dark, each white, each twice as
/// white, each red only, and each pair white together, compared (to 1e-3 of the largest change a colour
/// makes). A model is then f = f(dark) + sum over colours of c (f(white) - f(dark)) per channel.
fn linear_at(start: &Analytic, colours: &[String], values: &mut Values) -> Result<bool> {
    let base = Brdf::Analytic(start.clone());
    let dark = colours.iter().fold(base, |m, name| with_colour(&m, name, Vec3::ZERO));
    let mut brdfs = vec![dark.clone()];
    for name in colours {
        brdfs.push(with_colour(&dark, name, Vec3::ONE));
        brdfs.push(with_colour(&dark, name, Vec3::splat(2.0)));
        brdfs.push(with_colour(&dark, name, Vec3::X));
    }
    for i in 0..colours.len() {
        for j in i + 1..colours.len() {
            brdfs.push(with_colour(&with_colour(&dark, &colours[i], Vec3::ONE), &colours[j], Vec3::ONE));
        }
    }
    let v = values(&brdfs)?;
    let zero = &v[0];
    let (white, double, red) = (|j: usize| &v[1 + 3 * j], |j: usize| &v[2 + 3 * j], |j: usize| &v[3 + 3 * j]);
    let scale = (0..colours.len())
        .flat_map(|j| white(j).iter().zip(zero).flat_map(|(w, z)| (0..3).map(move |c| (w[c] - z[c]).abs())))
        .fold(0.0, f64::max);
    if !scale.is_finite() || scale == 0.0 {
        return Ok(false);
    }
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-3 * scale;
    for j in 0..colours.len() {
        for (s, zero) in zero.iter().enumerate() {
            for (c, &z) in zero.iter().enumerate() {
                let w = white(j)[s][c];
                let red_expected = if c == 0 { w } else { z };
                if !close(double(j)[s][c], 2.0 * w - z) || !close(red(j)[s][c], red_expected) {
                    return Ok(false);
                }
            }
        }
    }
    let mut pair = 1 + 3 * colours.len();
    for i in 0..colours.len() {
        for j in i + 1..colours.len() {
            let ok = (0..zero.len())
                .all(|s| (0..3).all(|c| close(v[pair][s][c], white(i)[s][c] + white(j)[s][c] - zero[s][c])));
            if !ok {
                return Ok(false);
            }
            pair += 1;
        }
    }
    Ok(true)
}

/// A built-in model's projection at `x` (its shape parameters): the model with unit colours, one brdf per
/// coefficient, and for the base colour model the part no colour multiplies.
fn built_in_projection(name: &str, x: &[f64], diffuse: DiffuseModel) -> Projection {
    let (zero, one) = (Vec3::ZERO, Vec3::ONE);
    let shape = x.first().copied().unwrap_or(0.0) as f32;
    let lobe = |kd: Vec3, metalness: f32, f0: Vec3| Brdf::CookTorrance { kd, f0, roughness: shape, metalness, diffuse };
    let basis = match name {
        "lambert" => vec![Brdf::Lambert { kd: one }],
        "oren-nayar" => vec![Brdf::OrenNayar { kd: one, sigma: shape }],
        "phong" => vec![Brdf::Lambert { kd: one }, Brdf::Phong { kd: zero, ks: one, shininess: shape }],
        "blinn-phong" => vec![Brdf::Lambert { kd: one }, Brdf::BlinnPhong { kd: zero, ks: one, shininess: shape }],
        BASE_COLOUR_MODEL => {
            // (1 - m) c f_diffuse + m (S0 + c (S1 - S0)) = m S0 + c ((1 - m) f_diffuse + m (S1 - S0)): the
            // offset m S0 (c = 0), and the model with c = 1 less it.
            let metalness = x.get(1).copied().unwrap_or(0.0) as f32;
            return Projection { offset: Some(lobe(zero, metalness, zero)), basis: vec![lobe(one, metalness, one)] };
        }
        // (1 - m) kd f_diffuse + m (S0 + f0 (S1 - S0)): Schlick's F is affine in f0, so the specular lobe is S0
        // (f0 = 0) plus f0 times (S1 - S0) (S1: f0 = 1).
        _ => vec![lobe(one, 0.0, zero), lobe(one, 1.0, zero), lobe(one, 1.0, one)],
    };
    Projection { offset: None, basis }
}

/// The per-channel coefficients of [`built_in_projection`]'s basis that make `brdf`.
fn built_in_coefficients(brdf: &Brdf) -> Vec<Vec3> {
    match *brdf {
        Brdf::Lambert { kd } | Brdf::OrenNayar { kd, .. } => vec![kd],
        Brdf::Phong { kd, ks, .. } | Brdf::BlinnPhong { kd, ks, .. } => vec![kd, ks],
        Brdf::CookTorrance { kd, f0, metalness: m, .. } => vec![(1.0 - m) * kd, m * (Vec3::ONE - f0), m * f0],
        Brdf::Measured(_) | Brdf::Analytic(_) => Vec::new(),
    }
}

/// A built-in model from its shape parameters `x` and per-channel coefficients of [`built_in_projection`]'s
/// basis (the last two of Cook-Torrance's are S0 and S1, recombined as metalness and f0 here).
fn built_in_assemble(name: &str, x: &[f64], diffuse: DiffuseModel, c: &[Vec3]) -> Brdf {
    let unit = |v: Vec3| v.clamp(Vec3::ZERO, Vec3::ONE);
    let shape = x.first().copied().unwrap_or(0.0) as f32;
    match name {
        "lambert" => Brdf::Lambert { kd: unit(c[0]) },
        "oren-nayar" => Brdf::OrenNayar { kd: unit(c[0]), sigma: shape },
        "phong" => Brdf::Phong { kd: unit(c[0]), ks: c[1].max(Vec3::ZERO), shininess: shape },
        "blinn-phong" => Brdf::BlinnPhong { kd: unit(c[0]), ks: c[1].max(Vec3::ZERO), shininess: shape },
        BASE_COLOUR_MODEL => {
            let metalness = x.get(1).copied().unwrap_or(0.0) as f32;
            Brdf::CookTorrance { kd: unit(c[0]), f0: unit(c[0]), roughness: shape, metalness, diffuse }
        }
        _ => {
            // c1 S0 + c2 S1 = m S0 + m f0 (S1 - S0): m = c1 + c2 (one metalness for the three channels:
            // their mean), f0 = c2 / m; kd = c0 / (1 - m). Where S0 was not told apart (c1 = 0), m f0 = c2
            // alone is known: m is then the least that keeps f0 within 1, the largest c2.
            let m = ((c[1] + c[2]).element_sum() / 3.0).max(c[2].max_element()).clamp(0.0, 1.0);
            let f0 = if m > 0.0 { unit(c[2] / m) } else { Vec3::ZERO };
            let kd = if m < 1.0 { unit(c[0] / (1.0 - m)) } else { Vec3::ZERO };
            Brdf::CookTorrance { kd, f0, roughness: shape, metalness: m, diffuse }
        }
    }
}
