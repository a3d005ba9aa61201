//! `vk-render reference`: the scene ray-traced on the CPU, the independent reference of the tests.

use std::path::PathBuf;

use clap::Args;

use super::{names_the_same_file, ImageArgs};
use vk_render::pictures::output::{write_image, write_png, OutputFormat};
use vk_render::Scene;

#[derive(Args)]
pub struct ReferenceArgs {
    /// The scene file (TOML, SCENE_FORMAT version 1).
    scene: PathBuf,

    /// The output image: .png or .exr.
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,

    /// Also write the object-id map (.png): one colour per object, black where no object is seen.
    #[arg(long, value_name = "IDS")]
    ids: Option<PathBuf>,

    #[command(flatten)]
    image: ImageArgs,
}

/// Ray-traces the scene and writes its image (and its object-id map).
pub fn run(args: ReferenceArgs) -> anyhow::Result<()> {
    let scene = Scene::load(&args.scene, &args.image.overrides())?;
    OutputFormat::for_path(&args.output)?;
    if let Some(ids) = &args.ids {
        if OutputFormat::for_path(ids)? != OutputFormat::Png {
            anyhow::bail!("{}: the object-id map is a .png image", ids.display());
        }
        if names_the_same_file(ids, &args.output) {
            anyhow::bail!("--ids {}: the same file as -o: give the object-id map a file of its own", ids.display());
        }
    }
    if scene.image.view != vk_render::scene::View::Radiance {
        anyhow::bail!(
            "{}: image.view = \"{}\": the CPU reference renders the radiance only",
            args.scene.display(),
            scene.image.view.name()
        );
    }
    let traced = vk_render::reference::render(&scene)?;
    write_image(&traced.image, &scene.image, &args.output)?;
    if scene.environment.is_some() {
        println!(
            "environment (reference): {} samples a pixel: standard error at most {:.2} of an 8-bit level at 99% of \
             the pixels",
            vk_render::reference::DEFAULT_SAMPLES,
            traced.p99_error_levels(&scene.image)
        );
    }
    if let Some(ids) = &args.ids {
        write_png(&traced.object_id_picture(), ids)?;
    }
    Ok(())
}
