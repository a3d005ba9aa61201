//! The exact mode's passes over one image: each pass integrates the environment with SAMPLES_PER_PASS new
//! samples a pixel (shaders/common/environment.glsl), and the image is their mean. The passes' spread gives
//! each pixel's standard error, and passes are added until it is below a stated bound in 8-bit levels.

use glam::Vec3;

use crate::pictures::output::{levels_moved, percentile_99};
use crate::scene::ImageSettings;

/// Samples a pixel per pass.
pub const SAMPLES_PER_PASS: u32 = 32;

/// The exact mode stops when the standard error of 99% of the pixels is at most this many 8-bit levels...
pub const TARGET_LEVELS: f32 = 0.5;

/// ...after at least this many passes (the spread of fewer says little)...
pub const MIN_PASSES: u32 = 4;

/// ...or at this many (8192 samples a pixel), stating the error reached.
pub const MAX_PASSES: u32 = 256;

/// The passes so far of one image, summed per pixel (one image's lifetime).
#[derive(Clone, Debug)]
pub struct Passes {
    /// Passes added so far.
    pub count: u32,
    sum: Vec<[f64; 3]>,
    sum_of_squares: Vec<[f64; 3]>,
}

/// How exact an exact render is.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Accuracy {
    /// The environment's samples a pixel, over every pass.
    pub samples: u32,
    /// The passes made.
    pub passes: u32,
    /// The 99th percentile over pixels of the standard error of the mean (the largest channel's), in 8-bit
    /// levels after the output transform.
    pub p99_levels: f32,
}

impl std::fmt::Display for Accuracy {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} samples a pixel in {} passes: standard error at most {:.2} of an 8-bit level at 99% of the pixels",
            self.samples, self.passes, self.p99_levels
        )
    }
}

impl Passes {
    /// No pass yet, for an image of `width` x `height` pixels.
    pub fn new(width: u32, height: u32) -> Self {
        let pixels = (width * height) as usize;
        Self { count: 0, sum: vec![[0.0; 3]; pixels], sum_of_squares: vec![[0.0; 3]; pixels] }
    }

    /// Samples a pixel so far.
    pub fn samples(&self) -> u32 {
        self.count * SAMPLES_PER_PASS
    }

    /// The first sample index of the next pass.
    pub fn next_first_sample(&self) -> u32 {
        self.samples()
    }

    /// Adds a pass's image: four native-endian f32 a pixel.
    pub fn add(&mut self, bytes: &[u8]) {
        for ((pixel, sum), squares) in bytes.chunks_exact(16).zip(&mut self.sum).zip(&mut self.sum_of_squares) {
            for c in 0..3 {
                let v =
                    f64::from(f32::from_ne_bytes([pixel[4 * c], pixel[4 * c + 1], pixel[4 * c + 2], pixel[4 * c + 3]]));
                sum[c] += v;
                squares[c] += v * v;
            }
        }
        self.count += 1;
    }

    /// The mean so far of pixel i.
    fn mean(&self, i: usize) -> Vec3 {
        let n = f64::from(self.count.max(1));
        Vec3::new((self.sum[i][0] / n) as f32, (self.sum[i][1] / n) as f32, (self.sum[i][2] / n) as f32)
    }

    /// The mean of the passes as four native-endian f32 a pixel (alpha 1), as a pass is read back.
    pub fn mean_bytes(&self) -> Vec<u8> {
        (0..self.sum.len()).flat_map(|i| self.mean(i).extend(1.0).to_array()).flat_map(f32::to_ne_bytes).collect()
    }

    /// Per pixel, the standard error of the mean (the largest channel's) in 8-bit levels of an image made
    /// with `settings`: how far one error up moves the mean's level (infinite before two passes).
    pub fn standard_errors(&self, settings: &ImageSettings) -> Vec<f32> {
        let n = f64::from(self.count);
        (0..self.sum.len())
            .map(|i| {
                if self.count < 2 {
                    return f32::INFINITY;
                }
                let error = |c: usize| {
                    let variance =
                        ((self.sum_of_squares[i][c] - self.sum[i][c] * self.sum[i][c] / n) / (n - 1.0)).max(0.0);
                    (variance / n).sqrt() as f32
                };
                levels_moved(self.mean(i), Vec3::new(error(0), error(1), error(2)), settings)
            })
            .collect()
    }

    /// How exact the mean is, in the levels of an image made with `settings`.
    pub fn accuracy(&self, settings: &ImageSettings) -> Accuracy {
        let p99_levels = percentile_99(&mut self.standard_errors(settings));
        Accuracy { samples: self.samples(), passes: self.count, p99_levels }
    }

    /// Whether the passes so far are enough.
    pub fn done(&self, settings: &ImageSettings) -> bool {
        self.count >= MAX_PASSES || (self.count >= MIN_PASSES && self.accuracy(settings).p99_levels <= TARGET_LEVELS)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn pass(values: &[f32]) -> Vec<u8> {
        values.iter().flat_map(|&v| [v, v, v, 1.0]).flat_map(f32::to_ne_bytes).collect()
    }

    #[test]
    fn the_standard_error_is_the_spread_of_the_passes_over_their_square_root() {
        let settings = crate::scene::Scene::parse("", std::path::Path::new("t.toml"), &[]).unwrap().image;
        let mut passes = Passes::new(2, 1);
        // Pixel 0 alternates 0.4 and 0.6 (sample deviation 0.1069 over 8 passes), pixel 1 is constant.
        for k in 0..8 {
            passes.add(&pass(&[if k % 2 == 0 { 0.4 } else { 0.6 }, 0.3]));
        }
        assert_eq!(passes.mean(0), Vec3::splat(0.5));
        let accuracy = passes.accuracy(&settings);
        let expected = 255.0 * (0.2f32 * 0.2 * 8.0 / 4.0 / 7.0).sqrt() / 8f32.sqrt();
        // The 99th percentile of two pixels is the larger.
        assert!((accuracy.p99_levels - expected).abs() < 1e-3, "{accuracy} vs {expected}");
        assert_eq!(accuracy.samples, 8 * SAMPLES_PER_PASS);
    }
}
