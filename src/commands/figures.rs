//! `vk-render figures`: every figure of the practical and one contact sheet per figure.

use std::path::PathBuf;

use clap::Args;

use super::sheets::{render_sheet, Tile};
use super::ImageArgs;
use vk_render::figures::FIGURES;
use vk_render::{Renderer, RendererOptions};

#[derive(Args)]
pub struct FiguresArgs {
    /// The folder to write into (created if needed).
    #[arg(short, long, value_name = "DIR")]
    output: PathBuf,

    #[command(flatten)]
    image: ImageArgs,
}

/// Renders every figure into the folder.
pub fn run(args: FiguresArgs, options: RendererOptions) -> anyhow::Result<()> {
    std::fs::create_dir_all(&args.output)
        .map_err(|e| anyhow::anyhow!("{}: cannot create the folder: {e}", args.output.display()))?;
    let overrides = args.image.overrides();
    let mut sheets = Vec::new();
    for figure in FIGURES {
        let mut tiles = Vec::new();
        for image in figure.images {
            let scene = image.scene(&overrides)?;
            tiles.push(Tile { scene, label: image.label.to_string(), path: args.output.join(image.png_name()) });
        }
        sheets.push((figure, tiles));
    }
    // One device, one set of compiled shaders and pipelines for every image, the pipelines built first.
    let mut renderer = Renderer::new(options)?;
    renderer.prepare(&sheets.iter().flat_map(|(_, tiles)| tiles.iter().map(|tile| &tile.scene)).collect::<Vec<_>>())?;
    for (figure, tiles) in &sheets {
        let sheet = args.output.join(format!("{}.png", figure.name));
        render_sheet(&mut renderer, figure.title, tiles, 4, &sheet)?;
    }
    Ok(())
}
