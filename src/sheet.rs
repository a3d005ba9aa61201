//! Contact sheets: images side by side, each with its label drawn under it, and an optional title.

use image::{Rgb, RgbImage};

use crate::text::{draw_text, text_width};

/// The labels' and title's text size in pixels (DejaVu Sans, anti-aliased).
const TEXT: f32 = 18.0;
/// The height of a line of that text (ascent to descent).
const GLYPH: u32 = 22;
/// The strip under each tile (and above the sheet for a title).
const STRIP: u32 = GLYPH + 10;
const GAP: u32 = 8;
const PAPER: Rgb<u8> = Rgb([24, 24, 24]);
const INK: Rgb<u8> = Rgb([240, 240, 240]);

/// Lays `tiles` out in rows of at most `columns`, each tile labelled, under an optional title.
pub fn contact_sheet(title: Option<&str>, tiles: &[(String, RgbImage)], columns: usize) -> RgbImage {
    let tile_w = tiles.iter().map(|(_, t)| t.width()).max().unwrap_or(0);
    let tile_h = tiles.iter().map(|(_, t)| t.height()).max().unwrap_or(0);
    let layout = SheetLayout::new(title, tiles.len(), (tile_w, tile_h), columns);
    let (width, height) = layout.size();
    let mut bytes = layout.title_band().into_raw();
    for row in tiles.chunks(layout.columns) {
        bytes.extend(layout.row_band(row).into_raw());
    }
    RgbImage::from_raw(width, height, bytes).expect("the bands fill the sheet")
}

/// Where a contact sheet puts its title and tiles, so that it can be made band by band, top to bottom:
/// the title band, then one band per row of tiles (a sweep of hundreds of images holds one row at a time).
pub struct SheetLayout {
    title: Option<String>,
    pub columns: usize,
    rows: usize,
    tile_w: u32,
    tile_h: u32,
}

impl SheetLayout {
    /// A sheet of `count` tiles of at most `tile_w` x `tile_h` pixels, in rows of at most `columns`.
    pub fn new(title: Option<&str>, count: usize, (tile_w, tile_h): (u32, u32), columns: usize) -> Self {
        let columns = columns.clamp(1, count.max(1));
        Self { title: title.map(str::to_string), columns, rows: count.div_ceil(columns), tile_w, tile_h }
    }

    /// The sheet's width and height.
    pub fn size(&self) -> (u32, u32) {
        let width = GAP + self.columns as u32 * (self.tile_w + GAP);
        (width, self.title_height() + self.rows as u32 * self.row_height())
    }

    fn title_height(&self) -> u32 {
        if self.title.is_some() {
            STRIP + GAP
        } else {
            GAP
        }
    }

    fn row_height(&self) -> u32 {
        self.tile_h + STRIP + GAP
    }

    /// The band above the first row: the title, if any, and a gap.
    pub fn title_band(&self) -> RgbImage {
        let mut band = RgbImage::from_pixel(self.size().0, self.title_height(), PAPER);
        if let Some(title) = &self.title {
            draw_text(&mut band, (GAP, (STRIP - GLYPH) / 2 + GAP / 2), title, TEXT, INK);
        }
        band
    }

    /// The band of one row of tiles (at most `columns`), each labelled under it.
    pub fn row_band(&self, tiles: &[(String, RgbImage)]) -> RgbImage {
        let mut band = RgbImage::from_pixel(self.size().0, self.row_height(), PAPER);
        for (column, (label, tile)) in tiles.iter().take(self.columns).enumerate() {
            let x = GAP + column as u32 * (self.tile_w + GAP);
            image::imageops::replace(&mut band, tile, i64::from(x), 0);
            let text_x = x + self.tile_w.saturating_sub(text_width(label, TEXT)) / 2;
            draw_text(&mut band, (text_x, self.tile_h + (STRIP - GLYPH) / 2), label, TEXT, INK);
        }
        band
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_and_labels_are_placed() {
        let red = RgbImage::from_pixel(40, 30, Rgb([255, 0, 0]));
        let blue = RgbImage::from_pixel(40, 30, Rgb([0, 0, 255]));
        let sheet = contact_sheet(Some("T"), &[("a".into(), red), ("b".into(), blue)], 4);
        assert_eq!(sheet.dimensions(), (GAP + 2 * (40 + GAP), STRIP + GAP + 30 + STRIP + GAP));
        assert_eq!(sheet.get_pixel(GAP, STRIP + GAP).0, [255, 0, 0]);
        assert_eq!(sheet.get_pixel(2 * GAP + 40, STRIP + GAP).0, [0, 0, 255]);
        // The labels and the title put ink in their strips (anti-aliased: some pixels wholly inked).
        let ink_in = |x0: u32, y0: u32, w: u32, h: u32| {
            (y0..y0 + h).any(|y| (x0..x0 + w).any(|x| sheet.get_pixel(x, y).0 == INK.0))
        };
        assert!(ink_in(GAP, STRIP + GAP + 30, 40, STRIP));
        assert!(ink_in(2 * GAP + 40, STRIP + GAP + 30, 40, STRIP));
        assert!(ink_in(0, 0, sheet.width(), STRIP));
    }

    #[test]
    fn different_labels_draw_differently() {
        let mut a = RgbImage::from_pixel(64, GLYPH, PAPER);
        let mut b = a.clone();
        draw_text(&mut a, (0, 0), "0.2", TEXT, INK);
        draw_text(&mut b, (0, 0), "0.4", TEXT, INK);
        assert_ne!(a, b);
        // Anti-aliased: edges hold levels between paper and ink.
        assert!(a.pixels().any(|p| p.0[0] > PAPER.0[0] + 20 && p.0[0] < INK.0[0] - 20));
        // Greek and degree signs are in the font: no '?' box.
        assert!(text_width("θi = 30°", TEXT) > text_width("ab", TEXT));
    }
}
