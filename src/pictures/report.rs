//! Comparison reports: images side by side, each labelled, with a false-colour map of their differences and
//! its colour bar (`vk-render compare`). Drawn straight into an 8-bit image so that the images keep their
//! exact pixels.

use check_rules::{viridis, DifferenceMap};
use image::{Rgb, RgbImage};

use crate::pictures::compare::{compare, Comparison};
use crate::pictures::sheet::paste;
use crate::pictures::text::{draw_text, text_width};

const GAP: u32 = 12;
const LABEL: f32 = 17.0;
const STRIP: u32 = 30;
const PAPER: Rgb<u8> = Rgb([255, 255, 255]);
const INK: Rgb<u8> = Rgb([20, 20, 20]);
const BAR_WIDTH: u32 = 24;
const BAR_LABELS: u32 = 64;

/// Two images' differences: the statistics in 8-bit levels, and per pixel the largest channel difference.
pub struct Difference {
    /// The differences' statistics, in 8-bit levels.
    pub stats: Comparison,
    /// Per pixel the largest channel difference, its heat map and where it is worst (as the browser's check
    /// page draws it too).
    pub map: DifferenceMap,
}

impl Difference {
    /// The differences of two images of one size.
    pub fn of(a: &RgbImage, b: &RgbImage) -> Self {
        Self { stats: compare(a, b, &vec![false; (a.width() * a.height()) as usize]), map: DifferenceMap::of(a, b) }
    }
}

/// The images side by side under a title, each labelled under it, then the colour bar of a difference map
/// (from 0 to `scale` levels) when there is one among them.
pub fn side_by_side(title: &str, panels: &[(String, RgbImage)], scale: Option<u8>) -> RgbImage {
    let panel_w = panels.iter().map(|(_, p)| p.width()).max().unwrap_or(0);
    let panel_h = panels.iter().map(|(_, p)| p.height()).max().unwrap_or(0);
    let bar = if scale.is_some() { GAP + BAR_WIDTH + BAR_LABELS } else { 0 };
    let width = GAP + panels.len() as u32 * (panel_w + GAP) + bar;
    let top = STRIP + GAP;
    let mut sheet = RgbImage::from_pixel(width, top + panel_h + STRIP, PAPER);
    draw_text(&mut sheet, (GAP, GAP / 2), title, LABEL + 2.0, INK);
    for (k, (label, panel)) in panels.iter().enumerate() {
        let x = GAP + k as u32 * (panel_w + GAP);
        paste(&mut sheet, panel, (x, top));
        let text_x = x + panel_w.saturating_sub(text_width(label, LABEL)) / 2;
        draw_text(&mut sheet, (text_x, top + panel_h + 6), label, LABEL, INK);
    }
    if let Some(scale) = scale {
        let x = width - BAR_WIDTH - BAR_LABELS;
        for y in 0..panel_h {
            let colour = Rgb(viridis(1.0 - f64::from(y) / f64::from(panel_h.max(2) - 1)));
            for dx in 0..BAR_WIDTH {
                sheet.put_pixel(x + dx, top + y, colour);
            }
        }
        for (fraction, value) in [(0.0, scale), (0.5, scale / 2), (1.0, 0)] {
            let y = top + ((panel_h.saturating_sub(14)) as f32 * fraction) as u32;
            draw_text(&mut sheet, (x + BAR_WIDTH + 6, y), &value.to_string(), LABEL - 3.0, INK);
        }
        draw_text(&mut sheet, (x - 4, top + panel_h + 6), "levels", LABEL - 3.0, INK);
    }
    sheet
}
