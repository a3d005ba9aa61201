//! The map of two images' differences a check's report shows: per pixel the largest channel difference, drawn
//! in viridis, and the square where they are worst, which the report magnifies.

use image::{Rgb, RgbImage};

/// Per pixel, the largest channel difference of two images of one size, in 8-bit levels.
#[derive(Clone, Debug, PartialEq)]
pub struct DifferenceMap {
    /// Row by row from the top.
    pub levels: Vec<u8>,
    /// Width in pixels.
    pub width: u32,
    /// Height in pixels.
    pub height: u32,
}

/// Viridis (van der Walt and Smith's colour map for matplotlib: it reads in grey and for colour-blind
/// readers), sampled at eight evenly spaced points, 0 dark blue to 1 yellow.
const VIRIDIS: [[u8; 3]; 8] = [
    [68, 1, 84],
    [70, 50, 127],
    [54, 92, 141],
    [39, 127, 143],
    [31, 162, 136],
    [74, 194, 110],
    [160, 219, 57],
    [254, 232, 37],
];

/// Viridis at `x` (clamped to 0..1), between its samples linearly, to the nearest level.
pub fn viridis(x: f64) -> [u8; 3] {
    let at = x.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let (below, above) = (at.floor() as usize, at.ceil() as usize);
    let t = at - at.floor();
    std::array::from_fn(|c| ((1.0 - t) * f64::from(VIRIDIS[below][c]) + t * f64::from(VIRIDIS[above][c])).round() as u8)
}

impl DifferenceMap {
    /// The differences of two images of one size.
    pub fn of(a: &RgbImage, b: &RgbImage) -> Self {
        let levels = a
            .pixels()
            .zip(b.pixels())
            .map(|(p, q)| (0..3).map(|c| p.0[c].abs_diff(q.0[c])).max().unwrap_or(0))
            .collect();
        Self { levels, width: a.width(), height: a.height() }
    }

    /// The largest level the colour bar spans: the largest difference, at least 1.
    pub fn scale(&self) -> u8 {
        self.levels.iter().copied().max().unwrap_or(0).max(1)
    }

    /// The differences in viridis, 0 dark blue to [`DifferenceMap::scale`] yellow.
    pub fn heat_map(&self) -> RgbImage {
        let scale = f64::from(self.scale());
        let mut map = RgbImage::new(self.width, self.height);
        for (pixel, &level) in map.pixels_mut().zip(&self.levels) {
            *pixel = Rgb(viridis(f64::from(level) / scale));
        }
        map
    }

    /// The side of the magnifier's square: a sixth of the image's shorter side, at least 16 pixels (at most
    /// the shorter side).
    pub fn magnified_side(&self) -> u32 {
        let shorter = self.width.min(self.height);
        (shorter / 6).max(16).min(shorter)
    }

    /// Where the differences are worst: the square of [`DifferenceMap::magnified_side`] whose summed
    /// difference is largest, searched at a quarter of its side: its left, top and side.
    pub fn worst_region(&self) -> (u32, u32, u32) {
        let (w, h) = (self.width, self.height);
        let side = self.magnified_side();
        // Summed-area table of the levels.
        let mut sums = vec![0u64; ((w + 1) * (h + 1)) as usize];
        for y in 0..h {
            let mut row = 0u64;
            for x in 0..w {
                row += u64::from(self.levels[(y * w + x) as usize]);
                sums[((y + 1) * (w + 1) + x + 1) as usize] = sums[(y * (w + 1) + x + 1) as usize] + row;
            }
        }
        let at = |x: u32, y: u32| sums[(y * (w + 1) + x) as usize];
        let step = (side / 4).max(1) as usize;
        let mut best = (0, 0, 0u64);
        for y in (0..=h - side).step_by(step) {
            for x in (0..=w - side).step_by(step) {
                let total = at(x + side, y + side) + at(x, y) - at(x + side, y) - at(x, y + side);
                if total > best.2 {
                    best = (x, y, total);
                }
            }
        }
        (best.0, best.1, side)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn viridis_runs_from_its_first_sample_to_its_last_through_the_others() {
        assert_eq!(viridis(-1.0), [68, 1, 84]);
        assert_eq!(viridis(1.0), [254, 232, 37]);
        assert_eq!(viridis(3.0 / 7.0), [39, 127, 143]);
        // Halfway between the second and third samples.
        assert_eq!(viridis(1.5 / 7.0), [62, 71, 134]);
    }

    #[test]
    fn the_worst_square_holds_the_differences_and_the_map_spans_them() {
        let a = RgbImage::new(120, 96);
        let mut b = a.clone();
        for (x, y) in [(70, 40), (75, 45), (80, 50)] {
            b.put_pixel(x, y, Rgb([0, 40, 10]));
        }
        let map = DifferenceMap::of(&a, &b);
        assert_eq!(map.scale(), 40);
        assert_eq!(map.magnified_side(), 16);
        let (x, y, side) = map.worst_region();
        // Searched every 4 pixels: the first square holding all three.
        assert_eq!((x, y, side), (68, 36, 16));
        let heat = map.heat_map();
        assert_eq!(heat.get_pixel(75, 45).0, [254, 232, 37]);
        assert_eq!(heat.get_pixel(0, 0).0, [68, 1, 84]);
        assert_eq!(DifferenceMap::of(&a, &a).scale(), 1);
    }
}
