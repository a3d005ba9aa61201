//! `vk-render figures`: every figure of the practical and one contact sheet per figure.

use std::path::PathBuf;

use clap::Args;

use super::sheets::{render_sheets, Arrangement, Sheet, Tile};
use super::ImageArgs;
use vk_render::scene::figures::FIGURES;
use vk_render::{Renderer, RendererOptions, Scene};

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
    let mut figures = Vec::new();
    for figure in FIGURES {
        let mut tiles = Vec::new();
        for image in figure.images {
            let scene = image.scene(&overrides)?;
            let (label, path) = (image.label.to_string(), args.output.join(image.png_name()));
            tiles.push(Tile { scene, label, path, on_disk: false });
        }
        figures.push((figure, tiles, args.output.join(format!("{}.png", figure.name))));
    }
    // One device, one set of compiled shaders and pipelines for every image, the pipelines built first.
    let scenes: Vec<&Scene> = figures.iter().flat_map(|(_, tiles, _)| tiles.iter().map(|tile| &tile.scene)).collect();
    let mut renderer = super::CommandRenderer::new(Renderer::for_scenes(options, &scenes)?);
    let sheets: Vec<Sheet> = figures
        .iter()
        .map(|(figure, tiles, path)| Sheet {
            title: figure.title,
            tiles,
            arrangement: Arrangement::Rows { columns: 4, fit_labels: false },
            path: Some(path),
        })
        .collect();
    render_sheets(Some(&mut renderer), &sheets)
}
