//! Where an image's differences lie: per object (and the background) and per part of it, the grazing band
//! along its silhouette, its highlight, its unlit part and the rest, its lit body.

use image::RgbImage;
use serde::Serialize;

use crate::{differences, judged_pixels, Statistics, Stats};

/// Pixels this close to a change of object id are an object's grazing band.
pub const GRAZING_BAND: u32 = 6;

/// An object's pixels darker than this (in levels of luminance) in the exact image are its unlit part.
const UNLIT_LEVEL: f32 = 2.0;

/// The share of an object's pixels, its brightest in the exact image, that are its highlight.
const HIGHLIGHT_SHARE: usize = 5;

/// The pixels within `radius` pixels (Chebyshev distance) of a change of object id: where a pixel's id
/// differs from its right or lower neighbour's, and the square around it (`object_ids` row by row, `None` the
/// background).
pub fn silhouette_band(object_ids: &[Option<usize>], width: u32, height: u32, radius: u32) -> Vec<bool> {
    let (w, h, r) = (width as i64, height as i64, radius as i64);
    let id = |x: i64, y: i64| object_ids[(y * w + x) as usize];
    let mut band = vec![false; object_ids.len()];
    for y in 0..h {
        for x in 0..w {
            let here = id(x, y);
            let edge = (x + 1 < w && id(x + 1, y) != here) || (y + 1 < h && id(x, y + 1) != here);
            if !edge {
                continue;
            }
            for by in (y - r).max(0)..=(y + r + 1).min(h - 1) {
                for bx in (x - r).max(0)..=(x + r + 1).min(w - 1) {
                    band[(by * w + bx) as usize] = true;
                }
            }
        }
    }
    band
}

/// One region's differences.
#[derive(Clone, Debug, PartialEq)]
pub struct Region {
    /// The object's index in the scene, None for the background.
    pub object: Option<usize>,
    /// "lit body", "unlit part", "highlight", "grazing band", or "open part" (the background's).
    pub part: &'static str,
    /// The differences over its judged pixels.
    pub stats: Stats,
}

/// The statistics of one region of one object (`object` None: the background), as a report states them.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RegionStatistics {
    /// The object's index in the scene, `None` for the background.
    pub object: Option<usize>,
    /// "lit body", "unlit part", "highlight", "grazing band", or "open part" (the background).
    pub part: &'static str,
    /// Its differences (flattened into the region's own object in JSON).
    #[serde(flatten)]
    pub statistics: Statistics,
}

impl From<&Region> for RegionStatistics {
    fn from(r: &Region) -> Self {
        Self { object: r.object, part: r.part, statistics: (&r.stats).into() }
    }
}

/// The luminance of an 8-bit pixel, in levels (Rec. 709's weights).
fn luminance(p: &image::Rgb<u8>) -> f32 {
    0.2126 * f32::from(p.0[0]) + 0.7152 * f32::from(p.0[1]) + 0.0722 * f32::from(p.0[2])
}

/// The differences of `mine` from the exact image, region by region (`object_ids` per pixel, row by row, at
/// the image's size): for each object (and the background), in its grazing band (within [`GRAZING_BAND`]
/// pixels of its silhouette), its highlight (its brightest 5% in the exact image), its unlit part (black in
/// the exact image: shadowed or facing away from every light) and the rest, its lit body: the statistics of
/// the judged pixels of each, every region with judged pixels.
pub fn regions(mine: &RgbImage, exact: &RgbImage, object_ids: &[Option<usize>]) -> Vec<Region> {
    let (w, h) = exact.dimensions();
    let judged = judged_pixels(exact);
    let diffs = differences(mine, exact, &judged);
    let band = silhouette_band(object_ids, w, h, GRAZING_BAND);
    let at = |i: usize| luminance(exact.get_pixel(i as u32 % w, i as u32 / w));
    let mut ids: Vec<Option<usize>> = object_ids.to_vec();
    ids.sort();
    ids.dedup();
    let mut regions = Vec::new();
    for id in ids {
        let pixels: Vec<usize> = (0..object_ids.len()).filter(|&i| object_ids[i] == id).collect();
        let mut brightness: Vec<f32> = pixels.iter().map(|&i| at(i)).collect();
        brightness.sort_by(f32::total_cmp);
        let highlight =
            brightness.get(brightness.len() * (100 - HIGHLIGHT_SHARE) / 100).copied().unwrap_or(f32::INFINITY).max(1.0);
        let part_of = |i: usize| {
            let here = at(i);
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_band_is_the_squares_around_each_change_of_id() {
        // A 10 x 1 row: the background, then object 0 from x = 5.
        let ids: Vec<Option<usize>> = (0..10).map(|x| (x >= 5).then_some(0)).collect();
        let band = silhouette_band(&ids, 10, 1, 1);
        // The change between x = 4 and 5: x = 3 to 6 (the radius either side of both).
        assert_eq!(band, [false, false, false, true, true, true, true, false, false, false]);
    }

    #[test]
    fn an_objects_parts_are_its_band_highlight_unlit_part_and_lit_body() {
        // 40 x 40: the background left of x = 20, an object right of it: black for y < 10, grey below, with a
        // brighter square (its 100 pixels, an eighth of the object's, hold its brightest 5%). The image
        // checked is 20 levels brighter on the object's grey only.
        let exact = RgbImage::from_fn(40, 40, |x, y| {
            let v = match (x, y) {
                (0..20, _) => 100,
                (_, 0..10) => 0,
                (25..35, 25..35) => 160,
                _ => 120,
            };
            image::Rgb([v; 3])
        });
        let ids: Vec<Option<usize>> = (0..1600).map(|i| (i % 40 >= 20).then_some(0)).collect();
        let mine = RgbImage::from_fn(40, 40, |x, y| {
            let p = exact.get_pixel(x, y).0[0];
            image::Rgb([if p == 120 { 140 } else { p }; 3])
        });
        let found = regions(&mine, &exact, &ids);
        let part = |object, name| found.iter().find(|r| r.object == object && r.part == name).unwrap();
        assert_eq!(part(None, "open part").stats.rms, 0.0);
        assert!(part(None, "grazing band").stats.judged > 0);
        // The unlit part away from its hard edge with the grey (y = 10) is untouched.
        assert_eq!(part(Some(0), "unlit part").stats.rms, 0.0);
        let (lit, highlight) = (part(Some(0), "lit body").stats, part(Some(0), "highlight").stats);
        // The grey 20 levels off, but where the blur reaches the square; the square off only there (its pixels
        // within the grazing band, x < 27, are the band's).
        assert!(lit.bias > 15.0 && lit.p99 == 20.0 && lit.rms <= 20.0, "{lit:?}");
        assert!(highlight.judged == 80 && highlight.rms > 0.0 && highlight.rms < 10.0, "{highlight:?}");
        assert!(found.iter().all(|r| r.object.is_none() || r.object == Some(0)));
    }
}
