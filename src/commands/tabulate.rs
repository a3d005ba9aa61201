//! `vk-render tabulate`: a material written as a MERL file, as if measured (its Rust mirror evaluated at the
//! centre of every entry), to load as `brdf = "measured"` or into any tool that reads MERL files.

use std::path::PathBuf;

use clap::Args;

use super::SetArgs;
use vk_render::analysis::{describe, select_materials};
use vk_render::brdf::measured::FILE_BYTES;
use vk_render::brdf::MeasuredTable;
use vk_render::Scene;

#[derive(Args)]
pub struct TabulateArgs {
    /// The scene file that defines the material.
    scene: PathBuf,

    /// The material to tabulate, by its [material.NAME].
    #[arg(long, value_name = "NAME")]
    material: String,

    /// The MERL file to write (90 x 90 x 180 entries, 34,992,012 bytes).
    #[arg(short, long, value_name = "OUT.binary")]
    output: PathBuf,

    #[command(flatten)]
    set: SetArgs,
}

/// Tabulates the material and writes the file.
pub fn run(args: TabulateArgs) -> anyhow::Result<()> {
    let scene = Scene::load(&args.scene, &args.set.overrides)?;
    let target = select_materials(&scene, Some(std::slice::from_ref(&args.material)))?.remove(0);
    let table = MeasuredTable::tabulate(args.output.clone(), |wi, wo| target.brdf.eval(glam::Vec3::Z, wi, wo));
    vk_render::output::write_file(&args.output, &table.to_bytes())?;
    println!("{} ({}) tabulated: {} ({FILE_BYTES} bytes)", target.name, describe(&target.brdf), args.output.display());
    Ok(())
}
