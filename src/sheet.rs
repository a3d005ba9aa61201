//! Contact sheets: images side by side, each with its label drawn under it, and an optional title.

use image::{Rgb, RgbImage};

/// Text height in pixels: the 8x8 font drawn at twice its size.
const TEXT_SCALE: u32 = 2;
const GLYPH: u32 = 8 * TEXT_SCALE;
/// The strip under each tile (and above the sheet for a title).
const STRIP: u32 = GLYPH + 12;
const GAP: u32 = 8;
const PAPER: Rgb<u8> = Rgb([24, 24, 24]);
const INK: Rgb<u8> = Rgb([240, 240, 240]);

/// Lays `tiles` out in rows of at most `columns`, each tile labelled, under an optional title.
pub fn contact_sheet(title: Option<&str>, tiles: &[(String, RgbImage)], columns: usize) -> RgbImage {
    let columns = columns.clamp(1, tiles.len().max(1));
    let rows = tiles.len().div_ceil(columns);
    let tile_w = tiles.iter().map(|(_, t)| t.width()).max().unwrap_or(0);
    let tile_h = tiles.iter().map(|(_, t)| t.height()).max().unwrap_or(0);
    let title_h = if title.is_some() { STRIP } else { 0 };
    let width = GAP + columns as u32 * (tile_w + GAP);
    let height = title_h + GAP + rows as u32 * (tile_h + STRIP + GAP);
    let mut sheet = RgbImage::from_pixel(width, height, PAPER);
    if let Some(title) = title {
        draw_text(&mut sheet, GAP, (STRIP - GLYPH) / 2 + GAP / 2, title);
    }
    for (index, (label, tile)) in tiles.iter().enumerate() {
        let x = GAP + (index % columns) as u32 * (tile_w + GAP);
        let y = title_h + GAP + (index / columns) as u32 * (tile_h + STRIP + GAP);
        image::imageops::replace(&mut sheet, tile, i64::from(x), i64::from(y));
        let text_w = text_width(label);
        let text_x = x + tile_w.saturating_sub(text_w) / 2;
        draw_text(&mut sheet, text_x, y + tile_h + (STRIP - GLYPH) / 2, label);
    }
    sheet
}

/// The width of `text` in pixels.
pub fn text_width(text: &str) -> u32 {
    text.chars().count() as u32 * GLYPH
}

/// Draws ASCII `text` (others become '?') with its top-left corner at (x, y), clipped to the image.
pub fn draw_text(image: &mut RgbImage, x: u32, y: u32, text: &str) {
    for (i, c) in text.chars().enumerate() {
        let code = if c.is_ascii() { c as usize } else { '?' as usize };
        let glyph = font8x8::legacy::BASIC_LEGACY[code];
        let left = x + i as u32 * GLYPH;
        for (row, bits) in glyph.iter().enumerate() {
            for column in 0..8u32 {
                // font8x8 keeps the leftmost pixel in the lowest bit.
                if bits & (1 << column) == 0 {
                    continue;
                }
                for dy in 0..TEXT_SCALE {
                    for dx in 0..TEXT_SCALE {
                        let (px, py) = (left + column * TEXT_SCALE + dx, y + row as u32 * TEXT_SCALE + dy);
                        if px < image.width() && py < image.height() {
                            image.put_pixel(px, py, INK);
                        }
                    }
                }
            }
        }
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
        // The labels and the title put ink in their strips.
        let ink_in = |x0: u32, y0: u32, w: u32, h: u32| {
            (y0..y0 + h).any(|y| (x0..x0 + w).any(|x| sheet.get_pixel(x, y).0 == INK.0))
        };
        assert!(ink_in(GAP, STRIP + GAP + 30, 40, STRIP));
        assert!(ink_in(2 * GAP + 40, STRIP + GAP + 30, 40, STRIP));
        assert!(ink_in(0, 0, sheet.width(), STRIP));
    }

    #[test]
    fn different_labels_draw_differently() {
        let mut a = RgbImage::from_pixel(64, 16, PAPER);
        let mut b = a.clone();
        draw_text(&mut a, 0, 0, "0.2");
        draw_text(&mut b, 0, 0, "0.4");
        assert_ne!(a, b);
    }
}
