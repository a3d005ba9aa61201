//! Charts of the analysis (lobes, albedos, furnace tables) drawn with plotters into PNG or SVG, their text
//! anti-aliased from a font embedded in the binary (DejaVu Sans, `assets/fonts/`): no system font needed.
//!
//! A chart is a [`Chart`]: it draws itself on any plotters backend, and [`write_chart`] picks the backend by
//! the file's extension and writes it the way every output is written (a temporary file renamed).

use std::path::Path;

use plotters::coord::Shift;
use plotters::prelude::*;

use crate::error::{Error, Result};
use crate::pictures::output::{write_file, write_png};

/// The family name the embedded font ([`crate::pictures::text::FONT`]) is registered under, once.
const FAMILY: &str = "sans-serif";

/// A distinct colour per series (Tableau 10), taken in turn.
pub const PALETTE: [RGBColor; 10] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
    RGBColor(188, 189, 34),
    RGBColor(23, 190, 207),
];

/// The coordinates of every chart here: two real axes.
pub type Plane = Cartesian2d<plotters::coord::types::RangedCoordf64, plotters::coord::types::RangedCoordf64>;

/// The result plotters' drawing returns on a backend.
pub type Drawn<DB> = std::result::Result<(), DrawingAreaErrorKind<<DB as DrawingBackend>::ErrorType>>;

/// Something that draws itself on a drawing area of any backend.
pub trait Chart {
    /// The picture's size in pixels.
    fn size(&self) -> (u32, u32);

    /// Draws the chart on `area`, which is [`Chart::size`] large.
    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Drawn<DB>;
}

/// The kinds of file a chart may be written to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ChartFile {
    /// A PNG image (`.png`), drawn with the embedded font.
    Png,
    /// An SVG drawing (`.svg`).
    Svg,
}

impl ChartFile {
    /// The kind `path` names by its extension, if it is a picture.
    pub fn for_path(path: &Path) -> Option<Self> {
        match path.extension().and_then(|e| e.to_str()).map(str::to_ascii_lowercase).as_deref() {
            Some("png") => Some(Self::Png),
            Some("svg") => Some(Self::Svg),
            _ => None,
        }
    }
}

/// Draws `chart` and writes it to `path` as the picture its extension names (.png or .svg).
///
/// # Errors
/// `Error::Output` naming the path.
pub fn write_chart(chart: &impl Chart, path: &Path) -> Result<()> {
    let failed = |message: String| Error::Output { path: path.to_path_buf(), message };
    match ChartFile::for_path(path) {
        Some(ChartFile::Png) => write_png(&chart_pixels(chart).map_err(failed)?, path),
        Some(ChartFile::Svg) => write_file(path, chart_svg(chart).map_err(failed)?.as_bytes()),
        None => Err(failed("a chart is written as .png or .svg".into())),
    }
}

/// The chart drawn into an image of its size; the error says what failed.
fn chart_pixels(chart: &impl Chart) -> std::result::Result<image::RgbImage, String> {
    register_font();
    let failed = |e: String| format!("cannot draw the chart: {e}");
    let (width, height) = chart.size();
    let mut pixels = vec![255u8; width as usize * height as usize * 3];
    {
        let area = BitMapBackend::with_buffer(&mut pixels, (width, height)).into_drawing_area();
        chart.draw(&area).map_err(|e| failed(e.to_string()))?;
        area.present().map_err(|e| failed(e.to_string()))?;
    }
    image::RgbImage::from_raw(width, height, pixels)
        .ok_or_else(|| failed("the picture's buffer has the wrong size".into()))
}

/// The chart as an SVG document; the error says what failed.
pub fn chart_svg(chart: &impl Chart) -> std::result::Result<String, String> {
    register_font();
    let failed = |e: String| format!("cannot draw the chart: {e}");
    let mut svg = String::new();
    {
        let area = SVGBackend::with_string(&mut svg, chart.size()).into_drawing_area();
        chart.draw(&area).map_err(|e| failed(e.to_string()))?;
        area.present().map_err(|e| failed(e.to_string()))?;
    }
    Ok(svg)
}

fn register_font() {
    static ONCE: std::sync::Once = std::sync::Once::new();
    ONCE.call_once(|| {
        // The font is part of the binary: it parses, or the build is broken (a test draws every chart).
        if plotters::style::register_font(FAMILY, FontStyle::Normal, crate::pictures::text::FONT).is_err() {
            log::error!("the embedded font does not parse: charts will have no text");
        }
    });
}

/// The text style of a chart: the embedded font at `size` pixels.
pub fn text(size: f64) -> TextStyle<'static> {
    TextStyle::from(FontDesc::new(FontFamily::Name(FAMILY), size, FontStyle::Normal))
}

/// One curve: its legend, its colour and its points.
#[derive(Clone, Debug)]
pub struct Series {
    /// Its legend entry.
    pub label: String,
    /// Its line colour.
    pub colour: RGBColor,
    /// (x, y) in the chart's axis units, drawn in order.
    pub points: Vec<(f64, f64)>,
    /// Drawn dashed (a second quantity of the same material, e.g. a bound).
    pub dashed: bool,
}

/// A plain x-y chart: a title, labelled axes over given ranges, the series and their legend, and straight
/// reference lines (e.g. y = 1 in a furnace plot).
#[derive(Clone, Debug)]
pub struct LineChart {
    /// Above the plot; empty for none.
    pub title: String,
    /// The x axis's title.
    pub x_label: String,
    /// The y axis's title.
    pub y_label: String,
    /// The x axis's span, (least, greatest).
    pub x_range: (f64, f64),
    /// The y axis's span, (least, greatest).
    pub y_range: (f64, f64),
    /// The curves, drawn in order, each with its legend entry.
    pub series: Vec<Series>,
    /// y values at which a black line crosses the whole chart (e.g. 1 in a furnace plot).
    pub horizontal_rules: Vec<f64>,
    /// The picture's size in pixels (width, height).
    pub size: (u32, u32),
}

impl Chart for LineChart {
    fn size(&self) -> (u32, u32) {
        self.size
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let mut chart = ChartBuilder::on(area)
            .caption(&self.title, text(20.0))
            .margin(16)
            .x_label_area_size(48)
            .y_label_area_size(72)
            .build_cartesian_2d(self.x_range.0..self.x_range.1, self.y_range.0..self.y_range.1)?;
        chart
            .configure_mesh()
            .x_label_formatter(&|x| short_number(*x))
            .y_label_formatter(&|y| short_number(*y))
            .x_desc(&self.x_label)
            .y_desc(&self.y_label)
            .label_style(text(14.0))
            .axis_desc_style(text(16.0))
            .light_line_style(RGBColor(235, 235, 235))
            .bold_line_style(RGBColor(210, 210, 210))
            .draw()?;
        for &y in &self.horizontal_rules {
            chart.draw_series(std::iter::once(PathElement::new(
                vec![(self.x_range.0, y), (self.x_range.1, y)],
                BLACK.stroke_width(1),
            )))?;
        }
        for series in &self.series {
            draw_series(&mut chart, series)?;
        }
        draw_legend(&mut chart, SeriesLabelPosition::UpperRight)
    }
}

/// Draws one series as a line (dashed if asked) with its legend entry.
pub fn draw_series<'a, DB: DrawingBackend + 'a>(chart: &mut ChartContext<'a, DB, Plane>, series: &Series) -> Drawn<DB> {
    let style = series.colour.stroke_width(2);
    let colour = series.colour;
    let drawn = if series.dashed {
        chart.draw_series(DashedLineSeries::new(series.points.iter().copied(), 8, 5, style))?
    } else {
        chart.draw_series(LineSeries::new(series.points.iter().copied(), style))?
    };
    drawn
        .label(&series.label)
        .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 24, y)], colour.stroke_width(2)));
    Ok(())
}

/// The legend of the series drawn so far.
pub fn draw_legend<'a, DB: DrawingBackend + 'a>(
    chart: &mut ChartContext<'a, DB, Plane>,
    position: SeriesLabelPosition,
) -> Drawn<DB> {
    chart
        .configure_series_labels()
        .position(position)
        .label_font(text(14.0))
        .background_style(WHITE.mix(0.85))
        .border_style(RGBColor(160, 160, 160))
        .draw()
}

/// A range from 0 (or the data's least value, if negative) to a little above the data's greatest, for an
/// axis: never empty.
pub fn value_range<'a>(values: impl IntoIterator<Item = &'a f64>) -> (f64, f64) {
    let (low, high) = values.into_iter().fold((0.0f64, 0.0f64), |(lo, hi), &v| (lo.min(v), hi.max(v)));
    let high = if high > low { high } else { low + 1.0 };
    (low, high + 0.08 * (high - low))
}

/// A lobe plot: above, the lobes in polar form in the plane of the cut (wi drawn, on the left); below, the
/// same curves against theta_o.
#[derive(Clone, Debug)]
pub struct LobeChart {
    /// Above the polar half.
    pub title: String,
    /// What the curves are, for the radial and y axes, e.g. "f_r cos θo (luminance)".
    pub quantity: String,
    /// One per curve: points (theta_o in degrees, value).
    pub series: Vec<Series>,
    /// The incidence angles drawn as arrows (degrees), with their colours.
    pub incident: Vec<(f64, RGBColor)>,
}

const LOBE_WIDTH: u32 = 1100;
const POLAR_HEIGHT: u32 = 560;
const CARTESIAN_HEIGHT: u32 = 420;

impl Chart for LobeChart {
    fn size(&self) -> (u32, u32) {
        (LOBE_WIDTH, POLAR_HEIGHT + CARTESIAN_HEIGHT)
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let (polar, cartesian) = area.split_vertically(POLAR_HEIGHT);
        let highest = value_range(self.series.iter().flat_map(|s| s.points.iter().map(|p| &p.1))).1;
        self.draw_polar(&polar.titled(&self.title, text(20.0))?, highest)?;
        let curves = LineChart {
            title: String::new(),
            x_label: "θo (degrees; negative on the side of wi)".into(),
            y_label: self.quantity.clone(),
            x_range: (-90.0, 90.0),
            y_range: (0.0, highest),
            series: self.series.clone(),
            horizontal_rules: Vec::new(),
            size: (LOBE_WIDTH, CARTESIAN_HEIGHT),
        };
        curves.draw(&cartesian)
    }
}

impl LobeChart {
    /// The polar half: rings of equal value, rays every 30 degrees, wi as arrows, the lobes as curves.
    fn draw_polar<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>, radius: f64) -> Drawn<DB> {
        let margin = 28;
        let (width, height) = area.dim_in_pixel();
        let (plot_w, plot_h) = (f64::from(width - 2 * margin), f64::from(height - 2 * margin));
        // Equal scales on both axes, so that rings are round: the wider of the two spans decides.
        let y_span = radius.max(2.0 * radius * plot_h / plot_w);
        let x_span = y_span * plot_w / plot_h / 2.0;
        let mut chart = ChartBuilder::on(area).margin(margin).build_cartesian_2d(-x_span..x_span, 0.0..y_span)?;
        let grey = RGBColor(200, 200, 200);
        let ring = nice_step(radius / 5.0);
        let mut r = ring;
        while r <= radius * 1.0001 {
            let arc: Vec<(f64, f64)> =
                (0..=180).map(|d| f64::from(d).to_radians()).map(|a| (r * a.cos(), r * a.sin())).collect();
            chart.draw_series(std::iter::once(PathElement::new(arc, grey.stroke_width(1))))?;
            chart.draw_series(std::iter::once(Text::new(format!("{}", round_label(r)), (r, 0.0), text(12.0))))?;
            r += ring;
        }
        for degrees in (-90..=90).step_by(30) {
            let a = f64::from(degrees).to_radians();
            let tip = (radius * a.sin(), radius * a.cos());
            chart.draw_series(std::iter::once(PathElement::new(vec![(0.0, 0.0), tip], grey.stroke_width(1))))?;
            let label = (1.04 * tip.0, 1.04 * tip.1);
            chart.draw_series(std::iter::once(Text::new(format!("{degrees}°"), label, text(12.0))))?;
        }
        for &(theta_i, colour) in &self.incident {
            let a = theta_i.to_radians();
            let tip = (-radius * a.sin(), radius * a.cos());
            chart.draw_series(DashedLineSeries::new([tip, (0.0, 0.0)], 6, 4, colour.stroke_width(1)))?;
            chart.draw_series(std::iter::once(Text::new(
                format!("wi {theta_i}°"),
                (1.02 * tip.0 - 0.08 * radius, 1.02 * tip.1),
                text(13.0).color(&colour),
            )))?;
        }
        for series in &self.series {
            let points = series.points.iter().map(|&(theta, v)| {
                let a = theta.to_radians();
                (v.max(0.0) * a.sin(), v.max(0.0) * a.cos())
            });
            if series.dashed {
                chart.draw_series(DashedLineSeries::new(points, 8, 5, series.colour.stroke_width(2)))?;
            } else {
                chart.draw_series(LineSeries::new(points, series.colour.stroke_width(2)))?;
            }
        }
        Ok(())
    }
}

/// 1, 2 or 5 times a power of ten, the nearest at or above `step`.
fn nice_step(step: f64) -> f64 {
    let power = 10f64.powf(step.log10().floor());
    [1.0, 2.0, 5.0, 10.0].iter().map(|m| m * power).find(|&s| s >= step).unwrap_or(10.0 * power)
}

/// A ring's value without float noise (0.30000000000000004 as 0.3).
fn round_label(value: f64) -> f64 {
    (value * 1e6).round() / 1e6
}

/// An axis label: no trailing zeros (30, not 30.0; 0.25, not 0.250).
pub fn short_number(value: f64) -> String {
    format!("{}", round_label(value))
}

/// A table as a picture: a title, a header row, rows of cells each row in its colour, and a note below.
#[derive(Clone, Debug)]
pub struct TableChart {
    /// Above the table.
    pub title: String,
    /// The columns' titles.
    pub header: Vec<String>,
    /// One row's cells and their text colour; a row with fewer cells than the header leaves the last columns empty.
    pub rows: Vec<(Vec<String>, RGBColor)>,
    /// One line below the table, grey.
    pub note: String,
}

const TABLE_ROW: u32 = 24;
const TABLE_FONT: f64 = 15.0;
/// The width of a character of the table's text, near enough to lay its columns out.
const TABLE_CHAR: u32 = 9;

impl TableChart {
    /// Each column's width in pixels: its widest cell.
    fn column_widths(&self) -> Vec<u32> {
        let mut widths: Vec<u32> = self.header.iter().map(|h| h.chars().count() as u32).collect();
        for (cells, _) in &self.rows {
            for (width, cell) in widths.iter_mut().zip(cells) {
                *width = (*width).max(cell.chars().count() as u32);
            }
        }
        widths.into_iter().map(|chars| chars * TABLE_CHAR + 24).collect()
    }
}

impl Chart for TableChart {
    fn size(&self) -> (u32, u32) {
        let width = self.column_widths().iter().sum::<u32>().max(self.note.chars().count() as u32 * 8) + 40;
        (width, TABLE_ROW * (self.rows.len() as u32 + 4) + 40)
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let widths = self.column_widths();
        let row_y = |row: u32| (40 + TABLE_ROW * row) as i32;
        area.draw(&Text::new(self.title.clone(), (20, 10), text(20.0)))?;
        let cells_at = |cells: &[String], row: u32, colour: RGBColor| -> Drawn<DB> {
            let mut x = 20;
            for (cell, width) in cells.iter().zip(&widths) {
                area.draw(&Text::new(cell.clone(), (x, row_y(row)), text(TABLE_FONT).color(&colour)))?;
                x += *width as i32;
            }
            Ok(())
        };
        cells_at(&self.header, 0, BLACK)?;
        let right = 20 + widths.iter().sum::<u32>() as i32;
        area.draw(&PathElement::new(vec![(20, row_y(1) - 4), (right, row_y(1) - 4)], BLACK.stroke_width(1)))?;
        for (k, (cells, colour)) in self.rows.iter().enumerate() {
            cells_at(cells, k as u32 + 1, *colour)?;
        }
        let note_row = self.rows.len() as u32 + 2;
        area.draw(&Text::new(self.note.clone(), (20, row_y(note_row)), text(13.0).color(&RGBColor(90, 90, 90))))?;
        Ok(())
    }
}

/// One false-colour panel: `cells` x `cells` values over [0, 90] x [0, 90] degrees, rows from the bottom;
/// `None` is drawn grey (no value there).
#[derive(Clone, Debug)]
pub struct HeatMap {
    /// The panel's caption.
    pub label: String,
    /// The side of its grid: `cells` x `cells` values.
    pub cells: usize,
    /// `cells * cells` values, row by row: value `row * cells + column`, row 0 at the bottom.
    pub values: Vec<Option<f64>>,
}

/// Heat maps side by side on one colour scale (viridis), with its colour bar: BRDF Explorer's image slice.
#[derive(Clone, Debug)]
pub struct HeatMapChart {
    /// Above the panels.
    pub title: String,
    /// The x axis's title under each panel.
    pub x_label: String,
    /// The y axis's title beside each panel.
    pub y_label: String,
    /// What the colours are, for the colour bar.
    pub quantity: String,
    /// The panels, left to right.
    pub panels: Vec<HeatMap>,
    /// The values at the colour scale's ends, (low, high); values beyond take the end's colour.
    pub range: (f64, f64),
}

const PANEL: u32 = 460;
const COLOUR_BAR: u32 = 150;
const NO_VALUE: RGBColor = RGBColor(150, 150, 150);

impl HeatMapChart {
    fn colour(&self, value: f64) -> RGBColor {
        let (low, high) = self.range;
        let [r, g, b] = check_rules::viridis((value - low) / (high - low));
        RGBColor(r, g, b)
    }
}

impl Chart for HeatMapChart {
    fn size(&self) -> (u32, u32) {
        (PANEL * self.panels.len() as u32 + COLOUR_BAR, PANEL + 60)
    }

    fn draw<DB: DrawingBackend>(&self, area: &DrawingArea<DB, Shift>) -> Drawn<DB> {
        area.fill(&WHITE)?;
        let area = area.titled(&self.title, text(20.0))?;
        let (panels, bar) = area.split_horizontally(PANEL * self.panels.len() as u32);
        for (panel, map) in panels.split_evenly((1, self.panels.len())).iter().zip(&self.panels) {
            let mut chart = ChartBuilder::on(panel)
                .caption(&map.label, text(15.0))
                .margin(12)
                .x_label_area_size(44)
                .y_label_area_size(56)
                .build_cartesian_2d(0.0..90.0, 0.0..90.0)?;
            chart
                .configure_mesh()
                .disable_mesh()
                .x_labels(7)
                .y_labels(7)
                .x_label_formatter(&|x| short_number(*x))
                .y_label_formatter(&|y| short_number(*y))
                .x_desc(&self.x_label)
                .y_desc(&self.y_label)
                .label_style(text(13.0))
                .axis_desc_style(text(14.0))
                .draw()?;
            let step = 90.0 / map.cells as f64;
            chart.draw_series(map.values.iter().enumerate().map(|(k, value)| {
                let (row, column) = ((k / map.cells) as f64, (k % map.cells) as f64);
                let colour = value.map_or(NO_VALUE, |v| self.colour(v));
                Rectangle::new(
                    [(column * step, row * step), ((column + 1.0) * step, (row + 1.0) * step)],
                    colour.filled(),
                )
            }))?;
        }
        let (low, high) = self.range;
        let mut chart = ChartBuilder::on(&bar)
            .margin_top(40)
            .margin_bottom(56)
            .margin_right(8)
            .y_label_area_size(86)
            .build_cartesian_2d(0.0..1.0, low..high)?;
        chart
            .configure_mesh()
            .disable_mesh()
            .disable_x_axis()
            .y_label_formatter(&|y| short_number(*y))
            .y_desc(&self.quantity)
            .label_style(text(13.0))
            .axis_desc_style(text(14.0))
            .draw()?;
        let steps = 256;
        let band = (high - low) / f64::from(steps);
        chart.draw_series((0..steps).map(|k| {
            let from = low + f64::from(k) * band;
            Rectangle::new([(0.0, from), (1.0, from + band)], self.colour(from + band / 2.0).filled())
        }))?;
        Ok(())
    }
}
