//! Contact sheets of rendered tiles, shared by `sweep` and `figures`.

use std::path::{Path, PathBuf};
use std::sync::mpsc::Receiver;

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
/// beside them: one row of tiles at a time in memory, however long the sweep. The files are written on a
/// thread of their own while the next tile renders (on lavapipe the renderer's own thread mostly waits for
/// the rasterizer's threads meanwhile). If anything fails, the files written are removed and the message
/// says so.
pub fn render_sheet(
    renderer: &mut Renderer,
    title: &str,
    tiles: &[Tile],
    columns: usize,
    sheet_path: &Path,
) -> anyhow::Result<()> {
    let tile_size = tiles.iter().fold((0, 0), |(w, h), t| (w.max(t.scene.image.width), h.max(t.scene.image.height)));
    let layout = SheetLayout::new(Some(title), tiles.len(), tile_size, columns);
    let bar = progress(tiles.len(), title);
    let (rendered, written, result) = std::thread::scope(|scope| {
        // One tile waits in the channel at most: the renderer runs one image ahead of the files.
        let (send, receive) = std::sync::mpsc::sync_channel::<image::RgbImage>(1);
        let writer = scope.spawn(move || write_sheet(&layout, tiles, sheet_path, receive));
        let mut rendered = Ok(());
        for tile in tiles {
            match render_png_pixels(renderer, &tile.scene) {
                // A send fails only when the writer has stopped on an error, which it returns.
                Ok(image) => {
                    bar.inc(1);
                    if send.send(image).is_err() {
                        break;
                    }
                }
                Err(e) => {
                    rendered = Err(e);
                    break;
                }
            }
        }
        drop(send);
        let (written, result) = writer.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        (rendered, written, result)
    });
    // A render's error comes first: the writer then only saw its tiles stop.
    if let Err(e) = rendered.map_err(anyhow::Error::from).and(result.map_err(anyhow::Error::from)) {
        for path in &written {
            let _ = std::fs::remove_file(path);
        }
        if written.is_empty() {
            return Err(e);
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

/// Writes each tile's PNG as its image arrives, and the sheet a row of tiles at a time; the files written,
/// and whether the sheet is whole (an error if the tiles stopped coming before the last).
fn write_sheet<'a>(
    layout: &SheetLayout,
    tiles: &'a [Tile],
    sheet_path: &Path,
    images: Receiver<image::RgbImage>,
) -> (Vec<&'a Path>, vk_render::Result<()>) {
    let mut written = Vec::new();
    let result = write_png_rows(sheet_path, layout.size(), |band| {
        band(&layout.title_band())?;
        let mut row = Vec::with_capacity(layout.columns);
        let mut images = images.iter();
        for (index, tile) in tiles.iter().enumerate() {
            let Some(image) = images.next() else {
                return Err(vk_render::Error::Output {
                    path: sheet_path.to_path_buf(),
                    message: "the tiles stopped before the sheet was whole".into(),
                });
            };
            write_png(&image, &tile.path)?;
            written.push(tile.path.as_path());
            row.push((tile.label.clone(), image));
            if row.len() == layout.columns || index + 1 == tiles.len() {
                band(&layout.row_band(&row))?;
                row.clear();
            }
        }
        Ok(())
    });
    (written, result)
}
