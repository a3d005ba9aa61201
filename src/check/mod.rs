//! Diagnosing a student's image against the exact one (`vk-render check`): the correct render and the render
//! of every mistake of the [`catalogue`] on the same scene, each compared with the student's image in a way
//! JPEG cannot fool, and ranked by how well they explain it. A layer above render, like the analysis.

pub mod catalogue;
pub mod report;
pub mod summary;

use image::RgbImage;

use crate::analysis::Channel;
use crate::error::{Error, Result};
use crate::output::tonemap;
use crate::render::Renderer;
use crate::scene::Scene;
use crate::vulkan::ShaderSources;
use catalogue::{Mistake, ShowsOn, Variant};

/// How an image is judged: both images blurred over 3 x 3 pixels (JPEG's block noise averages out), the
/// pixels within [`EDGE_MARGIN`] of a hard edge of the exact image left out (JPEG rings there: silhouettes,
/// shadow edges), then per pixel the largest channel difference, in 8-bit levels: its root mean square (which
/// a small region far off, a highlight of the wrong colour, weighs as it should), 99th percentile and mean.
pub const EDGE_MARGIN: u32 = 4;
/// A hard edge: neighbouring pixels more than this many levels apart in the exact image.
const EDGE_STEP: u8 = 48;
/// An image matches when the root mean square of its differences is at most [`MATCH_RMS`] levels and their
/// 99th percentile at most [`MATCH_P99`] (JPEG at quality 75 stays well within both on the practical's
/// images).
pub const MATCH_RMS: f64 = 2.0;
/// The bound on the 99th percentile of the differences, in 8-bit levels: see [`MATCH_RMS`].
pub const MATCH_P99: u8 = 8;
/// How much more a bias counts than the spread of the differences in [`Stats::distance`].
const BIAS_WEIGHT: f64 = 4.0;
/// A pixel differs when its blurred difference is above [`MATCH_P99`].
const PIXEL_TOLERANCE: u8 = MATCH_P99;

/// One candidate explanation: the correct render (no mistake) or a mistake's.
pub struct Candidate {
    /// The mistake rendered, `None` for the correct render.
    pub mistake: Option<&'static Mistake>,
    /// Its render, after the scene's output transform.
    pub image: RgbImage,
}

/// Renders the correct image of `scene` and each of `mistakes`' on `renderer`, telling `progress` how many
/// of how many are done. The renderer's shaders are the embedded ones again at the end.
///
/// # Errors
/// What rendering returns; `Error::Shader` naming a mistake whose edit no longer fits the shaders.
pub fn render_candidates(
    renderer: &mut Renderer,
    scene: &Scene,
    mistakes: &[&'static Mistake],
    mut progress: impl FnMut(usize, usize),
) -> Result<Vec<Candidate>> {
    let exact = renderer.render_rgb8(scene)?;
    let mut images: Vec<Option<RgbImage>> = vec![None; mistakes.len()];
    let mut done = 0;
    // The mistakes of the scene and of the output first, on the embedded shaders; then those of the shaders,
    // each on its variant, the embedded shaders put back once at the end (a failed render too).
    for (image, mistake) in images.iter_mut().zip(mistakes) {
        crate::interrupt::check()?;
        let made = match mistake.variant {
            Variant::Shader(_) => continue,
            Variant::Scene(change) => {
                let mut changed = scene.clone();
                change(&mut changed);
                renderer.render_rgb8(&changed)?
            }
            Variant::Rounding => rounded(&renderer.render(scene)?, scene),
        };
        *image = Some(made);
        done += 1;
        progress(done, mistakes.len());
    }
    let mut shader_variants = || -> Result<()> {
        for (image, mistake) in images.iter_mut().zip(mistakes) {
            let Variant::Shader(edits) = mistake.variant else { continue };
            crate::interrupt::check()?;
            let sources = edits
                .iter()
                .try_fold(ShaderSources::default(), |sources, e| sources.with_replaced(e.file, e.from, e.to))
                .map_err(|log| Error::Shader { path: mistake.name.to_string(), log })?;
            renderer.set_shaders(sources)?;
            *image = Some(renderer.render_rgb8(scene)?);
            done += 1;
            progress(done, mistakes.len());
        }
        Ok(())
    };
    let rendered = shader_variants();
    if mistakes.iter().any(|m| matches!(m.variant, Variant::Shader(_))) {
        renderer.set_shaders(ShaderSources::default())?;
    }
    rendered?;
    let mut candidates = vec![Candidate { mistake: None, image: exact }];
    candidates.extend(
        mistakes
            .iter()
            .zip(images)
            .filter_map(|(&mistake, image)| image.map(|image| Candidate { mistake: Some(mistake), image })),
    );
    Ok(candidates)
}

/// The course's output transform with the levels rounded instead of truncated.
fn rounded(hdr: &crate::HdrImage, scene: &Scene) -> RgbImage {
    let settings = &scene.image;
    let level = |c: f32| {
        let c = tonemap(c * settings.exposure, settings.tonemap);
        if c.is_nan() {
            0
        } else {
            (c.clamp(0.0, 1.0) * 255.0).round() as u8
        }
    };
    let bytes = hdr.pixels.iter().flat_map(|p| p.to_array()).map(level).collect();
    RgbImage::from_raw(hdr.width, hdr.height, bytes).unwrap_or_default()
}

/// Which pixels are judged: those not within [`EDGE_MARGIN`] of a hard edge of the exact image.
pub fn judged_pixels(exact: &RgbImage) -> Vec<bool> {
    let (w, h) = exact.dimensions();
    let step = |a: &image::Rgb<u8>, b: &image::Rgb<u8>| (0..3).any(|c| a.0[c].abs_diff(b.0[c]) > EDGE_STEP);
    let mut judged = vec![true; (w * h) as usize];
    for y in 0..h {
        for x in 0..w {
            let here = exact.get_pixel(x, y);
            let edge = (x + 1 < w && step(here, exact.get_pixel(x + 1, y)))
                || (y + 1 < h && step(here, exact.get_pixel(x, y + 1)));
            if !edge {
                continue;
            }
            let m = EDGE_MARGIN as i64;
            for ny in (y as i64 - m).max(0)..=(y as i64 + m + 1).min(h as i64 - 1) {
                for nx in (x as i64 - m).max(0)..=(x as i64 + m + 1).min(w as i64 - 1) {
                    judged[(ny * w as i64 + nx) as usize] = false;
                }
            }
        }
    }
    judged
}

/// The 3 x 3 box blur of an image (edges clamped).
fn blurred(image: &RgbImage) -> Vec<[f32; 3]> {
    let (w, h) = image.dimensions();
    let mut out = Vec::with_capacity((w * h) as usize);
    for y in 0..h as i64 {
        for x in 0..w as i64 {
            let mut sum = [0.0f32; 3];
            for dy in -1..=1 {
                for dx in -1..=1 {
                    let (sx, sy) = ((x + dx).clamp(0, w as i64 - 1), (y + dy).clamp(0, h as i64 - 1));
                    let p = image.get_pixel(sx as u32, sy as u32);
                    for (total, channel) in sum.iter_mut().zip(p.0) {
                        *total += f32::from(channel);
                    }
                }
            }
            out.push(sum.map(|s| s / 9.0));
        }
    }
    out
}

/// The judged difference of two images of one size: per pixel the largest channel difference of the blurred
/// images, in levels, and the mean of the signed differences of the channels (`a - b`); None for pixels
/// left out.
pub fn differences(a: &RgbImage, b: &RgbImage, judged: &[bool]) -> Vec<Option<(f32, f32)>> {
    blurred_differences(&blurred(a), &blurred(b), judged)
}

/// [`differences`] of images already blurred (each blurred once however many it is compared with).
fn blurred_differences(a: &[[f32; 3]], b: &[[f32; 3]], judged: &[bool]) -> Vec<Option<(f32, f32)>> {
    a.iter()
        .zip(b)
        .zip(judged)
        .map(|((p, q), &j)| {
            j.then(|| {
                (
                    (0..3).map(|c| (p[c] - q[c]).abs()).fold(0.0, f32::max),
                    (0..3).map(|c| p[c] - q[c]).sum::<f32>() / 3.0,
                )
            })
        })
        .collect()
}

/// The statistics of judged differences.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Stats {
    /// Root mean square of the per-pixel differences, in 8-bit levels.
    pub rms: f64,
    /// Mean of the per-pixel differences, in levels.
    pub mean: f64,
    /// The mean signed difference: JPEG's noise averages out of it, a level's bias does not (rounding
    /// instead of truncating is half a level brighter everywhere).
    pub bias: f64,
    /// 99th percentile of the per-pixel differences, in levels.
    pub p99: f64,
    /// The share of judged pixels over the per-pixel tolerance ([`MATCH_P99`] levels).
    pub over: f64,
    /// How many pixels were judged.
    pub judged: usize,
}

impl Stats {
    /// The statistics of per-pixel differences as [`differences`] gives them (`None`, a pixel left out, is
    /// skipped); all zero when no pixel is judged.
    pub fn of<'a>(differences: impl Iterator<Item = &'a Option<(f32, f32)>>) -> Self {
        let pairs: Vec<(f32, f32)> = differences.flatten().copied().collect();
        let mut values: Vec<f32> = pairs.iter().map(|p| p.0).collect();
        if values.is_empty() {
            return Self { rms: 0.0, mean: 0.0, bias: 0.0, p99: 0.0, over: 0.0, judged: 0 };
        }
        let bias = pairs.iter().map(|p| f64::from(p.1)).sum::<f64>() / pairs.len() as f64;
        values.sort_by(f32::total_cmp);
        let n = values.len();
        Self {
            rms: (values.iter().map(|&v| f64::from(v) * f64::from(v)).sum::<f64>() / n as f64).sqrt(),
            bias,
            mean: values.iter().map(|&v| f64::from(v)).sum::<f64>() / n as f64,
            p99: f64::from(values[((n - 1) as f64 * 0.99).round() as usize]),
            over: values.iter().filter(|&&v| v > f32::from(PIXEL_TOLERANCE)).count() as f64 / n as f64,
            judged: n,
        }
    }

    /// How far two images are, for ranking: the root mean square with the bias weighed in
    /// (`BIAS_WEIGHT` = 4 times), so that a level's bias counts over JPEG's noise.
    pub fn distance(&self) -> f64 {
        (self.rms * self.rms + (BIAS_WEIGHT * self.bias).powi(2)).sqrt()
    }

    /// Within the match tolerance.
    pub fn matches(&self) -> bool {
        self.rms <= MATCH_RMS && self.p99 <= f64::from(MATCH_P99)
    }
}

/// What the candidates say of an image.
pub struct Diagnosis {
    /// The image against the correct render.
    pub against_exact: Stats,
    /// Every candidate's distance from the image ([`Stats::distance`]: the root mean square with the bias
    /// weighed in), best first (the correct render among them).
    pub ranking: Vec<(Option<&'static Mistake>, f64)>,
    /// The verdict.
    pub verdict: Verdict,
}

/// What the diagnosis concludes.
#[derive(Debug, PartialEq)]
pub enum Verdict {
    /// The image is the correct one, within the tolerance.
    Matches,
    /// One mistake explains it clearly better than the correct render and any other mistake.
    Mistake(&'static str),
    /// Several mistakes explain it about as well: the scene cannot tell them apart.
    Tie(Vec<&'static str>),
    /// No mistake explains it.
    Unexplained,
}

/// A mistake explains an image when its difference is at most this share of the correct render's ...
const EXPLAINS_SHARE: f64 = 0.6;
/// ... and the image is about as close to it as a JPEG of it would be: within this many times the match
/// tolerance.
const EXPLAINS_RMS: f64 = 2.0 * MATCH_RMS;
/// Mistakes within this share of the best (or this many levels) tie with it.
const TIE_SHARE: f64 = 1.25;
const TIE_LEVELS: f64 = 0.25;

/// Ranks the candidates (the first the correct render) by how well they explain `mine`. A mistake is named
/// when it explains the image clearly better than the correct render, even when the image is within the
/// tolerance (rounding instead of truncating is at most a level off everywhere).
pub fn diagnose(mine: &RgbImage, candidates: &[Candidate]) -> Diagnosis {
    let judged = judged_pixels(&candidates[0].image);
    let mine = blurred(mine);
    let stats: Vec<Stats> =
        candidates.iter().map(|c| Stats::of(blurred_differences(&mine, &blurred(&c.image), &judged).iter())).collect();
    let against_exact = stats[0];
    let mut ranking: Vec<(Option<&'static Mistake>, f64)> =
        candidates.iter().zip(&stats).map(|(c, s)| (c.mistake, s.distance())).collect();
    ranking.sort_by(|a, b| a.1.total_cmp(&b.1));
    let best = ranking[0].1;
    let explaining: Vec<&'static Mistake> = ranking
        .iter()
        .filter(|(_, rms)| *rms <= (TIE_SHARE * best).max(best + TIE_LEVELS))
        .filter_map(|(mistake, rms)| {
            mistake.filter(|_| *rms < EXPLAINS_SHARE * against_exact.distance() && *rms <= EXPLAINS_RMS)
        })
        .collect();
    let verdict = match explaining.as_slice() {
        [] if against_exact.matches() => Verdict::Matches,
        [] => Verdict::Unexplained,
        [one] => Verdict::Mistake(one.name),
        many => Verdict::Tie(many.iter().map(|m| m.name).collect()),
    };
    Diagnosis { against_exact, ranking, verdict }
}

/// Where differences lie: for each object (and the background), in its grazing band (within
/// [`GRAZING_BAND`] pixels of its silhouette), its highlight (its brightest 5% in the exact image), its unlit
/// part (black in the exact image: shadowed or facing away from every light) and the rest, its lit body:
/// the statistics of the judged pixels of each.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// The object's index in the scene, None for the background.
    pub object: Option<usize>,
    /// "lit body", "unlit part", "highlight", "grazing band", or "open part" (the background's).
    pub part: &'static str,
    /// The differences over its judged pixels.
    pub stats: Stats,
}

/// An object's pixels darker than this (in levels of luminance) in the exact image are its unlit part.
const UNLIT_LEVEL: f32 = 2.0;

/// Pixels this close to a change of object id are an object's grazing band.
pub const GRAZING_BAND: u32 = 6;

/// The differences of `mine` from the exact image, region by region (`object_ids` per pixel, from the CPU
/// reference at the image's size): every region with judged pixels.
pub fn regions(mine: &RgbImage, exact: &RgbImage, object_ids: &[Option<usize>]) -> Vec<Region> {
    let (w, h) = exact.dimensions();
    let judged = judged_pixels(exact);
    let diffs = differences(mine, exact, &judged);
    let band = crate::compare::silhouette_band(object_ids, w, h, GRAZING_BAND);
    let luminance = |p: &image::Rgb<u8>| Channel::Luminance.of(p.0.map(f64::from)) as f32;
    let mut ids: Vec<Option<usize>> = object_ids.to_vec();
    ids.sort();
    ids.dedup();
    let mut regions = Vec::new();
    for id in ids {
        let pixels: Vec<usize> = (0..object_ids.len()).filter(|&i| object_ids[i] == id).collect();
        let mut brightness: Vec<f32> =
            pixels.iter().map(|&i| luminance(exact.get_pixel(i as u32 % w, i as u32 / w))).collect();
        brightness.sort_by(f32::total_cmp);
        let highlight = brightness.get(brightness.len() * 95 / 100).copied().unwrap_or(f32::INFINITY).max(1.0);
        let part_of = |i: usize| {
            let here = luminance(exact.get_pixel(i as u32 % w, i as u32 / w));
            if band[i] {
                "grazing band"
            } else if id.is_none() {
                "open part"
            } else if here >= highlight {
                "highlight"
            } else if here < UNLIT_LEVEL {
                "unlit part"
            } else {
                "lit body"
            }
        };
        for part in ["open part", "lit body", "unlit part", "highlight", "grazing band"] {
            let stats = Stats::of(pixels.iter().filter(|&&i| part_of(i) == part).map(|&i| &diffs[i]));
            if stats.judged > 0 {
                regions.push(Region { object: id, part, stats });
            }
        }
    }
    regions
}

/// The scene of the practical that tells `mistakes` apart best, among those where each shows (the
/// catalogue's), at `size`: where the two closest of their renders are farthest apart, and how far (the
/// distance of [`Stats::distance`], in levels). None when no scene separates every pair by more than twice
/// the match tolerance.
///
/// # Errors
/// What rendering returns.
pub fn scene_that_tells_apart(
    renderer: &mut Renderer,
    mistakes: &[&'static Mistake],
    (width, height): (u32, u32),
) -> Result<Option<(ShowsOn, f64)>> {
    let mut best: Option<(ShowsOn, f64)> = None;
    let mut tried: Vec<(&str, &[&str])> = Vec::new();
    for mistake in mistakes {
        let (name, overrides) = mistake.shows_on;
        if tried.contains(&(name, overrides)) {
            continue;
        }
        tried.push((name, overrides));
        let Some(image) = crate::figures::practical_image(name) else { continue };
        let mut all: Vec<crate::Override> = vec![
            crate::Override::new("image.width", i64::from(width)),
            crate::Override::new("image.height", i64::from(height)),
        ];
        for text in overrides {
            all.push(text.parse().map_err(|message: String| Error::Scene { file: name.into(), message })?);
        }
        let scene = image.scene(&all)?;
        let candidates = render_candidates(renderer, &scene, mistakes, |_, _| {})?;
        let judged = judged_pixels(&candidates[0].image);
        let renders: Vec<Vec<[f32; 3]>> = candidates[1..].iter().map(|c| blurred(&c.image)).collect();
        let mut closest = f64::INFINITY;
        for (i, a) in renders.iter().enumerate() {
            for b in &renders[i + 1..] {
                closest = closest.min(Stats::of(blurred_differences(a, b, &judged).iter()).distance());
            }
        }
        if closest > 2.0 * MATCH_RMS && best.is_none_or(|(_, d)| closest > d) {
            best = Some(((name, overrides), closest));
        }
    }
    Ok(best)
}
