//! `vk-render render`: one scene to a PNG or an EXR.

use std::path::PathBuf;

use clap::Args;

use super::{print_accuracy, render_png_pixels, warn, ImageArgs};
use vk_render::pictures::output::{write_image, write_png, OutputFormat};
use vk_render::vulkan::ShaderSources;
use vk_render::{Renderer, RendererOptions, Scene};

#[derive(Args)]
pub struct RenderArgs {
    /// The scene file (TOML, SCENE_FORMAT version 1).
    scene: PathBuf,

    /// The output image: .png or .exr.
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,

    /// Compile the shaders of this folder (a modified copy of shaders/) instead of the built-in ones.
    #[arg(long, value_name = "DIR")]
    shaders: Option<PathBuf>,

    #[command(flatten)]
    image: ImageArgs,
}

/// Renders the scene and writes the image.
pub fn run(args: RenderArgs, mut options: RendererOptions) -> anyhow::Result<()> {
    let overrides = args.image.overrides();
    // Everything that can be checked without a device is checked before one is opened.
    let scene = Scene::load(&args.scene, &overrides)?;
    OutputFormat::for_path(&args.output)?;
    warn(&scene);
    if let Some(folder) = &args.shaders {
        options.shaders = ShaderSources::from_directory(folder)
            .map_err(|e| anyhow::anyhow!("--shaders {}: cannot read the shaders: {e}", folder.display()))?;
    }
    let mut renderer = super::CommandRenderer::new(Renderer::for_scenes(options, &[&scene])?);
    match OutputFormat::for_path(&args.output)? {
        OutputFormat::Png => write_png(&render_png_pixels(&mut renderer, &scene)?, &args.output)?,
        OutputFormat::Exr => {
            write_image(&renderer.render(&scene)?, &scene.image, &args.output)?;
            print_accuracy(&renderer);
        }
    }
    log::info!("wrote {}", args.output.display());
    Ok(())
}
