//! Contact sheets of rendered tiles, shared by `sweep`, `sheet` and `figures`.

use std::path::{Path, PathBuf};
use std::sync::mpsc::Receiver;

use super::{progress, render_png_pixels};
use vk_render::pictures::output::{write_png, write_png_rows};
use vk_render::pictures::sheet::SheetLayout;
use vk_render::{Renderer, Scene};

/// One tile of a contact sheet: its scene, label and file, and whether that file is read rather than
/// rendered (a whole tile a `sweep --resume` found on disk, every tile of `vk-render sheet`).
pub struct Tile {
    pub scene: Scene,
    pub label: String,
    pub path: PathBuf,
    pub on_disk: bool,
}

impl Tile {
    /// The tile's size, as its scene fixes it.
    pub fn size(&self) -> (u32, u32) {
        (self.scene.image.width, self.scene.image.height)
    }

    /// Whether the tile's file is whole: a PNG of the tile's size that decodes (a `.partial-PID` file a
    /// killed process left is another name, and never counts).
    ///
    /// # Errors
    /// Why not, in a few words, for a message that names the path.
    pub fn check_on_disk(&self) -> Result<(), String> {
        read_tile(&self.path, self.size()).map(drop)
    }
}

/// How a sheet lays out its tiles.
pub enum Arrangement {
    /// Rows of at most `columns` tiles, each labelled under it; `fit_labels` shrinks (then clips) a label to
    /// its tile's width.
    Rows { columns: usize, fit_labels: bool },
    /// A grid: one row per label of `rows`, one column per label of `columns` (the tiles come row by row),
    /// the tiles unlabelled.
    Grid { rows: Vec<String>, columns: Vec<String> },
}

/// A contact sheet to make: its title, tiles, arrangement and file; with no file, only the tiles are
/// written (one shard of a sweep).
pub struct Sheet<'a> {
    pub title: &'a str,
    pub tiles: &'a [Tile],
    pub arrangement: Arrangement,
    pub path: Option<&'a Path>,
}

impl Sheet<'_> {
    /// The layout of the sheet, its tiles as large as the largest.
    fn layout(&self) -> SheetLayout {
        let tile_size = self.tiles.iter().fold((0, 0), |(w, h), t| (w.max(t.size().0), h.max(t.size().1)));
        match &self.arrangement {
            Arrangement::Rows { columns, fit_labels } => {
                let layout = SheetLayout::new(Some(self.title), self.tiles.len(), tile_size, *columns);
                if *fit_labels {
                    layout.with_fitted_labels()
                } else {
                    layout
                }
            }
            Arrangement::Grid { rows, columns } => {
                SheetLayout::grid(Some(self.title), rows.clone(), columns.clone(), tile_size)
            }
        }
    }
}

/// Renders every tile of every sheet that is not on disk, in order, and writes each as soon as it is done,
/// with its contact sheet made band by band beside them from the rendered and read tiles alike: one row of
/// tiles at a time in memory, however long the sweep. The files are written on a thread of their own, one
/// image behind the renders: on lavapipe the renderer's thread mostly waits for the rasterizer's threads,
/// and the next sheet's first tile renders while the last one's file is finished. With no renderer (every
/// tile on disk: `vk-render sheet`), nothing is rendered. If anything fails, the files of the sheet it
/// failed in that this call wrote are removed and the message says so (tiles that were on disk are kept);
/// the sheets before it are whole.
pub fn render_sheets(renderer: Option<&mut Renderer>, sheets: &[Sheet]) -> anyhow::Result<()> {
    let (rendered, written) = std::thread::scope(|scope| {
        // One tile waits in the channel at most.
        let (send, receive) = std::sync::mpsc::sync_channel::<image::RgbImage>(1);
        let writer = scope.spawn(move || write_sheets(sheets, &receive));
        let rendered = match renderer {
            Some(renderer) => render_tiles(renderer, sheets, &send),
            None => Ok(()),
        };
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

/// Renders the tiles not on disk and sends their images to the writer, until it stops taking them (on its
/// own error).
fn render_tiles(
    renderer: &mut Renderer,
    sheets: &[Sheet],
    send: &std::sync::mpsc::SyncSender<image::RgbImage>,
) -> vk_render::Result<()> {
    for sheet in sheets {
        let bar = progress(sheet.tiles.iter().filter(|tile| !tile.on_disk).count(), sheet.title);
        for tile in sheet.tiles.iter().filter(|tile| !tile.on_disk) {
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

/// Writes each sheet's tiles as their images arrive (reading those on disk instead), and the sheet a row
/// of tiles at a time, printing its path once whole; on a failure, removes the files of the sheet being
/// made that it wrote.
fn write_sheets(sheets: &[Sheet], images: &Receiver<image::RgbImage>) -> Result<(), WriteFailure> {
    for sheet in sheets {
        let mut written: Vec<&Path> = Vec::new();
        let mut stopped = false;
        let mut next = |tile| -> vk_render::Result<Option<image::RgbImage>> {
            let image = next_image(tile, images, &mut written)?;
            stopped |= image.is_none();
            Ok(image)
        };
        let result = match sheet.path {
            None => sheet.tiles.iter().filter(|tile| !tile.on_disk).try_for_each(|tile| match next(tile)? {
                Some(_) => Ok(()),
                None => Err(vk_render::Error::Output {
                    path: tile.path.clone(),
                    message: "the tiles stopped before this one was rendered".into(),
                }),
            }),
            Some(path) => {
                let layout = sheet.layout();
                write_png_rows(path, layout.size(), |band| {
                    band(&layout.title_band())?;
                    let mut row = Vec::with_capacity(layout.columns);
                    for (index, tile) in sheet.tiles.iter().enumerate() {
                        let Some(image) = next(tile)? else {
                            return Err(vk_render::Error::Output {
                                path: path.to_path_buf(),
                                message: "the tiles stopped before the sheet was whole".into(),
                            });
                        };
                        row.push((tile.label.clone(), image));
                        if row.len() == layout.columns || index + 1 == sheet.tiles.len() {
                            band(&layout.row_band(index / layout.columns, &row))?;
                            row.clear();
                        }
                    }
                    Ok(())
                })
            }
        };
        if let Err(e) = result {
            for path in &written {
                let _ = std::fs::remove_file(path);
            }
            return Err(WriteFailure { error: (!stopped).then_some(e), removed: written.len() });
        }
        if let Some(path) = sheet.path {
            println!("{}", path.display());
        }
    }
    Ok(())
}

/// The next tile's image: read from its file when it is on disk, else received from the renders and
/// written (its path added to `written`); `None` when the renders stopped.
fn next_image<'t>(
    tile: &'t Tile,
    images: &Receiver<image::RgbImage>,
    written: &mut Vec<&'t Path>,
) -> vk_render::Result<Option<image::RgbImage>> {
    if tile.on_disk {
        let path = &tile.path;
        let read = read_tile(path, tile.size());
        return read.map(Some).map_err(|message| vk_render::Error::Input { path: path.clone(), message });
    }
    let Ok(image) = images.recv() else { return Ok(None) };
    write_png(&image, &tile.path)?;
    written.push(&tile.path);
    Ok(Some(image))
}

/// The tile at `path`: a PNG of `width` x `height` that decodes whole, as 8-bit RGB.
///
/// # Errors
/// Why not, in a few words: missing, unreadable, not a PNG, cut short, another size.
fn read_tile(path: &Path, (width, height): (u32, u32)) -> Result<image::RgbImage, String> {
    let file = match std::fs::File::open(path) {
        Ok(file) => file,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Err("no such file".to_string()),
        Err(e) => return Err(format!("cannot read the tile: {e}")),
    };
    let reader = image::ImageReader::with_format(std::io::BufReader::new(file), image::ImageFormat::Png);
    let decoded = reader.decode().map_err(|e| format!("not a whole PNG image: {e}"))?;
    let (w, h) = (decoded.width(), decoded.height());
    if (w, h) != (width, height) {
        return Err(format!("a {w} x {h} image, not the tile's {width} x {height}"));
    }
    Ok(decoded.into_rgb8())
}
