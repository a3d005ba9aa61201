//! Contact sheets: images side by side, each with its label drawn under it, and an optional title; or a grid
//! of them, a label for each row at its left and for each column above it (a sweep over two parameters).

use image::{Rgb, RgbImage};

use crate::pictures::text::{draw_text, text_width};

/// The labels' and title's text size in pixels (DejaVu Sans, anti-aliased).
const TEXT: f32 = 18.0;
/// The height of a line of that text (ascent to descent).
const GLYPH: u32 = 22;
/// The strip under each tile (and above the sheet for a title).
const STRIP: u32 = GLYPH + 10;
const GAP: u32 = 8;
const PAPER: Rgb<u8> = Rgb([24, 24, 24]);
const INK: Rgb<u8> = Rgb([240, 240, 240]);

/// The smallest size a label is shrunk to before it is clipped instead.
const SMALLEST_TEXT: f32 = 9.0;
/// The widest the row labels' column of a grid gets: longer labels are shrunk or clipped to it.
const WIDEST_ROW_LABEL: u32 = 320;

/// Lays `tiles` out in rows of at most `columns`, each tile labelled, under an optional title.
pub fn contact_sheet(title: Option<&str>, tiles: &[(String, RgbImage)], columns: usize) -> RgbImage {
    let tile_w = tiles.iter().map(|(_, t)| t.width()).max().unwrap_or(0);
    let tile_h = tiles.iter().map(|(_, t)| t.height()).max().unwrap_or(0);
    assemble(&SheetLayout::new(title, tiles.len(), (tile_w, tile_h), columns), tiles)
}

/// The whole sheet of `layout` in memory, its tiles in order (for tests and small sheets: a sweep writes
/// its sheet band by band instead).
pub fn assemble(layout: &SheetLayout, tiles: &[(String, RgbImage)]) -> RgbImage {
    let (width, height) = layout.size();
    let mut bytes = layout.title_band().into_raw();
    for (row, tiles) in tiles.chunks(layout.columns).enumerate() {
        bytes.extend(layout.row_band(row, tiles).into_raw());
    }
    RgbImage::from_raw(width, height, bytes).expect("the bands fill the sheet")
}

/// How a sheet labels its tiles.
#[derive(Clone, Debug, PartialEq)]
enum Labels {
    /// Each tile's label centred under it as it is (the sheets of `figures` and of one-parameter sweeps).
    Under,
    /// Each tile's label under it, shrunk to the tile's width, and clipped to it at the smallest size (the
    /// long labels of sweeps over three or more parameters).
    UnderFitted,
    /// A grid: each row's label left of it, each column's above the first row, the tiles unlabelled (a
    /// sweep over two parameters). `margin` is the width of the row labels' column.
    Grid { rows: Vec<String>, columns: Vec<String>, margin: u32 },
}

/// Where a contact sheet puts its title and tiles, so that it can be made band by band, top to bottom:
/// the title band, then one band per row of tiles (a sweep of hundreds of images holds one row at a time).
pub struct SheetLayout {
    title: Option<String>,
    /// Tiles a row: at least 1, and no more than there are tiles.
    pub columns: usize,
    rows: usize,
    tile_w: u32,
    tile_h: u32,
    labels: Labels,
}

impl SheetLayout {
    /// A sheet of `count` tiles of at most `tile_w` x `tile_h` pixels, in rows of at most `columns`, each
    /// labelled under it.
    pub fn new(title: Option<&str>, count: usize, (tile_w, tile_h): (u32, u32), columns: usize) -> Self {
        let columns = columns.clamp(1, count.max(1));
        Self {
            title: title.map(str::to_string),
            columns,
            rows: count.div_ceil(columns),
            tile_w,
            tile_h,
            labels: Labels::Under,
        }
    }

    /// The same sheet with each label shrunk (then clipped) to its tile's width, so that a long label never
    /// runs into the next tile's.
    pub fn with_fitted_labels(mut self) -> Self {
        if self.labels == Labels::Under {
            self.labels = Labels::UnderFitted;
        }
        self
    }

    /// A grid of tiles of at most `tile_w` x `tile_h`: a row per label of `rows` (drawn at its left), a
    /// column per label of `columns` (drawn above the first row), the tiles themselves unlabelled; the
    /// tiles come row by row.
    pub fn grid(title: Option<&str>, rows: Vec<String>, columns: Vec<String>, (tile_w, tile_h): (u32, u32)) -> Self {
        let widest = rows.iter().map(|label| text_width(label, TEXT)).max().unwrap_or(0);
        let margin = widest.min(WIDEST_ROW_LABEL.max(tile_w));
        Self {
            title: title.map(str::to_string),
            columns: columns.len().max(1),
            rows: rows.len(),
            tile_w,
            tile_h,
            labels: Labels::Grid { rows, columns, margin },
        }
    }

    /// The sheet's width and height.
    pub fn size(&self) -> (u32, u32) {
        let width = self.left() + self.columns as u32 * (self.tile_w + GAP);
        (width, self.title_height() + self.rows as u32 * self.row_height())
    }

    /// Where the first column of tiles starts.
    fn left(&self) -> u32 {
        match &self.labels {
            Labels::Grid { margin, .. } => GAP + margin + GAP,
            _ => GAP,
        }
    }

    fn title_height(&self) -> u32 {
        let title = if self.title.is_some() { STRIP + GAP } else { GAP };
        match self.labels {
            Labels::Grid { .. } => title + STRIP,
            _ => title,
        }
    }

    fn row_height(&self) -> u32 {
        match self.labels {
            Labels::Grid { .. } => self.tile_h + GAP,
            _ => self.tile_h + STRIP + GAP,
        }
    }

    /// The band above the first row: the title, if any, and a gap (and a grid's column labels).
    pub fn title_band(&self) -> RgbImage {
        let mut band = RgbImage::from_pixel(self.size().0, self.title_height(), PAPER);
        let y = (STRIP - GLYPH) / 2 + GAP / 2;
        match &self.title {
            Some(title) if self.labels == Labels::Under => draw_text(&mut band, (GAP, y), title, TEXT, INK),
            // The keys of a sweep over several parameters can be longer than the sheet is wide.
            Some(title) => draw_fitted(&mut band, (GAP, y), self.size().0.saturating_sub(2 * GAP), title, false),
            None => {}
        }
        if let Labels::Grid { columns, .. } = &self.labels {
            let y = self.title_height() - STRIP + (STRIP - GLYPH) / 2;
            for (column, label) in columns.iter().enumerate() {
                let x = self.left() + column as u32 * (self.tile_w + GAP);
                draw_fitted(&mut band, (x, y), self.tile_w, label, true);
            }
        }
        band
    }

    /// The band of row `row` (from 0) of tiles (at most `columns`): each labelled under it, or in a grid
    /// unlabelled after the row's label.
    pub fn row_band(&self, row: usize, tiles: &[(String, RgbImage)]) -> RgbImage {
        let mut band = RgbImage::from_pixel(self.size().0, self.row_height(), PAPER);
        let left = self.left();
        for (column, (label, tile)) in tiles.iter().take(self.columns).enumerate() {
            let x = left + column as u32 * (self.tile_w + GAP);
            paste(&mut band, tile, (x, 0));
            let y = self.tile_h + (STRIP - GLYPH) / 2;
            match &self.labels {
                Labels::Under => {
                    let text_x = x + self.tile_w.saturating_sub(text_width(label, TEXT)) / 2;
                    draw_text(&mut band, (text_x, y), label, TEXT, INK);
                }
                Labels::UnderFitted => draw_fitted(&mut band, (x, y), self.tile_w, label, true),
                Labels::Grid { .. } => {}
            }
        }
        if let Labels::Grid { rows, margin, .. } = &self.labels {
            if let Some(label) = rows.get(row) {
                draw_fitted(&mut band, (GAP, self.tile_h.saturating_sub(GLYPH) / 2), *margin, label, false);
            }
        }
        band
    }
}

/// Draws `label` within `width` pixels from (x, y) (centred when `centre`): at the labels' size when it
/// fits, else shrunk to fit, and below the smallest size clipped to the width. The area is paper, and the
/// label is drawn on a strip of its own so that nothing of it lands outside the width.
fn draw_fitted(band: &mut RgbImage, (x, y): (u32, u32), width: u32, label: &str, centre: bool) {
    if width == 0 || y >= band.height() || label.is_empty() {
        return;
    }
    let natural = text_width(label, TEXT);
    let size = if natural <= width { TEXT } else { (TEXT * width as f32 / natural as f32).max(SMALLEST_TEXT) };
    let drawn = text_width(label, size);
    let height = GLYPH.min(band.height() - y);
    let mut strip = RgbImage::from_pixel(width, height, PAPER);
    let offset_x = if centre { width.saturating_sub(drawn) / 2 } else { 0 };
    // A shrunk label sits on the same middle line as one at full size.
    let offset_y = ((GLYPH as f32 - GLYPH as f32 * size / TEXT) / 2.0).round() as u32;
    draw_text(&mut strip, (offset_x, offset_y), label, size, INK);
    paste(band, &strip, (x, y));
}

/// Copies `image` into `onto` with its top left corner at (x, y), row by row, clipped to `onto`
/// (`image::imageops::replace` goes pixel by pixel: 0.7 ms a 600 x 400 tile, a twentieth of a sweep's image).
pub fn paste(onto: &mut RgbImage, image: &RgbImage, (x, y): (u32, u32)) {
    let width = image.width().min(onto.width().saturating_sub(x)) as usize * 3;
    let rows = image.height().min(onto.height().saturating_sub(y)) as usize;
    let (stride, onto_stride) = (image.width() as usize * 3, onto.width() as usize * 3);
    let start = y as usize * onto_stride + x as usize * 3;
    for row in 0..rows {
        let to = start + row * onto_stride;
        onto.as_mut()[to..to + width].copy_from_slice(&image.as_raw()[row * stride..row * stride + width]);
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
    fn a_grid_labels_its_rows_and_columns_not_its_tiles() {
        let tile = |v: u8| RgbImage::from_pixel(40, 30, Rgb([v, 0, 0]));
        let rows = vec!["kd = 0.1".to_string(), "kd = 0.9".to_string()];
        let columns = vec!["s = 1".to_string(), "s = 2".to_string(), "s = 3".to_string()];
        let layout = SheetLayout::grid(Some("a x b"), rows.clone(), columns, (40, 30));
        let tiles: Vec<(String, RgbImage)> = (0..6).map(|i| (String::new(), tile(100 + i))).collect();
        let sheet = assemble(&layout, &tiles);
        let margin = text_width(&rows[0], TEXT).max(text_width(&rows[1], TEXT));
        let (left, top) = (GAP + margin + GAP, STRIP + GAP + STRIP);
        assert_eq!(sheet.dimensions(), (left + 3 * (40 + GAP), top + 2 * (30 + GAP)));
        // Row by row: the fifth tile is the second row's second.
        assert_eq!(sheet.get_pixel(left + 40 + GAP, top + 30 + GAP).0, [104, 0, 0]);
        let ink_in = |x0: u32, y0: u32, w: u32, h: u32| {
            (y0..y0 + h).any(|y| (x0..x0 + w).any(|x| sheet.get_pixel(x, y).0 == INK.0))
        };
        assert!(ink_in(GAP, top, margin, 30), "no row label");
        assert!(ink_in(left, STRIP + GAP, 40, STRIP), "no column label");
        assert!(!ink_in(left, top + 30, sheet.width() - left, GAP), "a tile is labelled under it");
    }

    #[test]
    fn fitted_labels_stay_within_their_tile() {
        let tiles: Vec<(String, RgbImage)> = ["kd = 0.3, sigma = 0.2, roughness = 0.55", "b"]
            .iter()
            .map(|label| (label.to_string(), RgbImage::from_pixel(40, 30, Rgb([0, 0, 0]))))
            .collect();
        let fitted = assemble(&SheetLayout::new(None, 2, (40, 30), 4).with_fitted_labels(), &tiles);
        let plain = assemble(&SheetLayout::new(None, 2, (40, 30), 4), &tiles);
        let strip_y = GAP + 30;
        let inked = |sheet: &RgbImage, x: u32| (strip_y..strip_y + STRIP).any(|y| sheet.get_pixel(x, y).0 != PAPER.0);
        // The gap between the two tiles' strips: the long label runs into it unfitted, not fitted.
        assert!((GAP + 40..2 * GAP + 40).any(|x| inked(&plain, x)));
        assert!(!(GAP + 40..2 * GAP + 40).any(|x| inked(&fitted, x)));
        assert!((GAP..GAP + 40).any(|x| inked(&fitted, x)), "the long label is not drawn at all");
        // A label that fits is drawn the same either way.
        let short = [("b".to_string(), RgbImage::from_pixel(40, 30, Rgb([0, 0, 0])))];
        let layout = || SheetLayout::new(None, 1, (40, 30), 4);
        assert_eq!(assemble(&layout().with_fitted_labels(), &short), assemble(&layout(), &short));
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
