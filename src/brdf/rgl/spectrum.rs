//! Spectral RGL files reduced to RGB: each measured spectrum's CIE 1931 XYZ (2-degree observer) under the
//! equal-energy illuminant E, taken to D65 by Bradford's adaptation, then to linear sRGB (IEC 61966-2-1's
//! primaries). The colour-matching functions are Wyman, Sloan and Shirley's multi-lobe fit (2013, "Simple
//! Analytic Approximations to the CIE XYZ Color Matching Functions", JCGT 2(2)), within about 1% of the
//! tables. Integrated by trapezoids over the file's own wavelengths, each of X, Y and Z normalised by its
//! function's integral there, so that a flat spectrum is E's white exactly and becomes sRGB's white.

use glam::{Mat3, Vec3};

/// One lobe of the fit: a Gaussian of mean `mu` (nm) with its width `below` left of it and `above` right.
fn lobe(lambda: f32, mu: f32, below: f32, above: f32) -> f32 {
    let sigma = if lambda < mu { below } else { above };
    (-0.5 * ((lambda - mu) / sigma).powi(2)).exp()
}

/// x-bar, y-bar and z-bar of CIE 1931 at `lambda` nanometres (Wyman, Sloan and Shirley's fit).
pub fn cie_1931(lambda: f32) -> Vec3 {
    Vec3::new(
        1.056 * lobe(lambda, 599.8, 37.9, 31.0) + 0.362 * lobe(lambda, 442.0, 16.0, 26.7)
            - 0.065 * lobe(lambda, 501.1, 20.4, 26.2),
        0.821 * lobe(lambda, 568.8, 46.9, 40.5) + 0.286 * lobe(lambda, 530.9, 16.3, 31.1),
        1.217 * lobe(lambda, 437.0, 11.8, 36.0) + 0.681 * lobe(lambda, 459.0, 26.0, 13.8),
    )
}

/// XYZ to linear sRGB (IEC 61966-2-1), columns as glam takes them.
const XYZ_TO_SRGB: Mat3 = Mat3::from_cols_array(&[
    3.2406, -0.9689, 0.0557, //
    -1.5372, 1.8758, -0.2040, //
    -0.4986, 0.0415, 1.0570,
]);

/// Bradford's XYZ to cone responses, columns as glam takes them.
const BRADFORD: Mat3 = Mat3::from_cols_array(&[
    0.8951, -0.7502, 0.0389, //
    0.2664, 1.7135, -0.0685, //
    -0.1614, 0.0367, 1.0296,
]);

/// D65's white, Y = 1.
const D65: Vec3 = Vec3::new(0.95047, 1.0, 1.08883);

/// Per wavelength of `wavelengths` (nm, increasing), the weights that make red, green and blue of a spectrum
/// sampled there: `rgb = sum over k of weights[k] * spectrum[k]`.
///
/// # Errors
/// Fewer than 2 wavelengths, not increasing, or none where the eye sees (the functions integrate to 0).
pub fn rgb_weights(wavelengths: &[f32]) -> Result<Vec<Vec3>, String> {
    if wavelengths.len() < 2 || wavelengths.windows(2).any(|w| w[0] >= w[1]) {
        return Err("the wavelengths are fewer than 2 or not increasing".into());
    }
    // Trapezoids: each sample's share of the range.
    let n = wavelengths.len();
    let widths: Vec<f32> =
        (0..n).map(|k| 0.5 * (wavelengths[(k + 1).min(n - 1)] - wavelengths[k.saturating_sub(1)])).collect();
    let xyz: Vec<Vec3> = wavelengths.iter().zip(&widths).map(|(&l, &w)| cie_1931(l) * w).collect();
    let totals: Vec3 = xyz.iter().sum();
    if totals.min_element() <= 1e-3 {
        return Err(format!("the wavelengths {} to {} nm miss what the eye sees", wavelengths[0], wavelengths[n - 1]));
    }
    let e_to_d65 = BRADFORD.inverse() * Mat3::from_diagonal(BRADFORD * D65 / (BRADFORD * Vec3::ONE)) * BRADFORD;
    let to_rgb = XYZ_TO_SRGB * e_to_d65;
    Ok(xyz.iter().map(|&weights| to_rgb * (weights / totals)).collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_fit_peaks_where_cie_1931_does() {
        // By hand: y-bar(555) = 0.821 exp(-0.5 (13.8 / 46.9)^2) + 0.286 exp(-0.5 (24.1 / 31.1)^2) = 0.998.
        assert!((cie_1931(555.0).y - 0.998).abs() < 1e-3, "{}", cie_1931(555.0));
        // The tables' peaks: x-bar 1.062 at 600 nm, z-bar 1.782 at 445 nm (within the fit's 1%... 3%).
        assert!((cie_1931(600.0).x - 1.062).abs() < 0.02);
        assert!((cie_1931(445.0).z - 1.782).abs() < 0.06);
    }

    #[test]
    fn a_flat_spectrum_is_white_and_a_red_one_red() {
        let wavelengths: Vec<f32> = (0..=40).map(|k| 380.0 + 10.0 * k as f32).collect();
        let weights = rgb_weights(&wavelengths).unwrap();
        let of = |spectrum: &dyn Fn(f32) -> f32| -> Vec3 {
            wavelengths.iter().zip(&weights).map(|(&l, &w)| w * spectrum(l)).sum()
        };
        let grey = of(&|_| 0.5);
        assert!((grey - Vec3::splat(0.5)).abs().max_element() < 1e-3, "{grey}");
        let red = of(&|l| if l >= 620.0 { 1.0 } else { 0.0 });
        assert!(red.x > 5.0 * red.y.abs() && red.x > 5.0 * red.z.abs(), "{red}");
        assert!(rgb_weights(&[500.0, 400.0]).is_err());
        assert!(rgb_weights(&[900.0, 1000.0]).unwrap_err().contains("miss what the eye sees"));
    }
}
