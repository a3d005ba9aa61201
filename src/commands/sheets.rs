//! Contact sheets of rendered tiles, shared by `sweep` and `figures`.

use std::path::PathBuf;

use super::{progress, render_png_pixels};
use vk_render::output::{write_png, write_png_rows};
use vk_render::sheet::SheetLayout;
use vk_render::{Renderer, Scene};

/// One tile of a contact sheet: its scene, label and file.
pub struct Tile {
    pub scene: Scene,
    pub label: String,
    pub path: PathBuf,
}

/// Renders every tile and writes it as soon as it is done, with the labelled contact sheet made band by band
/// beside them: one row of tiles at a time in memory, however long the sweep. If anything fails, the files
/// written are removed and the message says so.
pub fn render_sheet(
    renderer: &mut Renderer,
    title: &str,
    tiles: &[Tile],
    columns: usize,
    sheet_path: &std::path::Path,
) -> anyhow::Result<()> {
    let tile_size = tiles.iter().fold((0, 0), |(w, h), t| (w.max(t.scene.image.width), h.max(t.scene.image.height)));
    let layout = SheetLayout::new(Some(title), tiles.len(), tile_size, columns);
    let mut written: Vec<&std::path::Path> = Vec::new();
    let bar = progress(tiles.len(), title);
    let result = write_png_rows(sheet_path, layout.size(), |band| {
        band(&layout.title_band())?;
        let mut row = Vec::with_capacity(layout.columns);
        for (index, tile) in tiles.iter().enumerate() {
            let image = render_png_pixels(renderer, &tile.scene)?;
            bar.inc(1);
            write_png(&image, &tile.path)?;
            written.push(&tile.path);
            row.push((tile.label.clone(), image));
            if row.len() == layout.columns || index + 1 == tiles.len() {
                band(&layout.row_band(&row))?;
                row.clear();
            }
        }
        Ok(())
    });
    if let Err(e) = result {
        for path in &written {
            let _ = std::fs::remove_file(path);
        }
        if written.is_empty() {
            return Err(e.into());
        }
        anyhow::bail!(
            "{e} (nothing is left of this sheet: the {} file(s) written before it were removed)",
            written.len()
        );
    }
    bar.finish_and_clear();
    println!("{}", sheet_path.display());
    Ok(())
}
