//! How `vk-render check` judges a student's image: against the exact render and each mistake's render at
//! the image's size, compared in a way JPEG cannot fool, and ranked by how well each explains it. No device
//! here: vk-render renders the candidates and decides with this crate (src/check), and the browser's check
//! page (a `vk-render site` folder) decides with the same crate compiled to WebAssembly (`crates/web/`), against
//! renders made at `site` time, so that the two verdicts cannot differ by a rule. What the check shows beside
//! its verdict (the statistics per region, the map of differences and where they are worst) is made here too.

mod difference;
mod regions;

use image::RgbImage;
use serde::Serialize;

pub use difference::{viridis, DifferenceMap};
pub use regions::{regions, silhouette_band, Region, RegionStatistics, GRAZING_BAND};

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

/// A mistake explains an image when its difference is at most this share of the correct render's ...
const EXPLAINS_SHARE: f64 = 0.6;
/// ... and the image is about as close to it as a JPEG of it would be: within this many times the match
/// tolerance.
const EXPLAINS_RMS: f64 = 2.0 * MATCH_RMS;
/// Mistakes within this share of the best (or this many levels) tie with it.
const TIE_SHARE: f64 = 1.25;
const TIE_LEVELS: f64 = 0.25;

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
pub fn blurred(image: &RgbImage) -> Vec<[f32; 3]> {
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
pub fn blurred_differences(a: &[[f32; 3]], b: &[[f32; 3]], judged: &[bool]) -> Vec<Option<(f32, f32)>> {
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

/// How the candidates explain an image: the first candidate is the correct render, each other one a mistake's
/// (labelled `L`, as the caller names mistakes).
#[derive(Clone, Debug, PartialEq)]
pub struct Ranked<L> {
    /// The image against the correct render.
    pub against_exact: Stats,
    /// Every candidate's distance from the image ([`Stats::distance`]: the root mean square with the bias
    /// weighed in), best first (the correct render, `None`, among them).
    pub ranking: Vec<(Option<L>, f64)>,
    /// The mistakes that explain the image (clearly better than the correct render, and about as well as the
    /// best): none, one, or several that the scene cannot tell apart.
    pub explaining: Vec<L>,
}

/// What a check concludes of an image, its mistakes labelled `L`.
#[derive(Clone, Debug, PartialEq)]
pub enum Verdict<L> {
    /// The image is the correct one, within the tolerance.
    Matches,
    /// One mistake explains it clearly better than the correct render and any other mistake.
    Mistake(L),
    /// Several mistakes explain it about as well: the scene cannot tell them apart.
    Tie(Vec<L>),
    /// No mistake explains it.
    Unexplained,
}

impl<L: Copy> Ranked<L> {
    /// The verdict: the mistakes that explain the image, else whether it is within the tolerance.
    pub fn verdict(&self) -> Verdict<L> {
        match self.explaining.as_slice() {
            [] if self.against_exact.matches() => Verdict::Matches,
            [] => Verdict::Unexplained,
            [one] => Verdict::Mistake(*one),
            many => Verdict::Tie(many.to_vec()),
        }
    }
}

impl<L> Verdict<L> {
    /// The verdict's one word, as reports and JSON name it.
    pub fn word(&self) -> &'static str {
        match self {
            Verdict::Matches => "matches",
            Verdict::Mistake(_) => "mistake",
            Verdict::Tie(_) => "tie",
            Verdict::Unexplained => "unexplained",
        }
    }

    /// The same verdict with its mistakes labelled `label(mistake)`.
    pub fn map<M>(self, label: impl Fn(L) -> M) -> Verdict<M> {
        match self {
            Verdict::Matches => Verdict::Matches,
            Verdict::Mistake(one) => Verdict::Mistake(label(one)),
            Verdict::Tie(many) => Verdict::Tie(many.into_iter().map(label).collect()),
            Verdict::Unexplained => Verdict::Unexplained,
        }
    }

    /// The mistakes it names: one, the tied ones, or none.
    pub fn mistakes(&self) -> &[L] {
        match self {
            Verdict::Mistake(one) => std::slice::from_ref(one),
            Verdict::Tie(many) => many,
            Verdict::Matches | Verdict::Unexplained => &[],
        }
    }
}

/// Differences in 8-bit levels, as a check's report states them.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Statistics {
    /// Root mean square of the per-pixel differences.
    pub rms: f64,
    /// Mean of the per-pixel differences.
    pub mean: f64,
    /// 99th percentile of the per-pixel differences.
    pub p99: f64,
    /// The share of the judged pixels over the match's per-pixel tolerance.
    pub over: f64,
}

impl From<&Stats> for Statistics {
    fn from(s: &Stats) -> Self {
        Self { rms: s.rms, mean: s.mean, p99: s.p99, over: s.over }
    }
}

/// Ranks the candidates (the first the correct render, `None`; each other labelled) by how well they explain
/// `mine`. A mistake explains it when it does clearly better than the correct render, even when the image is
/// within the tolerance (rounding instead of truncating is at most a level off everywhere).
pub fn rank<L: Copy>(mine: &RgbImage, candidates: &[(Option<L>, &RgbImage)]) -> Ranked<L> {
    let judged = judged_pixels(candidates[0].1);
    let mine = blurred(mine);
    let stats: Vec<Stats> =
        candidates.iter().map(|c| Stats::of(blurred_differences(&mine, &blurred(c.1), &judged).iter())).collect();
    let against_exact = stats[0];
    let mut ranking: Vec<(Option<L>, f64)> = candidates.iter().zip(&stats).map(|(c, s)| (c.0, s.distance())).collect();
    ranking.sort_by(|a, b| a.1.total_cmp(&b.1));
    let best = ranking[0].1;
    let explaining = ranking
        .iter()
        .filter(|(_, distance)| *distance <= (TIE_SHARE * best).max(best + TIE_LEVELS))
        .filter_map(|(mistake, distance)| {
            mistake.filter(|_| *distance < EXPLAINS_SHARE * against_exact.distance() && *distance <= EXPLAINS_RMS)
        })
        .collect();
    Ranked { against_exact, ranking, explaining }
}

/// An image to check from its file's bytes: PNG or JPEG, 8-bit RGB (alpha, if any, left out), decoded
/// within `limits`; grey-scale and 16-bit images are refused.
///
/// # Errors
/// What is wrong with it, in one line.
pub fn decode_image(bytes: &[u8], limits: image::Limits) -> Result<RgbImage, String> {
    let mut reader = image::ImageReader::new(std::io::Cursor::new(bytes))
        .with_guessed_format()
        .map_err(|e| format!("not a PNG or JPEG image vk-render can read: {e}"))?;
    reader.limits(limits);
    let image = reader.decode().map_err(|e| format!("not a PNG or JPEG image vk-render can read: {e}"))?;
    match image {
        image::DynamicImage::ImageRgb8(rgb) => Ok(rgb),
        image::DynamicImage::ImageRgba8(rgba) => Ok(image::DynamicImage::ImageRgba8(rgba).to_rgb8()),
        other => Err(format!(
            "a {:?} image; vk-render compares 8-bit RGB images, as the course's skeleton writes them",
            other.color()
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 40 x 30 image: a smooth gradient, and a block `shift` levels off in its middle.
    fn picture(shift: i16) -> RgbImage {
        RgbImage::from_fn(40, 30, |x, y| {
            let base = (60 + x + y) as i16 + if (10..30).contains(&x) && (8..22).contains(&y) { shift } else { 0 };
            let v = base.clamp(0, 255) as u8;
            image::Rgb([v, v / 2, 255 - v])
        })
    }

    #[test]
    fn the_statistics_of_differences_are_those_computed_by_hand() {
        let differences = [Some((1.0, 1.0)), None, Some((3.0, -3.0)), Some((0.0, 0.0)), Some((10.0, 10.0))];
        let stats = Stats::of(differences.iter());
        assert_eq!(stats.judged, 4);
        assert!((stats.rms - (110.0f64 / 4.0).sqrt()).abs() < 1e-12);
        assert_eq!(stats.mean, 3.5);
        assert_eq!(stats.bias, 2.0);
        assert_eq!(stats.p99, 10.0);
        assert_eq!(stats.over, 0.25);
        assert!((stats.distance() - (27.5f64 + 64.0).sqrt()).abs() < 1e-12);
        assert!(!stats.matches());
    }

    #[test]
    fn the_closest_mistake_explains_an_image_and_twins_tie() {
        let (exact, darker, brighter) = (picture(0), picture(-30), picture(30));
        let candidates = [(None, &exact), (Some("darker"), &darker), (Some("brighter"), &brighter)];
        let ranked = rank(&picture(-29), &candidates);
        assert_eq!(ranked.explaining, ["darker"]);
        assert_eq!(ranked.ranking[0].0, Some("darker"));
        assert!(!ranked.against_exact.matches());
        // The exact image itself, a level off: no mistake explains it, and it matches.
        let ranked = rank(&picture(1), &candidates);
        assert!(ranked.explaining.is_empty() && ranked.against_exact.matches(), "{ranked:?}");
        // Two mistakes that render alike tie.
        let twins = [(None, &exact), (Some("darker"), &darker), (Some("also darker"), &darker)];
        assert_eq!(rank(&darker, &twins).explaining, ["darker", "also darker"]);
        // An image none of them makes is unexplained: far from all, nearest to no mistake.
        let ranked = rank(&picture(90), &candidates);
        assert!(ranked.explaining.is_empty() && !ranked.against_exact.matches(), "{ranked:?}");
    }

    #[test]
    fn pixels_near_hard_edges_of_the_exact_image_are_not_judged() {
        let judged = judged_pixels(&picture(100));
        // The block's edge at x = 10 (a step of 100 levels): 4 pixels either side left out (and one more
        // before it, the edge being between x = 9 and 10).
        assert!(!judged[(15 * 40 + 10) as usize] && !judged[(15 * 40 + 5) as usize]);
        assert!(judged[(15 * 40 + 4) as usize] && judged[(15 * 40 + 20) as usize]);
        assert!(judged[0]);
    }

    #[test]
    fn what_is_not_a_colour_png_or_jpeg_is_refused_in_one_line() {
        let refused = decode_image(b"not an image at all", image::Limits::default()).unwrap_err();
        assert!(refused.starts_with("not a PNG or JPEG image vk-render can read"), "{refused}");
        let mut png = Vec::new();
        image::GrayImage::new(4, 4).write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png).unwrap();
        assert!(decode_image(&png, image::Limits::default()).unwrap_err().contains("L8"));
        let mut limits = image::Limits::default();
        limits.max_image_width = Some(2);
        assert!(decode_image(&png, limits).is_err());
    }
}
