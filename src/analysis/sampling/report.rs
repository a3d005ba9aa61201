//! The sampling test as pictures and numbers: per view, the samples' histogram over the upper hemisphere, the
//! counts the density expects and their difference in standard deviations, side by side as Mitsuba's χ²
//! plots show them (on the equal-area (φ, cos θ) grid the statistic counts on); and the verdicts as CSV.

use plotters::coord::Shift;
use plotters::prelude::*;

use super::{SamplingReport, ViewOutcome, GRID};
use crate::pictures::chart::{short_number, text, Chart, Drawn};

/// The difference map's ends, in standard deviations of a cell's count.
const DEVIATIONS: f64 = 5.0;

const PANEL_WIDTH: u32 = 500;
const ROW_HEIGHT: u32 = 230;
const TITLE: u32 = 40;

/// The report's picture.
pub struct SamplingChart<'a> {
    /// Above the rows.
    pub title: String,
    /// The test drawn.
    pub report: &'a SamplingReport,
}

/// A view's row caption: its angles and its χ² verdict.
fn caption(view: &ViewOutcome, level_each: f64) -> String {
    let chi = &view.chi_square;
    format!(
        "θo {}°, φo {}°: χ² p = {:.3e}, {}",
        view.theta_o,
        view.phi_o,
        chi.p_value,
        if chi.passes(level_each) { "passes" } else { "FAILS" }
    )
}

/// Red for counts above those expected, blue below, white where they agree.
fn diverging(value: f64) -> RGBColor {
    let t = (value / DEVIATIONS).clamp(-1.0, 1.0);
    let fade = |c: u8, t: f64| (255.0 + (f64::from(c) - 255.0) * t) as u8;
    if t >= 0.0 {
        RGBColor(fade(202, t), fade(0, t), fade(32, t))
    } else {
        RGBColor(fade(5, -t), fade(113, -t), fade(176, -t))
    }
}

impl Chart for SamplingChart<'_> {
    fn size(&self) -> (u32, u32) {
        (3 * PANEL_WIDTH, TITLE + ROW_HEIGHT * self.report.views.len() as u32)
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let area = area.titled(&self.title, text(20.0))?;
        let rows = area.split_evenly((self.report.views.len(), 1));
        for (row, view) in rows.iter().zip(&self.report.views) {
            let row = row.titled(&caption(view, self.report.level_each), text(16.0))?;
            draw_view(&row, view)?;
        }
        Ok(())
    }
}

/// One view's three panels.
fn draw_view<DB: DrawingBackend>(row: &DrawingArea<DB, Shift>, view: &ViewOutcome) -> Drawn<DB> {
    let upper = GRID.cells() / 2;
    let total = view.samples as f64;
    let observed: Vec<f64> = view.histogram[upper..].iter().map(|&c| c as f64).collect();
    let expected: Vec<f64> = view.cells.probability[upper..].iter().map(|p| p.max(0.0) * total).collect();
    let most = observed.iter().chain(&expected).fold(1.0f64, |m, &v| m.max(v));
    let deviations: Vec<f64> = observed
        .iter()
        .zip(&expected)
        .map(|(o, e)| {
            if *e > 0.0 {
                (o - e) / e.sqrt()
            } else if *o > 0.0 {
                DEVIATIONS
            } else {
                0.0
            }
        })
        .collect();
    let count_colour = |v: f64| {
        let [r, g, b] = check_rules::viridis(v / most);
        RGBColor(r, g, b)
    };
    let panels = row.split_evenly((1, 3));
    let counts = format!("0 to {most:.0} a cell");
    draw_panel(&panels[0], &format!("samples ({counts})"), &observed, count_colour)?;
    draw_panel(&panels[1], &format!("density × samples ({counts})"), &expected, count_colour)?;
    let caption = format!("(samples − expected) / √expected, ±{DEVIATIONS}");
    draw_panel(&panels[2], &caption, &deviations, diverging)
}

/// A panel of the upper hemisphere's cells, φ across from 0° to 360° (Mitsuba's plots': the lobe about the
/// mirror of a view at φo = 0 in the middle) and cos θ up, coloured by `colour`.
fn draw_panel<DB: DrawingBackend>(
    panel: &DrawingArea<DB, Shift>,
    caption: &str,
    values: &[f64],
    colour: impl Fn(f64) -> RGBColor,
) -> Drawn<DB> {
    let mut chart = ChartBuilder::on(panel)
        .caption(caption, text(13.0))
        .margin(8)
        .x_label_area_size(34)
        .y_label_area_size(44)
        .build_cartesian_2d(0.0..360.0, 0.0..1.0)?;
    chart
        .configure_mesh()
        .disable_mesh()
        .x_labels(7)
        .y_labels(3)
        .x_label_formatter(&|x| short_number(*x))
        .y_label_formatter(&|y| short_number(*y))
        .x_desc("φ (degrees)")
        .y_desc("cos θ")
        .label_style(text(12.0))
        .axis_desc_style(text(12.0))
        .draw()?;
    let (rows, columns) = (GRID.cos_bins / 2, GRID.phi_bins);
    let (height, width) = (1.0 / rows as f64, 360.0 / columns as f64);
    chart.draw_series(values.iter().enumerate().map(|(k, &value)| {
        let (row, column) = ((k / columns) as f64, (k % columns) as f64);
        let x = (180.0 + column * width) % 360.0;
        Rectangle::new([(x, row * height), (x + width, (row + 1.0) * height)], colour(value).filled())
    }))?;
    Ok(())
}

/// The numbers per view as CSV: the χ² test, the density's integral, the estimator and the albedo, and
/// whether every test at the view passed.
pub fn views_csv(report: &SamplingReport) -> String {
    let mut csv = String::from(
        "theta_o,phi_o,samples,chi_square,degrees_of_freedom,p_value,level,cells_pooled,impossible_samples,\
         no_sample,no_sample_tested,invalid,density_integral,density_bound,density_below,estimate_r,estimate_g,estimate_b,\
         standard_error_r,standard_error_g,standard_error_b,albedo_r,albedo_g,albedo_b,albedo_bound,passed\n",
    );
    for view in &report.views {
        let chi = &view.chi_square;
        let (integral, bound) = view.density_integral();
        let albedo = view.albedo();
        let passed = report.verdicts.iter().filter(|v| v.view == Some((view.theta_o, view.phi_o))).all(|v| v.passed);
        let row: Vec<String> = [view.theta_o, view.phi_o, view.samples as f64, chi.statistic]
            .iter()
            .map(f64::to_string)
            .chain([chi.degrees_of_freedom.to_string(), chi.p_value.to_string(), report.level_each.to_string()])
            .chain([chi.pooled.to_string(), chi.impossible.to_string(), view.no_sample.to_string()])
            .chain([view.no_sample_tested.to_string(), view.invalid.to_string()])
            .chain([integral, bound, view.density_below()].map(|v| v.to_string()))
            .chain(view.estimate.iter().chain(&view.standard_error).chain(&albedo).map(f64::to_string))
            .chain([view.cells.f_cos_error.to_string(), passed.to_string()])
            .collect();
        csv.push_str(&row.join(","));
        csv.push('\n');
    }
    csv
}
