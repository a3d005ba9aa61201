//! Importance sampling of an environment by its luminance: the tables the exact mode's shaders search
//! (shaders/common/environment.glsl, `environment_sample` and `environment_pdf`).
//!
//! The table's cells are the map's texels (on a grid of at most MAX_SAMPLING_WIDTH across). A cell's weight
//! is the mean luminance of the texels within one texel of it, plus a sixteenth of the brightest of them,
//! times sin(theta) at its centre: the map is read bilinearly, so a bright texel's light reaches into its
//! neighbours, and a cell must never be much less likely than the radiance it shows (a small weight under a
//! bright reading is a firefly), nor much more (wasted samples). A floor of a thousandth of the mean weight
//! keeps every direction possible.

use std::f32::consts::PI;

use super::EnvironmentMap;

/// The widest sampling grid: finer maps share cells.
pub const MAX_SAMPLING_WIDTH: u32 = 1024;

/// Rec. 709 luminance.
pub fn luminance(rgb: glam::Vec3) -> f32 {
    0.2126 * rgb.x + 0.7152 * rgb.y + 0.0722 * rgb.z
}

/// The cumulative tables of the sampling grid: the marginal over rows (height + 1 values from 0 to 1) and,
/// per row, the conditional over its columns (width + 1 values from 0 to 1); each cell's probability; and a
/// guide to each cumulative table (Chen and Asau 1974's cutpoints): for bucket k of `buckets(n)` equal
/// buckets of [0, 1], the interval that holds k / buckets, so that a search for u starts between its bucket's
/// two cutpoints instead of over the whole table. The shader reads a table one lane at a time on lavapipe:
/// the guides make a draw about 9 reads instead of 23 (at 1024 x 512), and the probabilities the density's 1
/// instead of 4, for the same intervals and the same values.
#[derive(Clone, Debug, PartialEq)]
pub struct SamplingTable {
    /// Cells across: the map's width, at most [`MAX_SAMPLING_WIDTH`].
    pub width: u32,
    /// Cells down: half of `width`.
    pub height: u32,
    /// The cumulative distribution over rows: `height + 1` values from 0 to 1.
    pub marginal: Vec<f32>,
    /// Per row, the cumulative distribution over its columns: `width + 1` values from 0 to 1, row after row.
    pub conditional: Vec<f32>,
    /// Each cell's probability ([`SamplingTable::cell_probability`]), row after row.
    pub probabilities: Vec<f32>,
    /// The marginal's cutpoints: `buckets(height) + 1` intervals.
    pub marginal_guide: Vec<u32>,
    /// Per row, its conditional's cutpoints: `buckets(width) + 1` intervals, row after row.
    pub conditional_guide: Vec<u32>,
}

/// How many buckets a guide of a table of `n` intervals has: a power of two (so that u times it, and k over
/// it, are exact in float32, and u's bucket is the one the cutpoints were computed for) at least `n`.
fn buckets(n: u32) -> u32 {
    n.next_power_of_two()
}

/// The last interval i in [0, count) of `cdf` (count + 1 values, non-decreasing from 0) with cdf[i] <= u.
fn interval(cdf: &[f32], u: f32) -> u32 {
    let count = cdf.len() - 1;
    (cdf[..count].partition_point(|&c| c <= u).max(1) - 1) as u32
}

/// The cutpoints of `cdf`: for each k in 0 ..= buckets, the interval of k / buckets.
fn guide(cdf: &[f32]) -> Vec<u32> {
    let n = buckets((cdf.len() - 1) as u32);
    (0..=n).map(|k| interval(cdf, k as f32 / n as f32)).collect()
}

impl SamplingTable {
    /// The table of `map`, each cell weighted by the luminance it shows and sin(theta) (see the module's text).
    pub fn new(map: &EnvironmentMap) -> Self {
        let width = map.width.min(MAX_SAMPLING_WIDTH);
        let height = width / 2;
        let mut weights = vec![0.0f64; (width * height) as usize];
        for j in 0..height {
            let rows = texel_span(j, height, map.height);
            let sin_theta = (PI * (j as f32 + 0.5) / height as f32).sin();
            for i in 0..width {
                let columns = texel_span(i, width, map.width);
                let (mut brightest, mut sum, mut count) = (0.0f32, 0.0f32, 0.0f32);
                for y in rows.0.max(0)..=rows.1.min(map.height as i64 - 1) {
                    for x in columns.0..=columns.1 {
                        let x = x.rem_euclid(i64::from(map.width)) as u32;
                        let texel = luminance(map.texel(x, y as u32));
                        brightest = brightest.max(texel);
                        sum += texel;
                        count += 1.0;
                    }
                }
                weights[(j * width + i) as usize] = f64::from((sum / count + brightest / 16.0) * sin_theta);
            }
        }
        let mean = weights.iter().sum::<f64>() / weights.len() as f64;
        let floor = if mean > 0.0 { 1e-3 * mean } else { 1.0 };
        weights.iter_mut().for_each(|w| *w += floor);

        let mut marginal = Vec::with_capacity(height as usize + 1);
        let mut conditional = Vec::with_capacity((height * (width + 1)) as usize);
        let row_sums: Vec<f64> = weights.chunks_exact(width as usize).map(|row| row.iter().sum()).collect();
        let total: f64 = row_sums.iter().sum();
        let mut running = 0.0;
        marginal.push(0.0);
        for (row, sum) in weights.chunks_exact(width as usize).zip(&row_sums) {
            running += sum;
            marginal.push((running / total) as f32);
            let mut across = 0.0;
            conditional.push(0.0);
            for w in row {
                across += w;
                conditional.push((across / sum) as f32);
            }
            // Exactly 1 at the end, whatever the rounding.
            *conditional.last_mut().unwrap_or(&mut 0.0) = 1.0;
        }
        *marginal.last_mut().unwrap_or(&mut 0.0) = 1.0;
        let marginal_guide = guide(&marginal);
        let conditional_guide = conditional.chunks_exact(width as usize + 1).flat_map(guide).collect();
        let mut table =
            Self { width, height, marginal, conditional, probabilities: Vec::new(), marginal_guide, conditional_guide };
        table.probabilities = (0..height)
            .flat_map(|j| (0..width).map(move |i| (i, j)))
            .map(|(i, j)| table.cell_probability(i, j))
            .collect();
        table
    }

    /// The probability of cell (i, j): the product of its row's and its column's (the cumulative tables do
    /// not decrease, so neither difference is negative).
    pub fn cell_probability(&self, i: u32, j: u32) -> f32 {
        let row = self.marginal[j as usize + 1] - self.marginal[j as usize];
        let at = (j * (self.width + 1) + i) as usize;
        row * (self.conditional[at + 1] - self.conditional[at])
    }
}

/// The texels of a map `texels` wide whose bilinear reading reaches into cell `cell` of a grid `cells`
/// wide: those the cell covers and one more on each side.
fn texel_span(cell: u32, cells: u32, texels: u32) -> (i64, i64) {
    let first = (u64::from(cell) * u64::from(texels) / u64::from(cells)) as i64;
    let last = ((u64::from(cell) + 1) * u64::from(texels)).div_ceil(u64::from(cells)) as i64 - 1;
    (first - 1, last + 1)
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn probabilities_sum_to_one_and_follow_the_light() {
        let mut map = EnvironmentMap { width: 16, height: 8, texels: vec![Vec3::splat(0.1); 128] };
        map.texels[3 * 16 + 5] = Vec3::splat(100.0);
        let table = SamplingTable::new(&map);
        let total: f32 =
            (0..8).flat_map(|j| (0..16).map(move |i| (i, j))).map(|(i, j)| table.cell_probability(i, j)).sum();
        assert!((total - 1.0).abs() < 1e-5, "{total}");
        // The bright texel and its neighbours, whose bilinear reading it reaches, are the likeliest cells.
        assert!(table.cell_probability(5, 3) > 10.0 * table.cell_probability(10, 3));
        assert!(table.cell_probability(4, 3) > 10.0 * table.cell_probability(10, 3));
    }

    /// shaders/common/environment.glsl's `cdf_interval`: the binary search between u's bucket's cutpoints.
    fn guided_interval(cdf: &[f32], guide: &[u32], u: f32) -> u32 {
        let count = (cdf.len() - 1) as u32;
        let buckets = guide.len() as u32 - 1;
        let bucket = ((u * buckets as f32) as u32).min(buckets - 1);
        let (mut low, mut high) = (guide[bucket as usize], (guide[bucket as usize + 1] + 1).min(count));
        while low + 1 < high {
            let middle = (low + high) / 2;
            if cdf[middle as usize] <= u {
                low = middle;
            } else {
                high = middle;
            }
        }
        low
    }

    #[test]
    fn the_guided_search_finds_the_interval_the_whole_search_does() {
        // A map 12 x 6 (its buckets 16 and 8: not the table's sizes), black but for one bright and one dim
        // texel: most cells have the floor's tiny probability, so many cumulative values lie close together.
        let mut map = EnvironmentMap { width: 12, height: 6, texels: vec![Vec3::ZERO; 72] };
        map.texels[2 * 12 + 7] = Vec3::splat(1000.0);
        map.texels[4 * 12 + 1] = Vec3::splat(0.5);
        let table = SamplingTable::new(&map);
        assert_eq!((table.marginal_guide.len(), table.conditional_guide.len()), (9, 6 * 17));
        let rows = table.conditional.chunks_exact(13).zip(table.conditional_guide.chunks_exact(17));
        for (cdf, guide) in std::iter::once((&table.marginal[..], &table.marginal_guide[..])).chain(rows) {
            // Every cumulative value, its neighbours in float32, every bucket's edges, and a grid over [0, 1).
            let edges = (0..=16).map(|k| k as f32 / 16.0);
            let grid = (0..4096).map(|k| k as f32 / 4096.0);
            let points: Vec<f32> = cdf.iter().copied().chain(edges).chain(grid).collect();
            for u in points.iter().flat_map(|&u| [u, f32::from_bits(u.to_bits().saturating_sub(1)), u.next_up()]) {
                if (0.0..=1.0).contains(&u) {
                    assert_eq!(guided_interval(cdf, guide, u), interval(cdf, u), "u = {u:e} in {cdf:?}");
                }
            }
        }
        // The probabilities are the cells' own.
        assert_eq!(table.probabilities.len(), 72);
        assert_eq!(table.probabilities[2 * 12 + 7], table.cell_probability(7, 2));
    }
}
