//! `vk-render export`: a material written for another renderer (glTF 2.0, MaterialX Standard Surface or
//! OpenPBR, Mitsuba 3, pbrt-v4), by the mapping of docs/export.md; `vk-render fit --export` writes a fit so.

use std::path::{Path, PathBuf};

use clap::builder::PossibleValuesParser;
use clap::Args;

use super::SetArgs;
use vk_render::analysis::{describe, select_materials, NamedBrdf};
use vk_render::export::{export, Format};
use vk_render::pictures::output::write_file;
use vk_render::Scene;

/// The command line's names of the formats.
pub fn format_names() -> PossibleValuesParser {
    PossibleValuesParser::new(Format::ALL.map(Format::name))
}

#[derive(Args)]
pub struct ExportArgs {
    /// The scene or analysis file that defines the material.
    file: PathBuf,

    /// The material to export, by its [material.NAME]: lambert, oren-nayar or cook-torrance (fit the other
    /// models to cook-torrance and export the fit: vk-render fit --export).
    #[arg(long, value_name = "NAME")]
    material: String,

    /// The format to write.
    #[arg(long, value_parser = format_names())]
    format: String,

    /// The file to write (.gltf, .mtlx, .xml, .pbrt).
    #[arg(short, long, value_name = "OUT")]
    output: PathBuf,

    #[command(flatten)]
    set: SetArgs,
}

/// Exports the material and says what the format could not hold as ours.
pub fn run(args: ExportArgs) -> anyhow::Result<()> {
    let scene = Scene::load(&args.file, &args.set.overrides)?;
    let material = select_materials(&scene, Some(std::slice::from_ref(&args.material)))?.remove(0);
    write_export(&material, &args.format, &args.output)
}

/// Writes `material` in the format named `format` to `output`, then prints where and the notes; an error names
/// the material.
pub fn write_export(material: &NamedBrdf, format: &str, output: &Path) -> anyhow::Result<()> {
    let format = Format::named(format).ok_or_else(|| anyhow::anyhow!("--format {format}: not a format"))?;
    let exported = export(&material.name, &material.brdf, format)
        .map_err(|e| anyhow::anyhow!("--material {}: {e}", material.name))?;
    write_file(output, exported.text.as_bytes())?;
    println!("{} ({}) written as {}: {}", material.name, describe(&material.brdf), format.title(), output.display());
    for note in &exported.notes {
        println!("  note: {note}");
    }
    Ok(())
}
