//! `vk-render compare`: two scenes rendered, side by side with the map of their differences, and the
//! differences' statistics printed.

use std::path::PathBuf;

use clap::Args;

use super::{render_png_pixels, warn, ImageArgs};
use vk_render::pictures::output::{write_png, OutputFormat};
use vk_render::pictures::report::{side_by_side, Difference};
use vk_render::{Override, Renderer, RendererOptions, Scene};

#[derive(Args)]
pub struct CompareArgs {
    /// The first scene file.
    a: PathBuf,

    /// The second scene file.
    b: PathBuf,

    /// The report (.png): A, B and the map of their differences with its colour bar.
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,

    /// Overrides applied to both scenes.
    #[command(flatten)]
    image: ImageArgs,

    /// Override one value of B alone (after those of both), e.g. --set-b environment.mode=fast to compare a
    /// scene's exact and fast environment light.
    #[arg(long = "set-b", value_name = "KEY=VALUE")]
    set_b: Vec<Override>,
}

/// Renders both scenes, prints their differences and writes the report.
pub fn run(args: CompareArgs, options: RendererOptions) -> anyhow::Result<()> {
    let overrides = args.image.overrides();
    let overrides_b: Vec<Override> = overrides.iter().chain(&args.set_b).cloned().collect();
    let (a, b) = (Scene::load(&args.a, &overrides)?, Scene::load(&args.b, &overrides_b)?);
    if OutputFormat::for_path(&args.output)? != OutputFormat::Png {
        anyhow::bail!("{}: a comparison report is a .png image", args.output.display());
    }
    let size = |scene: &Scene| (scene.image.width, scene.image.height);
    if size(&a) != size(&b) {
        anyhow::bail!(
            "{} is {} x {} and {} is {} x {}: give them one size (--width and --height apply to both)",
            args.a.display(),
            a.image.width,
            a.image.height,
            args.b.display(),
            b.image.width,
            b.image.height
        );
    }
    warn(&a);
    warn(&b);
    let mut renderer = super::CommandRenderer::new(Renderer::for_scenes(options, &[&a, &b])?);
    let (image_a, image_b) = (render_png_pixels(&mut renderer, &a)?, render_png_pixels(&mut renderer, &b)?);
    let difference = Difference::of(&image_a, &image_b);
    let stats = &difference.stats;
    let differing = difference.map.levels.iter().filter(|&&level| level > 0).count();
    println!(
        "mean {:.3} levels, p99 {}, max {} (8-bit levels of the PNGs, largest channel); {:.2}% of the pixels differ, \
         {:.2}% by more than 3 levels",
        stats.mean_abs,
        stats.p99,
        stats.max,
        100.0 * differing as f64 / difference.map.levels.len() as f64,
        100.0 * stats.fraction_over_3
    );
    let name = |path: &PathBuf| {
        path.file_name().map_or_else(|| path.display().to_string(), |n| n.to_string_lossy().into_owned())
    };
    let panels = [
        (format!("A: {}", name(&args.a)), image_a),
        (
            format!(
                "B: {}{}",
                name(&args.b),
                args.set_b.iter().map(|o| format!(", {}={}", o.path, o.value)).collect::<String>()
            ),
            image_b,
        ),
        (format!("|A - B|, 0 to {} levels", difference.map.scale()), difference.map.heat_map()),
    ];
    let title = format!("mean {:.3}, p99 {}, max {} levels", stats.mean_abs, stats.p99, stats.max);
    write_png(&side_by_side(&title, &panels, Some(difference.map.scale())), &args.output)?;
    Ok(())
}
