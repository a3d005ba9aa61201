//! Image comparison for tests: 8-bit differences away from silhouettes, summarised, with pictures on failure.

use std::path::{Path, PathBuf};

use image::RgbImage;

/// Differences between a candidate and a reference image, in 8-bit levels, over the compared pixels.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Pixels compared (those not excluded).
    pub compared: usize,
    /// Mean absolute difference over every channel.
    pub mean_abs: f64,
    /// 99th percentile of the per-pixel largest channel difference.
    pub p99: u8,
    /// Largest channel difference.
    pub max: u8,
    /// Fraction of pixels with a channel more than 3 levels off.
    pub fraction_over_3: f64,
}

impl std::fmt::Display for Comparison {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} px compared: mean abs {:.3}, p99 {}, max {}, {:.3}% over 3 levels",
            self.compared,
            self.mean_abs,
            self.p99,
            self.max,
            100.0 * self.fraction_over_3
        )
    }
}

/// The pixels near a change of object id, where a rasterizer's coverage and a ray tracer's centre sample
/// legitimately disagree (crates/check-rules: a check's grazing band is the same).
pub use check_rules::silhouette_band;

/// Compares two images of the same size, leaving out the pixels where `excluded` is true.
pub fn compare(candidate: &RgbImage, reference: &RgbImage, excluded: &[bool]) -> Comparison {
    assert_eq!(candidate.dimensions(), reference.dimensions(), "images of different sizes");
    let mut worst: Vec<u8> = Vec::new();
    let mut total = 0u64;
    for ((a, b), &skip) in candidate.pixels().zip(reference.pixels()).zip(excluded) {
        if skip {
            continue;
        }
        let diffs = [0, 1, 2].map(|c| a.0[c].abs_diff(b.0[c]));
        total += diffs.iter().map(|&d| u64::from(d)).sum::<u64>();
        worst.push(*diffs.iter().max().unwrap_or(&0));
    }
    let compared = worst.len();
    let over_3 = worst.iter().filter(|&&d| d > 3).count();
    worst.sort_unstable();
    let p99 = if compared == 0 { 0 } else { worst[((compared - 1) as f64 * 0.99).round() as usize] };
    Comparison {
        compared,
        mean_abs: if compared == 0 { 0.0 } else { total as f64 / (3 * compared) as f64 },
        p99,
        max: worst.last().copied().unwrap_or(0),
        fraction_over_3: if compared == 0 { 0.0 } else { over_3 as f64 / compared as f64 },
    }
}

/// The pixels more than `levels` off (in any channel) whose eight neighbours are all more than `levels` off
/// too: the inside of a region of difference. Differences only along edges, lines at most two pixels wide (a
/// silhouette's or a shadow edge's coverage, which rasterizers may decide differently), have none; a missing
/// highlight or shadow, or a wrong material, has many.
pub fn regions_of_difference(candidate: &RgbImage, reference: &RgbImage, levels: u8) -> usize {
    assert_eq!(candidate.dimensions(), reference.dimensions(), "images of different sizes");
    let (w, h) = candidate.dimensions();
    let off = |x: u32, y: u32| {
        let (a, b) = (candidate.get_pixel(x, y), reference.get_pixel(x, y));
        (0..3).any(|c| a.0[c].abs_diff(b.0[c]) > levels)
    };
    let mut inside = 0;
    for y in 1..h.saturating_sub(1) {
        for x in 1..w.saturating_sub(1) {
            if (y - 1..=y + 1).all(|ny| (x - 1..=x + 1).all(|nx| off(nx, ny))) {
                inside += 1;
            }
        }
    }
    inside
}

/// Writes `NAME-candidate.png`, `NAME-reference.png` and `NAME-diff.png` (false colour: black equal, blue 1
/// level, green 2-3, yellow 4-15, red more; excluded pixels dark grey) under `folder`, and returns their paths.
///
/// # Errors
/// The I/O error if the folder or a file cannot be written.
pub fn write_failure_images(
    folder: &Path,
    name: &str,
    candidate: &RgbImage,
    reference: &RgbImage,
    excluded: &[bool],
) -> std::io::Result<Vec<PathBuf>> {
    std::fs::create_dir_all(folder)?;
    let diff = RgbImage::from_fn(candidate.width(), candidate.height(), |x, y| {
        let i = (y * candidate.width() + x) as usize;
        if excluded[i] {
            return image::Rgb([40, 40, 40]);
        }
        let (a, b) = (candidate.get_pixel(x, y), reference.get_pixel(x, y));
        let d = (0..3).map(|c| a.0[c].abs_diff(b.0[c])).max().unwrap_or(0);
        image::Rgb(match d {
            0 => [0, 0, 0],
            1 => [0, 0, 255],
            2..=3 => [0, 200, 0],
            4..=15 => [255, 255, 0],
            _ => [255, 0, 0],
        })
    });
    let paths: Vec<PathBuf> =
        ["candidate", "reference", "diff"].iter().map(|kind| folder.join(format!("{name}-{kind}.png"))).collect();
    for (path, picture) in paths.iter().zip([candidate, reference, &diff]) {
        picture.save(path).map_err(std::io::Error::other)?;
    }
    Ok(paths)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn regions_of_difference_count_the_inside_of_blobs_not_lines() {
        let grey = RgbImage::from_pixel(20, 20, image::Rgb([100, 100, 100]));
        let mut changed = grey.clone();
        // A line two pixels wide, far off: an edge, no region.
        for y in 0..20 {
            for x in [3, 4] {
                changed.put_pixel(x, y, image::Rgb([200, 100, 100]));
            }
        }
        assert_eq!(regions_of_difference(&changed, &grey, 3), 0);
        // A 5 x 5 blob four levels off: its 3 x 3 inside counts; three levels off does not count at all.
        for y in 10..15 {
            for x in 10..15 {
                changed.put_pixel(x, y, image::Rgb([100, 104, 100]));
            }
        }
        assert_eq!(regions_of_difference(&changed, &grey, 3), 9);
        assert_eq!(regions_of_difference(&changed, &grey, 4), 0);
    }
}
