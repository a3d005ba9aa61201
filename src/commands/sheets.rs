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

/// A contact sheet to make: its title, tiles, columns and file.
pub struct Sheet<'a> {
    pub title: &'a str,
    pub tiles: &'a [Tile],
    pub columns: usize,
    pub path: &'a Path,
}

/// Renders every tile of every sheet, in order, and writes each as soon as it is done, with its labelled
/// contact sheet made band by band beside them: one row of tiles at a time in memory, however long the
/// sweep. The files are written on a thread of their own, one image behind the renders: on lavapipe the
/// renderer's thread mostly waits for the rasterizer's threads, and the next sheet's first tile renders
/// while the last one's file is finished. If anything fails, the files of the sheet it failed in are
/// removed and the message says so; the sheets before it are whole.
pub fn render_sheets(renderer: &mut Renderer, sheets: &[Sheet]) -> anyhow::Result<()> {
    let (rendered, written) = std::thread::scope(|scope| {
        // One tile waits in the channel at most.
        let (send, receive) = std::sync::mpsc::sync_channel::<image::RgbImage>(1);
        let writer = scope.spawn(move || write_sheets(sheets, &receive));
        let rendered = render_tiles(renderer, sheets, &send);
        drop(send);
        (rendered, writer.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic)))
    });
    // A render's error comes first: the writer then only saw the tiles stop.
    let failure = match (rendered, written) {
        (Ok(()), Ok(())) => return Ok(()),
        (Err(e), written) => (anyhow::Error::from(e), written.err().map_or(0, |f| f.removed)),
        (Ok(()), Err(f)) => {
            (f.error.map_or_else(|| anyhow::anyhow!("the tiles stopped"), anyhow::Error::from), f.removed)
        }
    };
    match failure {
        (e, 0) => Err(e),
        (e, removed) => {
            anyhow::bail!("{e} (nothing is left of this sheet: the {removed} file(s) written before it were removed)")
        }
    }
}

/// Renders the tiles and sends their images to the writer, until it stops taking them (on its own error).
fn render_tiles(
    renderer: &mut Renderer,
    sheets: &[Sheet],
    send: &std::sync::mpsc::SyncSender<image::RgbImage>,
) -> vk_render::Result<()> {
    for sheet in sheets {
        let bar = progress(sheet.tiles.len(), sheet.title);
        for tile in sheet.tiles {
            let image = render_png_pixels(renderer, &tile.scene)?;
            bar.inc(1);
            if send.send(image).is_err() {
                return Ok(());
            }
        }
    }
    Ok(())
}

/// Why the writer stopped: its own error (`None` when the tiles stopped coming), and how many files of the
/// sheet it was making it removed.
struct WriteFailure {
    error: Option<vk_render::Error>,
    removed: usize,
}

/// Writes each sheet's tiles as their images arrive, and the sheet a row of tiles at a time, printing its
/// path once whole; on a failure, removes the files of the sheet being made.
fn write_sheets(sheets: &[Sheet], images: &Receiver<image::RgbImage>) -> Result<(), WriteFailure> {
    for sheet in sheets {
        let tile_size =
            sheet.tiles.iter().fold((0, 0), |(w, h), t| (w.max(t.scene.image.width), h.max(t.scene.image.height)));
        let layout = SheetLayout::new(Some(sheet.title), sheet.tiles.len(), tile_size, sheet.columns);
        let mut written: Vec<&Path> = Vec::new();
        let mut stopped = false;
        let result = write_png_rows(sheet.path, layout.size(), |band| {
            band(&layout.title_band())?;
            let mut row = Vec::with_capacity(layout.columns);
            for (index, tile) in sheet.tiles.iter().enumerate() {
                let Ok(image) = images.recv() else {
                    stopped = true;
                    return Err(vk_render::Error::Output {
                        path: sheet.path.to_path_buf(),
                        message: "the tiles stopped before the sheet was whole".into(),
                    });
                };
                write_png(&image, &tile.path)?;
                written.push(&tile.path);
                row.push((tile.label.clone(), image));
                if row.len() == layout.columns || index + 1 == sheet.tiles.len() {
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
            return Err(WriteFailure { error: (!stopped).then_some(e), removed: written.len() });
        }
        println!("{}", sheet.path.display());
    }
    Ok(())
}
