//! The piecewise-bilinear 2D distributions of Dupuy and Jakob's parameterisation (2018, "An Adaptive
//! Parameterization for Efficient Material Acquisition and Rendering", section 5), as Mitsuba's `measured`
//! model reads RGL files with them: values at the nodes of a regular grid over `[0, 1]^2` (x the fastest),
//! one grid per combination of parameter values (theta_i, phi_i, ...), each parameter interpolated linearly
//! between the grids. A grid is either read as it is (a function: the NDF, the projected area, the spectra) or
//! as a density, normalised to integrate to 1 over the square, with its cumulative sums, so that a point of
//! the square maps to a uniform variate and back (the VNDF, the luminance).

use glam::Vec2;

/// A 2D function or density on `[0, 1]^2`, with its grids per parameter values.
#[derive(Clone, Debug)]
pub struct Grid2D {
    /// Nodes along x and y (at least 2 each).
    width: usize,
    height: usize,
    /// Each parameter's values, increasing, the outermost dimension of the data first.
    parameters: Vec<Vec<f32>>,
    /// The values of every grid, one after the other (normalised for a density).
    values: Vec<f32>,
    /// For a density: per grid and row, the integral of the row from its start to each node ...
    conditional: Vec<f32>,
    /// ... and per grid, the integral up to each row's node (the last 1).
    marginal: Vec<f32>,
    /// Whether it is a density (with the sums above).
    density: bool,
}

/// The grids a parameter point falls between, with their weights.
type Corners = Vec<(usize, f32)>;

impl Grid2D {
    /// A function: `values` (every grid of `height` rows of `width`, the grids in the parameters' order, the
    /// last parameter fastest) interpolated as they are.
    ///
    /// # Errors
    /// A size that does not agree with the values, fewer than 2 nodes a side, a parameter with no value or
    /// out of order.
    pub fn function(values: Vec<f32>, width: usize, height: usize, parameters: Vec<Vec<f32>>) -> Result<Self, String> {
        let grid =
            Self { width, height, parameters, values, conditional: Vec::new(), marginal: Vec::new(), density: false };
        grid.check()?;
        Ok(grid)
    }

    /// A density: each grid normalised to integrate to 1 over the square, with its cumulative sums.
    ///
    /// # Errors
    /// As [`Grid2D::function`], and a grid with a negative value or that integrates to 0.
    pub fn density(values: Vec<f32>, width: usize, height: usize, parameters: Vec<Vec<f32>>) -> Result<Self, String> {
        let mut grid = Self::function(values, width, height, parameters)?;
        grid.density = true;
        let (w, h) = (width, height);
        let cells = w * h;
        grid.conditional = vec![0.0; grid.values.len()];
        grid.marginal = vec![0.0; grid.values.len() / w];
        for (slice, values) in grid.values.chunks_mut(cells).enumerate() {
            if values.iter().any(|&v| v < 0.0) {
                return Err(format!("grid {slice} has a negative value"));
            }
            // The integral of the linear interpolant along each row, in units of a cell's side, then down the
            // rows' totals: trapezoids are exact for linear pieces.
            let conditional = &mut grid.conditional[slice * cells..(slice + 1) * cells];
            for y in 0..h {
                let mut sum = 0.0f64;
                for x in 1..w {
                    sum += 0.5 * (f64::from(values[y * w + x - 1]) + f64::from(values[y * w + x]));
                    conditional[y * w + x] = sum as f32;
                }
            }
            let marginal = &mut grid.marginal[slice * h..(slice + 1) * h];
            let mut sum = 0.0f64;
            for y in 1..h {
                sum += 0.5 * (f64::from(conditional[y * w - 1]) + f64::from(conditional[(y + 1) * w - 1]));
                marginal[y] = sum as f32;
            }
            if sum <= 0.0 {
                return Err(format!("grid {slice} integrates to 0"));
            }
            let scale = (1.0 / sum) as f32;
            for v in values.iter_mut().chain(conditional.iter_mut()).chain(marginal.iter_mut()) {
                *v *= scale;
            }
        }
        Ok(grid)
    }

    /// Appends the grid's floats to `out` (its values, then for a density its conditional and marginal
    /// sums) and returns its header as the GPU reads it (`RglGrid` of `shaders/brdf/rgl.glsl`): width,
    /// height, and the offsets of the three arrays in `out` (a function's last two are its values' offset).
    pub fn pack(&self, out: &mut Vec<f32>) -> [u32; 5] {
        let offset = |out: &Vec<f32>| out.len() as u32;
        let values = offset(out);
        out.extend_from_slice(&self.values);
        let conditional = offset(out);
        out.extend_from_slice(&self.conditional);
        let marginal = offset(out);
        out.extend_from_slice(&self.marginal);
        [self.width as u32, self.height as u32, values, conditional, marginal]
    }

    /// Each parameter's values.
    pub fn parameters(&self) -> &[Vec<f32>] {
        &self.parameters
    }

    fn check(&self) -> Result<(), String> {
        if self.width < 2 || self.height < 2 {
            return Err(format!("a grid of {} x {} nodes: at least 2 x 2", self.width, self.height));
        }
        for (k, values) in self.parameters.iter().enumerate() {
            if values.is_empty() || values.windows(2).any(|p| p[0] >= p[1]) {
                return Err(format!("parameter {k}'s values are empty or not increasing"));
            }
        }
        let grids: usize = self.parameters.iter().map(Vec::len).product();
        if grids.checked_mul(self.width * self.height) != Some(self.values.len()) {
            return Err(format!(
                "{} values for {grids} grids of {} x {} nodes",
                self.values.len(),
                self.width,
                self.height
            ));
        }
        Ok(())
    }

    /// The grids around `parameter` (one value per parameter) and their weights: per parameter the two values
    /// around it (clamped at the ends), linearly.
    fn corners(&self, parameter: &[f32]) -> Corners {
        let mut corners: Corners = vec![(0, 1.0)];
        let mut stride: usize = self.parameters.iter().map(Vec::len).product();
        for (values, &p) in self.parameters.iter().zip(parameter) {
            stride /= values.len();
            if values.len() == 1 {
                continue;
            }
            let below = values[..values.len() - 1].iter().rposition(|&v| v <= p).unwrap_or(0);
            let t = ((p - values[below]) / (values[below + 1] - values[below])).clamp(0.0, 1.0);
            corners = corners
                .iter()
                .flat_map(|&(grid, w)| [(grid + below * stride, w * (1.0 - t)), (grid + (below + 1) * stride, w * t)])
                .collect();
        }
        corners
    }

    /// `array`'s entry `index` of each grid (of `per_grid` entries), weighed by the corners.
    fn lookup(array: &[f32], per_grid: usize, corners: &Corners, index: usize) -> f32 {
        corners.iter().map(|&(grid, w)| w * array[grid * per_grid + index]).sum()
    }

    /// The cell of `position` (clamped into the square) and the position within it.
    fn cell(&self, position: Vec2) -> ((usize, usize), Vec2) {
        let scaled =
            position.clamp(Vec2::ZERO, Vec2::ONE) * Vec2::new((self.width - 1) as f32, (self.height - 1) as f32);
        let x = (scaled.x as usize).min(self.width - 2);
        let y = (scaled.y as usize).min(self.height - 2);
        ((x, y), scaled - Vec2::new(x as f32, y as f32))
    }

    /// The values at the cell's four corners: (x, y), (x + 1, y), (x, y + 1), (x + 1, y + 1).
    fn corner_values(&self, corners: &Corners, (x, y): (usize, usize)) -> [f32; 4] {
        let (w, cells) = (self.width, self.width * self.height);
        let at = |i| Self::lookup(&self.values, cells, corners, i);
        [at(y * w + x), at(y * w + x + 1), at((y + 1) * w + x), at((y + 1) * w + x + 1)]
    }

    /// The value at `position` (bilinear between the nodes, the parameters linear between the grids); for a
    /// density, the density over the square.
    pub fn eval(&self, position: Vec2, parameter: &[f32]) -> f32 {
        let corners = self.corners(parameter);
        let (cell, f) = self.cell(position);
        let [v00, v10, v01, v11] = self.corner_values(&corners, cell);
        let value = (1.0 - f.y) * ((1.0 - f.x) * v00 + f.x * v10) + f.y * ((1.0 - f.x) * v01 + f.x * v11);
        value * self.cells_per_unit()
    }

    fn cells_per_unit(&self) -> f32 {
        if self.density {
            ((self.width - 1) * (self.height - 1)) as f32
        } else {
            1.0
        }
    }

    /// A density's cumulative distribution at `position`: the uniform variate that [`Grid2D::sample`] maps to
    /// it (y by the marginal, x by the conditional at that y), and the density there.
    pub fn invert(&self, position: Vec2, parameter: &[f32]) -> (Vec2, f32) {
        let corners = self.corners(parameter);
        let (w, h, cells) = (self.width, self.height, self.width * self.height);
        let ((x, y), f) = self.cell(position);
        let [v00, v10, v01, v11] = self.corner_values(&corners, (x, y));
        // The density along x at this y is linear from c0 to c1 over the cell.
        let c0 = (1.0 - f.y) * v00 + f.y * v01;
        let c1 = (1.0 - f.y) * v10 + f.y * v11;
        let density = ((1.0 - f.x) * c0 + f.x * c1) * self.cells_per_unit();
        let conditional = |i| Self::lookup(&self.conditional, cells, &corners, i);
        let before = (1.0 - f.y) * conditional(y * w + x) + f.y * conditional((y + 1) * w + x);
        let row_total = |row| conditional(row * w + w - 1);
        let (r0, r1) = (row_total(y), row_total(y + 1));
        let u = (before + f.x * (c0 + 0.5 * f.x * (c1 - c0))) / ((1.0 - f.y) * r0 + f.y * r1);
        let v = Self::lookup(&self.marginal, h, &corners, y) + f.y * (r0 + 0.5 * f.y * (r1 - r0));
        (Vec2::new(u, v), density)
    }

    /// The point of the square a uniform variate maps to under a density (the inverse of
    /// [`Grid2D::invert`]), and the density there.
    pub fn sample(&self, variate: Vec2, parameter: &[f32]) -> (Vec2, f32) {
        let corners = self.corners(parameter);
        let (w, h, cells) = (self.width, self.height, self.width * self.height);
        let mut u = variate.clamp(Vec2::splat(f32::EPSILON), Vec2::splat(1.0 - f32::EPSILON));
        let marginal = |row| Self::lookup(&self.marginal, h, &corners, row);
        let y = (0..h - 1).rev().find(|&row| marginal(row) <= u.y).unwrap_or(0);
        u.y -= marginal(y);
        let conditional = |i| Self::lookup(&self.conditional, cells, &corners, i);
        let (r0, r1) = (conditional(y * w + w - 1), conditional((y + 1) * w + w - 1));
        let t = solve_linear_ramp(u.y, r0, r1);
        u.x *= (1.0 - t) * r0 + t * r1;
        let along = |i| (1.0 - t) * conditional(y * w + i) + t * conditional((y + 1) * w + i);
        let x = (0..w - 1).rev().find(|&i| along(i) <= u.x).unwrap_or(0);
        u.x -= along(x);
        let [v00, v10, v01, v11] = self.corner_values(&corners, (x, y));
        let (c0, c1) = ((1.0 - t) * v00 + t * v01, (1.0 - t) * v10 + t * v11);
        let s = solve_linear_ramp(u.x, c0, c1);
        let point = Vec2::new((x as f32 + s) / (w - 1) as f32, (y as f32 + t) / (h - 1) as f32);
        (point, ((1.0 - s) * c0 + s * c1) * self.cells_per_unit())
    }
}

/// The fraction s of a cell where the integral of a density rising linearly from `a` to `b` across it,
/// s (a + s (b - a) / 2), reaches `area`.
fn solve_linear_ramp(area: f32, a: f32, b: f32) -> f32 {
    let s = if (a - b).abs() < 1e-4 * (a + b) {
        2.0 * area / (a + b)
    } else {
        (a - (a * a + 2.0 * area * (b - a)).max(0.0).sqrt()) / (a - b)
    };
    if s.is_finite() {
        s.clamp(0.0, 1.0)
    } else {
        0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_function_is_bilinear_between_its_nodes_and_linear_between_its_grids() {
        // Two grids of 2 x 2 nodes, for a parameter at 0 and 2: f(x, y) = 1 + x + 2y, then its double.
        let values = vec![1.0, 2.0, 3.0, 4.0, 2.0, 4.0, 6.0, 8.0];
        let grid = Grid2D::function(values, 2, 2, vec![vec![0.0, 2.0]]).unwrap();
        assert_eq!(grid.eval(Vec2::new(0.25, 0.5), &[0.0]), 1.0 + 0.25 + 1.0);
        assert_eq!(grid.eval(Vec2::new(0.25, 0.5), &[2.0]), 2.0 * 2.25);
        // Halfway between the grids, and past the last (clamped).
        assert_eq!(grid.eval(Vec2::new(0.25, 0.5), &[1.0]), 1.5 * 2.25);
        assert_eq!(grid.eval(Vec2::new(1.0, 1.0), &[7.0]), 8.0);
    }

    #[test]
    fn a_density_integrates_to_1_and_its_cumulative_distribution_is_computed_by_hand() {
        // 3 x 2 nodes: rows (1, 1, 1) and (1, 3, 1). Row integrals in cell units: 2 and 4; the square's,
        // (2 + 4) / 2 = 3. Normalised to the unit square (2 cells by 1): the density is value / 3 * 2.
        let grid = Grid2D::density(vec![1.0, 1.0, 1.0, 1.0, 3.0, 1.0], 3, 2, Vec::new()).unwrap();
        assert!((grid.eval(Vec2::new(0.5, 1.0), &[]) - 2.0).abs() < 1e-6);
        assert!((grid.eval(Vec2::new(0.0, 0.0), &[]) - 2.0 / 3.0).abs() < 1e-6);
        // The cumulative distribution at y = 1 is 1 whatever x; at x = 1, y = 0.5: the marginal up to half the
        // height, 0.5 (r0 + 0.5 * 0.5 (r1 - r0)) with the rows' totals r0 = 2/3 and r1 = 4/3: 0.41667.
        let (top, _) = grid.invert(Vec2::new(0.3, 1.0), &[]);
        assert!((top.y - 1.0).abs() < 1e-6, "{top}");
        let (middle, _) = grid.invert(Vec2::new(1.0, 0.5), &[]);
        assert!((middle.x - 1.0).abs() < 1e-6 && (middle.y - 0.5 * (2.0 + 0.25 * 2.0) / 3.0).abs() < 1e-6, "{middle}");
        // On the bottom row (all 1s) x's distribution is uniform.
        assert!((grid.invert(Vec2::new(0.3, 0.0), &[]).0.x - 0.3).abs() < 1e-6);
    }

    #[test]
    fn sampling_inverts_the_cumulative_distribution() {
        let values: Vec<f32> = (0..5 * 4 * 2).map(|i| 0.2 + ((i * 7919) % 13) as f32 / 4.0).collect();
        let grid = Grid2D::density(values, 5, 4, vec![vec![0.0, 1.0]]).unwrap();
        let mut worst = 0.0f32;
        for i in 1..20 {
            for j in 1..20 {
                let point = Vec2::new(i as f32 / 20.0, j as f32 / 20.0);
                for parameter in [0.0, 0.3, 1.0] {
                    let (variate, density) = grid.invert(point, &[parameter]);
                    let (back, sampled_density) = grid.sample(variate, &[parameter]);
                    worst = worst.max((back - point).abs().max_element());
                    assert!((density - sampled_density).abs() <= 1e-4 * density, "{density} {sampled_density}");
                }
            }
        }
        assert!(worst < 1e-4, "{worst}");
    }

    #[test]
    fn sizes_that_do_not_agree_are_refused() {
        assert!(Grid2D::function(vec![0.0; 4], 2, 2, vec![vec![0.0, 1.0]])
            .unwrap_err()
            .contains("4 values for 2 grids"));
        assert!(Grid2D::function(vec![0.0; 2], 2, 1, Vec::new()).unwrap_err().contains("at least 2 x 2"));
        assert!(Grid2D::function(vec![0.0; 8], 2, 2, vec![vec![1.0, 0.0]]).unwrap_err().contains("not increasing"));
        assert!(Grid2D::density(vec![0.0; 4], 2, 2, Vec::new()).unwrap_err().contains("integrates to 0"));
        assert!(Grid2D::density(vec![1.0, -1.0, 1.0, 1.0], 2, 2, Vec::new()).unwrap_err().contains("negative"));
    }
}
