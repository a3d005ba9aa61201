//! `vk-render sweep`: one image per value of a scene key, and their labelled contact sheet.

use std::path::PathBuf;

use clap::Args;

use super::sheets::{render_sheets, Sheet, Tile};
use super::{warn, ImageArgs};
use vk_render::output::OutputFormat;
use vk_render::{Renderer, RendererOptions, Scene};

#[derive(Args)]
pub struct SweepArgs {
    /// The scene file (TOML, SCENE_FORMAT version 1).
    scene: PathBuf,

    /// The dotted key to vary, e.g. material.grey.sigma.
    #[arg(long, value_name = "KEY")]
    param: String,

    /// The values, separated by commas, e.g. 0,0.2,0.4,0.6.
    #[arg(long, value_name = "V1,V2,...", value_delimiter = ',', required = true)]
    values: Vec<String>,

    /// The contact sheet (.png); each tile is written beside it as SHEET-VALUE.png.
    #[arg(short, long, value_name = "SHEET")]
    output: PathBuf,

    /// Tiles per row of the sheet (1 to 64).
    #[arg(long, default_value_t = 4, value_parser = clap::value_parser!(u32).range(1..=64))]
    columns: u32,

    #[command(flatten)]
    image: ImageArgs,
}

/// Checks every value, then renders and writes the tiles and the sheet.
pub fn run(args: SweepArgs, options: RendererOptions) -> anyhow::Result<()> {
    if OutputFormat::for_path(&args.output)? != OutputFormat::Png {
        anyhow::bail!("{}: a contact sheet is a .png image", args.output.display());
    }
    let stem = args.output.file_stem().unwrap_or_default().to_string_lossy().into_owned();
    let short_key = args.param.rsplit('.').next().unwrap_or(&args.param).to_string();
    // Every scene is loaded and checked before anything is rendered or written.
    if let Some(empty) = args.values.iter().position(|value| value.trim().is_empty()) {
        anyhow::bail!(
            "--values {:?}: value {} of {} is empty (give the values separated by commas: 0,0.2,0.4)",
            args.values.join(","),
            empty + 1,
            args.values.len()
        );
    }
    let mut tiles = Vec::new();
    for value in &args.values {
        let value = value.trim();
        let mut overrides = args.image.overrides();
        overrides.push(format!("{}={value}", args.param).parse().map_err(anyhow::Error::msg)?);
        let scene = Scene::load(&args.scene, &overrides)?;
        let path = args.output.with_file_name(format!("{stem}-{}.png", file_safe(value)));
        tiles.push(Tile { scene, label: format!("{short_key} = {value}"), path });
    }
    if let Some(first) = tiles.first() {
        warn(&first.scene);
    }
    let mut renderer = Renderer::for_scenes(options, &tiles.iter().map(|tile| &tile.scene).collect::<Vec<_>>())?;
    let sheet = Sheet { title: &args.param, tiles: &tiles, columns: args.columns as usize, path: &args.output };
    render_sheets(&mut renderer, &[sheet])
}

/// A value as part of a file name: anything but letters, digits, '.', '-' and '_' becomes '_'.
fn file_safe(value: &str) -> String {
    value.chars().map(|c| if c.is_ascii_alphanumeric() || "._-".contains(c) { c } else { '_' }).collect()
}
