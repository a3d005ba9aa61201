//! A measured material's own sampler: for each of [`VIEWS`] view elevations, the table's f_r cos(theta_i)
//! over the half vector, tabulated on a grid of nodes and interpolated bilinearly between them, drawn by its
//! marginal over 1 - cos(theta_h) and its conditional over phi_h (as Mitsuba 3's `Marginal2D` draws a
//! bilinear patchwork); `measured_sample` in `shaders/brdf/measured_sampler.glsl` draws half vectors so and
//! reflects the view about them.
//!
//! Why half vectors: a measured metal's lobe is narrow about the mirror direction, where the half vector is
//! the normal, and the MERL table itself is finest there (its theta_h index is sqrt(theta_h / 90 degrees) *
//! 90). The grid's rows follow that index; its columns split phi_h, the half vector's azimuth from the
//! view's, over 0 to 180 degrees (an isotropic table is the same at -phi_h: the sampler draws the side by a
//! coin). Over x = 1 - cos(theta_h) and phi_h the solid angle is dx dphi_h, so the interpolated values are
//! the density itself, and it is continuous: a density that steps from cell to cell is one that the
//! sampling test's cubature cannot bound (its halves agree where a step falls between their nodes). Between
//! two tabulated elevations the sampler draws from either, in proportion to how near the view is, and its
//! density is the same mixture: exact, whatever the view.
//!
//! The distribution is the table's at its nodes, not the model's: the cosine strategy beside it (the
//! material's share, `lobe_share`) covers whatever falls between them.

use std::f64::consts::{FRAC_PI_2, PI};

use glam::{DVec3, Vec3};

/// The view elevations tabulated: theta_o = k 90 / (VIEWS - 1) degrees.
pub const VIEWS: usize = 32;
/// Intervals between the grid's rows of nodes: row r at theta_h = 90 (r / ROWS)^2 degrees.
pub const ROWS: usize = 90;
/// Intervals between each row's nodes: node j at phi_h = 180 j / COLUMNS degrees.
pub const COLUMNS: usize = 32;
/// The floats of one view's distribution: the row intervals' cumulative and own probabilities, the rows'
/// integrals over phi_h (the marginal density at each row), then the nodes' densities row after row.
pub const VIEW_FLOATS: usize = 2 * ROWS + (ROWS + 1) + (ROWS + 1) * (COLUMNS + 1);
/// The floats of a table's sampler.
pub const SAMPLER_FLOATS: usize = VIEWS * VIEW_FLOATS;

/// 1 - cos(theta_h) at row `r` of nodes, as 2 sin^2(theta_h / 2), which keeps its digits near the normal.
/// Mirrors `sampler_row` in `shaders/brdf/measured_sampler.glsl`.
pub fn row_edge(r: usize) -> f64 {
    let u = r as f64 / ROWS as f64;
    let half = 0.5 * FRAC_PI_2 * u * u;
    2.0 * half.sin() * half.sin()
}

/// The view at elevation `k` (of [`VIEWS`]) in the frame where n = +z and the view's azimuth is 0.
pub fn view(k: usize) -> DVec3 {
    let theta = k as f64 * FRAC_PI_2 / (VIEWS - 1) as f64;
    DVec3::new(theta.sin(), 0.0, theta.cos())
}

/// The half vector at 1 - cos(theta_h) = `x` and azimuth phi in that frame.
fn half_vector(x: f64, phi: f64) -> DVec3 {
    let sin_theta = (x * (2.0 - x)).max(0.0).sqrt();
    DVec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), 1.0 - x)
}

/// The integrand over half vectors: f_r cos(theta_i) times the reflection's Jacobian 4 (wo . h) (so that a
/// density in proportion to it is one in proportion to f_r cos(theta_i) over wi), the luminance of f_r; zero
/// where the reflected direction is not above the surface.
fn integrand(f_r: &impl Fn(Vec3, Vec3) -> Vec3, wo: DVec3, h: DVec3) -> f64 {
    let wo_h = wo.dot(h);
    if wo_h <= 0.0 {
        return 0.0;
    }
    let wi = 2.0 * wo_h * h - wo;
    if wi.z <= 0.0 {
        return 0.0;
    }
    let f = f_r(wi.as_vec3().normalize(), wo.as_vec3());
    // Rec. 709's luminance, as the renderer's own samplers weigh colours.
    let luminance = f64::from(f.dot(Vec3::new(0.2126, 0.7152, 0.0722)));
    luminance.max(0.0) * wi.z * 4.0 * wo_h
}

/// View `k`'s distribution from its nodes' values (row after row), in the layout of [`VIEW_FLOATS`]: the
/// density at a node is its value over the integral of the bilinear patchwork over the whole hemisphere of
/// half vectors (twice the half that phi_h from 0 to 180 degrees covers); all zero when that is zero.
fn view_distribution(nodes: &[f64]) -> Vec<f32> {
    let step = PI / COLUMNS as f64;
    // Each row's integral over phi_h (the trapezoids are exact on lines), then each row interval's integral.
    let rows: Vec<f64> = nodes
        .chunks_exact(COLUMNS + 1)
        .map(|row| row.windows(2).map(|pair| 0.5 * (pair[0] + pair[1]) * step).sum())
        .collect();
    let intervals: Vec<f64> =
        (0..ROWS).map(|r| 0.5 * (rows[r] + rows[r + 1]) * (row_edge(r + 1) - row_edge(r))).collect();
    let half: f64 = intervals.iter().sum();
    let scale = if half > 0.0 { 1.0 / half } else { 0.0 };
    let mut floats = Vec::with_capacity(VIEW_FLOATS);
    let mut before = 0.0;
    for interval in &intervals {
        floats.push((before * scale) as f32);
        before += interval;
    }
    floats.extend(intervals.iter().map(|i| (i * scale) as f32));
    floats.extend(rows.iter().map(|m| (m * scale) as f32));
    floats.extend(nodes.iter().map(|v| (0.5 * v * scale) as f32));
    floats
}

/// The sampler of a table whose f_r(wi, wo) about the normal +z is `f_r` (the table's evaluation, which
/// makes its sampler on first use: [`super::measured::MeasuredTable::sampler`]): [`SAMPLER_FLOATS`] floats,
/// view after view, in the layout that `shaders/brdf/measured_sampler.glsl` reads.
pub fn sampler(f_r: impl Fn(Vec3, Vec3) -> Vec3 + Sync) -> Vec<f32> {
    let nodes = crate::parallel::rows((VIEWS * (ROWS + 1)) as u32, |i| {
        let (k, r) = (i as usize / (ROWS + 1), i as usize % (ROWS + 1));
        (0..=COLUMNS)
            .map(|j| integrand(&f_r, view(k), half_vector(row_edge(r), j as f64 * PI / COLUMNS as f64)))
            .collect()
    });
    nodes.chunks_exact((ROWS + 1) * (COLUMNS + 1)).flat_map(view_distribution).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Where view `k`'s row interval probabilities and its nodes' densities begin.
    fn probabilities(k: usize) -> usize {
        k * VIEW_FLOATS + ROWS
    }
    fn node(k: usize, r: usize, j: usize) -> usize {
        k * VIEW_FLOATS + 3 * ROWS + 1 + r * (COLUMNS + 1) + j
    }

    #[test]
    fn the_rows_follow_the_tables_theta_h_index() {
        // Row r at theta_h = 90 (r / 90)^2 degrees: row 30 at 10 degrees.
        assert!((row_edge(30) - (1.0 - 10f64.to_radians().cos())).abs() < 1e-12);
        assert_eq!(row_edge(0), 0.0);
        assert!((row_edge(ROWS) - 1.0).abs() < 1e-12);
        // Near the normal 2 sin^2 keeps the digits 1 - cos loses: row 1, theta_h = 0.011 degrees.
        let theta = FRAC_PI_2 / (ROWS * ROWS) as f64;
        assert!((row_edge(1) / (theta * theta / 2.0) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn a_constant_tables_distribution_is_cos_theta_i_by_hand() {
        // f_r constant: seen from the normal, the density over half vectors is in proportion to
        // cos(theta_i) 4 (wo . h) = 4 cos(theta_h) cos(2 theta_h) where theta_h < 45 degrees (the view then
        // reflects above the surface), whatever phi_h. With x = 1 - cos(theta_h), c = 1 - x, that is
        // 4 c (2 c^2 - 1), whose integral over x from 0 to 1 - cos 45 degrees is 1/2, over phi_h 2 pi: the
        // density is 4 c (2 c^2 - 1) / pi.
        let floats = sampler(|_, _| Vec3::ONE);
        for r in [0, 10, 40, 62] {
            let c = 1.0 - row_edge(r);
            let expected = 4.0 * c * (2.0 * c * c - 1.0) / PI;
            for j in [0, 7, COLUMNS] {
                let got = f64::from(floats[node(0, r, j)]);
                // The patchwork's integral is a trapezoid rule's, a little off the exact 1/2.
                assert!((got / expected - 1.0).abs() < 2e-3, "row {r}, node {j}: {got} against {expected}");
            }
        }
        // Past 45 degrees nothing.
        assert_eq!(floats[node(0, 70, 3)], 0.0);
        // The row intervals' probabilities add up to 1, their cumulative ones in order.
        let total: f32 = floats[probabilities(0)..probabilities(0) + ROWS].iter().sum();
        assert!((total - 1.0).abs() < 1e-5, "{total}");
        assert!((floats[11] - floats[10] - floats[probabilities(0) + 10]).abs() < 1e-7);
    }

    #[test]
    fn a_grazing_view_draws_towards_itself_and_nothing_from_a_table_that_measures_nothing() {
        let floats = sampler(|_, _| Vec3::ONE);
        // At 90 degrees the view only reflects above the surface about half vectors leaning its way
        // (phi_h < 90 degrees).
        assert!(floats[node(VIEWS - 1, 40, 0)] > 0.0);
        assert_eq!(floats[node(VIEWS - 1, 40, COLUMNS)], 0.0);
        let nothing = sampler(|_, _| Vec3::ZERO);
        assert!(nothing.iter().all(|&v| v == 0.0));
    }

    #[test]
    fn the_shaders_read_the_layout_made_here() {
        let sampler = include_str!("../../shaders/brdf/measured_sampler.glsl");
        for (name, value) in [("VIEWS", VIEWS), ("ROWS", ROWS), ("COLUMNS", COLUMNS)] {
            assert!(sampler.contains(&format!("const uint SAMPLER_{name} = {value}u;")), "SAMPLER_{name}");
        }
        let tables = include_str!("../../shaders/brdf/measured.glsl");
        assert!(tables.contains(&format!("const uint MEASURED_SAMPLER_FLOATS = {SAMPLER_FLOATS}u;")));
    }
}
