//! `vk-render sweep`: one image per combination of the values of one or more scene keys, and their
//! labelled contact sheet; split into shares (`--shard K/N`) for several processes or machines, and resumed
//! (`--resume`) after a stop. `vk-render sheet`: the same sheet made from the tiles on disk, rendering
//! nothing (once every share is done).

use std::path::PathBuf;

use clap::Args;

use super::sheets::{render_sheets, Arrangement, Sheet, Tile};
use super::{warn, ImageArgs};
use vk_render::pictures::output::OutputFormat;
use vk_render::scene::grid::{Grid, GridParam, GridValue, Shard};
use vk_render::{Renderer, RendererOptions, Scene};

/// What `sweep` and `sheet` share: the scene, the grid of values, the sheet and the image options, which
/// fix every tile's scene, label, file and size.
#[derive(Args)]
pub struct GridArgs {
    /// The scene file (TOML, SCENE_FORMAT version 1).
    scene: PathBuf,

    /// A dotted key to vary, e.g. material.grey.sigma, each followed by its --values. Given several times,
    /// every combination of the values is rendered: two keys make a grid (a row per value of the first, a
    /// column per value of the second), three or more a labelled tile per combination.
    #[arg(long, value_name = "KEY", required = true)]
    param: Vec<String>,

    /// The values of the --param before it, separated by commas, e.g. 0,0.2,0.4,0.6.
    #[arg(long, value_name = "V1,V2,...", required = true, allow_hyphen_values = true)]
    values: Vec<String>,

    /// The contact sheet (.png); each tile is written beside it as SHEET-VALUE.png (one --param) or
    /// SHEET-KEY=VALUE-KEY=VALUE.png (several, each key by its last segment).
    #[arg(short, long, value_name = "SHEET")]
    output: PathBuf,

    /// Tiles per row of the sheet (1 to 64; default 4). Not with two --param: their sheet is a grid, a
    /// column per value of the second key.
    #[arg(long, value_parser = clap::value_parser!(u32).range(1..=64))]
    columns: Option<u32>,

    #[command(flatten)]
    image: ImageArgs,
}

#[derive(Args)]
pub struct SweepArgs {
    #[command(flatten)]
    grid: GridArgs,

    /// Render only the K-th of N shares of the combinations (combination i, from 0, is in share i % N + 1).
    /// With N above 1 no sheet is written: once every share is done, `vk-render sheet` with the same
    /// arguments (less --shard and --resume) makes it from the tiles.
    #[arg(long, value_name = "K/N")]
    shard: Option<Shard>,

    /// Keep every tile already whole on disk (a PNG of the tile's size) instead of rendering it again: to
    /// finish a sweep that was stopped. The sheet is made from the kept and rendered tiles alike.
    #[arg(long)]
    resume: bool,
}

/// A sweep's tiles, checked: every combination's scene, label and file, in the grid's order, and how its
/// sheet lays them out.
struct Plan {
    tiles: Vec<Tile>,
    title: String,
    arrangement: Arrangement,
}

impl GridArgs {
    /// The grid of the --param/--values pairs, each value checked as `--set` takes it.
    fn grid(&self) -> anyhow::Result<Grid> {
        if self.param.len() != self.values.len() {
            anyhow::bail!(
                "--param is given {} time(s) and --values {}: give one --values V1,V2,... after each --param KEY",
                self.param.len(),
                self.values.len()
            );
        }
        let mut params = Vec::with_capacity(self.param.len());
        for (key, list) in self.param.iter().zip(&self.values) {
            let key = key.trim();
            let texts: Vec<&str> = list.split(',').collect();
            let mut values = Vec::with_capacity(texts.len());
            for (index, text) in texts.iter().enumerate() {
                let which = format!("--param {key} --values {:?}: value {} of {}", list, index + 1, texts.len());
                if text.trim().is_empty() {
                    anyhow::bail!("{which} is empty (give the values separated by commas: 0,0.2,0.4)");
                }
                values.push(GridValue::parse(text).map_err(|e| anyhow::anyhow!("{which}: {e}"))?);
            }
            params.push(GridParam { key: key.to_string(), values });
        }
        Grid::new(params).map_err(anyhow::Error::msg)
    }

    /// Every tile of the sweep, its scene loaded and checked (before anything is rendered or written), and
    /// the sheet's title and arrangement.
    fn plan(&self) -> anyhow::Result<Plan> {
        if OutputFormat::for_path(&self.output)? != OutputFormat::Png {
            anyhow::bail!("{}: a contact sheet is a .png image", self.output.display());
        }
        let grid = self.grid()?;
        let keys: Vec<&str> = grid.params().iter().map(|param| param.key.as_str()).collect();
        let labels = |param: usize| -> Vec<String> {
            let name = grid.short_name(param);
            grid.params()[param].values.iter().map(|value| format!("{name} = {}", value.text)).collect()
        };
        let arrangement = match (keys.len(), self.columns) {
            (2, Some(columns)) => anyhow::bail!(
                "--columns {columns}: a sweep of two --param is a grid (a row per value of {}, a column per value \
                 of {}): leave --columns out",
                keys[0],
                keys[1]
            ),
            (2, None) => Arrangement::Grid { rows: labels(0), columns: labels(1) },
            (count, columns) => Arrangement::Rows { columns: columns.unwrap_or(4) as usize, fit_labels: count > 2 },
        };
        let mut tiles = Vec::with_capacity(grid.len());
        for combination in grid.combinations() {
            let mut overrides = self.image.overrides();
            overrides.extend(combination.overrides());
            let scene = Scene::load(&self.scene, &overrides)?;
            let (label, path) = (combination.label(&grid), combination.tile_path(&grid, &self.output));
            tiles.push(Tile { scene, label, path, on_disk: false });
        }
        Ok(Plan { tiles, title: keys.join(" x "), arrangement })
    }
}

/// Checks every combination, then renders and writes the tiles of the shard (all by default) that are not
/// kept, and the sheet when the sweep is whole.
pub fn run(args: SweepArgs, options: RendererOptions) -> anyhow::Result<()> {
    let shard = args.shard.unwrap_or(Shard { k: 1, n: 1 });
    let plan = args.grid.plan()?;
    if let Some(first) = plan.tiles.first() {
        warn(&first.scene);
    }
    let total = plan.tiles.len();
    let mut tiles: Vec<Tile> =
        plan.tiles.into_iter().enumerate().filter(|(index, _)| shard.contains(*index)).map(|(_, tile)| tile).collect();
    if args.resume {
        for tile in &mut tiles {
            tile.on_disk = tile.check_on_disk().is_ok();
        }
        let kept = tiles.iter().filter(|tile| tile.on_disk).count();
        println!("--resume: skipped {kept} of {} tile(s), already whole on disk", tiles.len());
    }
    let scenes: Vec<&Scene> = tiles.iter().filter(|tile| !tile.on_disk).map(|tile| &tile.scene).collect();
    // No device is opened when every tile is kept.
    let mut renderer = if scenes.is_empty() {
        None
    } else {
        Some(super::CommandRenderer::new(Renderer::for_scenes(options, &scenes)?))
    };
    let path = (shard.n == 1).then_some(args.grid.output.as_path());
    let sheet = Sheet { title: &plan.title, tiles: &tiles, arrangement: plan.arrangement, path };
    render_sheets(renderer.as_deref_mut(), &[sheet])?;
    if shard.n > 1 {
        let rendered = tiles.iter().filter(|tile| !tile.on_disk).count();
        println!(
            "shard {}/{}: {rendered} tile(s) written ({} in this shard, {total} in the sweep); once every shard is \
             done, make the sheet with: {}",
            shard.k,
            shard.n,
            tiles.len(),
            sheet_command()
        );
    }
    Ok(())
}

/// `vk-render sheet`: checks every combination as `sweep` does, then that every tile is on disk and whole,
/// and writes the sheet from them, the same bytes as one `sweep` writes; renders nothing, opens no device.
pub fn run_sheet(args: GridArgs) -> anyhow::Result<()> {
    let mut plan = args.plan()?;
    let problems: Vec<(PathBuf, String)> =
        plan.tiles.iter().filter_map(|tile| tile.check_on_disk().err().map(|why| (tile.path.clone(), why))).collect();
    if let Some((path, why)) = problems.first() {
        anyhow::bail!(
            "{} of {} tile(s) are missing or not whole, the first {} ({why}): render every shard of the sweep \
             first (no sheet was written)",
            problems.len(),
            plan.tiles.len(),
            path.display()
        );
    }
    for tile in &mut plan.tiles {
        tile.on_disk = true;
    }
    let sheet =
        Sheet { title: &plan.title, tiles: &plan.tiles, arrangement: plan.arrangement, path: Some(&args.output) };
    render_sheets(None, &[sheet])
}

/// This command line as `vk-render sheet` takes it: `sweep` made `sheet`, --shard and --resume left out,
/// each word quoted for a POSIX shell where it needs to be.
fn sheet_command() -> String {
    let mut words = Vec::new();
    let mut args = std::env::args_os().map(|arg| arg.to_string_lossy().into_owned());
    words.extend(args.next().map(|program| quoted(&program)));
    let mut in_sweep = false;
    while let Some(arg) = args.next() {
        match arg.as_str() {
            "sweep" if !in_sweep => {
                in_sweep = true;
                words.push("sheet".to_string());
            }
            "--shard" if in_sweep => {
                args.next();
            }
            "--resume" if in_sweep => {}
            _ if in_sweep && arg.starts_with("--shard=") => {}
            _ => words.push(quoted(&arg)),
        }
    }
    words.join(" ")
}

/// `word` as one word of a POSIX shell command: as it is when it holds only safe characters, else in single
/// quotes.
fn quoted(word: &str) -> String {
    let safe = |c: char| c.is_ascii_alphanumeric() || "-_./=,:@%+".contains(c);
    if !word.is_empty() && word.chars().all(safe) {
        word.to_string()
    } else {
        format!("'{}'", word.replace('\'', r"'\''"))
    }
}
