//! `vk-render tabulate`: a material written as a MERL file, as if measured (its Rust mirror evaluated at the
//! centre of every entry; a .brdf file's own GLSL, on the GPU), to load as `brdf = "measured"` or into any
//! tool that reads MERL files; or, a built-in model or a `.brdf` file with a Rust mirror, as an RGL `.bsdf`
//! file (`--output NAME.bsdf`: the paper's parameterisation, src/brdf/rgl/tabulate.rs).

use std::path::PathBuf;

use clap::Args;

use super::SetArgs;
use vk_render::analysis::{describe, select_materials, tabulated};
use vk_render::brdf::measured::FILE_BYTES;
use vk_render::brdf::{rgl, Brdf, MeasuredTable};
use vk_render::{Renderer, RendererOptions, Scene};

#[derive(Args)]
pub struct TabulateArgs {
    /// The scene file that defines the material.
    scene: PathBuf,

    /// The material to tabulate, by its [material.NAME].
    #[arg(long, value_name = "NAME")]
    material: String,

    /// The file to write: a MERL file (90 x 90 x 180 entries, 34,992,012 bytes), or with the extension
    /// .bsdf an RGL file (a built-in model, about 0.6 MB; or a .brdf file with a Rust mirror, its incident
    /// azimuths over the whole turn, about 10 MB).
    #[arg(short, long, value_name = "OUT.binary|OUT.bsdf")]
    output: PathBuf,

    #[command(flatten)]
    set: SetArgs,
}

/// Tabulates the material and writes the file: a built-in model by its Rust mirror, with no device; a .brdf
/// file by the probe pass (its GLSL as the renders run it).
pub fn run(args: TabulateArgs, options: RendererOptions) -> anyhow::Result<()> {
    let scene = Scene::load(&args.scene, &args.set.overrides)?;
    let target = select_materials(&scene, Some(std::slice::from_ref(&args.material)))?.remove(0);
    if args.output.extension().is_some_and(|e| e == "bsdf") {
        let description = format!("vk-render tabulate: {} ({})", target.name, describe(&target.brdf));
        let fields = rgl::tabulate::tabulate_model(&target.brdf, &description)
            .map_err(|e| anyhow::anyhow!("--material {}: {e}", args.material))?;
        let bytes = rgl::tensor::write(&fields);
        vk_render::pictures::output::write_file(&args.output, &bytes)?;
        println!(
            "{} ({}) tabulated: {} (an RGL file, {} bytes)",
            target.name,
            describe(&target.brdf),
            args.output.display(),
            bytes.len()
        );
        return Ok(());
    }
    let table = match &target.brdf {
        Brdf::Analytic(_) => {
            let mut renderer = super::CommandRenderer::new(Renderer::new(options)?);
            tabulated(&mut renderer, &target.brdf, args.output.clone())?
        }
        brdf => MeasuredTable::tabulate(args.output.clone(), |wi, wo| brdf.eval(glam::Vec3::Z, wi, wo)),
    };
    vk_render::pictures::output::write_file(&args.output, &table.to_bytes())?;
    println!("{} ({}) tabulated: {} ({FILE_BYTES} bytes)", target.name, describe(&target.brdf), args.output.display());
    Ok(())
}
