//! The commands of `vk-render`, one module each: its arguments and what it does. `main.rs` is the table of
//! them; what several share (the scene overrides, warnings, output paths) is here.

pub mod check;
pub mod compare;
pub mod devices;
pub mod export;
pub mod figures;
pub mod fit;
pub mod furnace;
pub mod plot;
#[cfg(feature = "preview")]
pub mod preview;
pub mod reference;
pub mod render;
pub mod sampling;
mod sheets;
pub mod sweep;
pub mod tabulate;

use std::path::{Path, PathBuf};

use clap::Args;

use vk_render::analysis::{select_materials, NamedBrdf};
use vk_render::pictures::chart::ChartFile;
use vk_render::pictures::output::write_file;
use vk_render::scene::{Shorthands, View};
use vk_render::{Override, Renderer, Scene};

/// Options that override `[image]` and any other value of the scene(s).
#[derive(Args)]
pub struct ImageArgs {
    /// Image width in pixels (same as --set image.width=W).
    #[arg(long)]
    width: Option<i64>,

    /// Image height in pixels (same as --set image.height=H).
    #[arg(long)]
    height: Option<i64>,

    /// MSAA samples per pixel (same as --set image.samples=N).
    #[arg(long)]
    samples: Option<i64>,

    /// What the image shows: the radiance, or one term of the shading (same as --set image.view=VIEW).
    #[arg(long, value_parser = clap::builder::PossibleValuesParser::new(View::ALL.map(View::name)))]
    view: Option<String>,

    /// How the scene's [environment] is integrated: exact (stills) or fast (prefiltered) (same as --set
    /// environment.mode=MODE).
    #[arg(long, value_parser = ["exact", "fast"])]
    environment_mode: Option<String>,

    #[command(flatten)]
    set: SetArgs,
}

/// `--set`: overrides of any value of the scene.
#[derive(Args)]
pub struct SetArgs {
    /// Override one scene value by its dotted path, e.g. material.grey.kd=0.8 or light.0.power=30.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub overrides: Vec<Override>,
}

impl ImageArgs {
    /// The shorthands as overrides, then the --set ones.
    pub fn overrides(&self) -> Vec<Override> {
        let shorthands = Shorthands {
            width: self.width,
            height: self.height,
            samples: self.samples,
            view: self.view.as_deref(),
            environment_mode: self.environment_mode.as_deref(),
        };
        let mut overrides = shorthands.overrides();
        overrides.extend(self.set.overrides.iter().cloned());
        overrides
    }
}

/// A command's renderer. When the command is done with it, one warning line says where an analytic model
/// gave NaN, an infinity or a negative value, if one did (images count such values as 0; the plots show
/// them as they are).
pub struct CommandRenderer(Renderer);

impl CommandRenderer {
    /// Wraps a renderer made for the command.
    pub fn new(renderer: Renderer) -> Self {
        Self(renderer)
    }
}

impl std::ops::Deref for CommandRenderer {
    type Target = Renderer;

    fn deref(&self) -> &Renderer {
        &self.0
    }
}

impl std::ops::DerefMut for CommandRenderer {
    fn deref_mut(&mut self) -> &mut Renderer {
        &mut self.0
    }
}

impl Drop for CommandRenderer {
    fn drop(&mut self) {
        if let Some(invalid) = self.0.take_invalid_values() {
            eprintln!("warning: {invalid}");
        }
    }
}

/// Prints the scene's warnings on standard error.
pub fn warn(scene: &Scene) {
    for warning in scene.warnings() {
        eprintln!("warning: {warning}");
    }
}

/// Whether two output paths name the same file: their folders (which exist) resolved, and the same name.
pub fn names_the_same_file(a: &Path, b: &Path) -> bool {
    let resolved = |path: &Path| {
        let folder = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
        folder.canonicalize().ok().map(|folder| folder.join(path.file_name().unwrap_or_default()))
    };
    resolved(a).is_some() && resolved(a) == resolved(b)
}

/// What every analysis command takes: a scene, which of its materials, `--set`, and the file to write.
#[derive(Args)]
pub struct StudyArgs {
    /// The scene file whose [material.NAME] tables are studied (objects and lights are not needed).
    pub scene: PathBuf,

    /// The materials to study, by name, separated by commas (default: every one the scene defines).
    #[arg(long, value_name = "NAME,...", value_delimiter = ',')]
    pub material: Option<Vec<String>>,

    /// The file to write: .png or .svg (the picture) or .csv (its numbers).
    #[arg(short, long, value_name = "OUT")]
    pub output: PathBuf,

    #[command(flatten)]
    pub set: SetArgs,
}

/// The kinds of file an analysis command writes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudyFile {
    Chart(ChartFile),
    Csv,
}

impl StudyArgs {
    /// The scene and the materials to study, checked before a device is opened.
    pub fn materials(&self) -> anyhow::Result<Vec<NamedBrdf>> {
        let scene = Scene::load(&self.scene, &self.set.overrides)?;
        Ok(select_materials(&scene, self.material.as_deref())?)
    }

    /// Writes the study: the CSV alone when `-o` names one; else the picture `draw` writes at `-o`, with its
    /// numbers beside it as the same name's `.csv` (for people who plot themselves). Both or neither: when
    /// the picture fails, the CSV written first is removed.
    pub fn write(&self, csv: &str, draw: impl FnOnce(&Path) -> vk_render::Result<()>) -> anyhow::Result<()> {
        if self.output_file()? == StudyFile::Csv {
            return Ok(write_file(&self.output, csv.as_bytes())?);
        }
        let beside = self.output.with_extension("csv");
        write_file(&beside, csv.as_bytes())?;
        if let Err(e) = draw(&self.output) {
            let _ = std::fs::remove_file(&beside);
            return Err(e.into());
        }
        Ok(())
    }

    /// What `-o` names: a picture or a table.
    pub fn output_file(&self) -> anyhow::Result<StudyFile> {
        let csv = self.output.extension().is_some_and(|e| e.eq_ignore_ascii_case("csv"));
        match ChartFile::for_path(&self.output) {
            Some(chart) => Ok(StudyFile::Chart(chart)),
            None if csv => Ok(StudyFile::Csv),
            None => anyhow::bail!("{}: unsupported output type (use .png, .svg or .csv)", self.output.display()),
        }
    }
}

/// A PNG's pixels of the scene; for a term view, its scale is printed on standard output (the scale depends
/// on the image: see `TermScale`), for an exact environment how exact it came out.
pub fn render_png_pixels(renderer: &mut Renderer, scene: &Scene) -> vk_render::Result<image::RgbImage> {
    let picture = renderer.render_picture(scene)?;
    match &picture.scale {
        Some(scale) => println!("{}", scale.describe()),
        None => print_accuracy(renderer),
    }
    Ok(picture.pixels)
}

/// Says how exact the environment light of the last image is, when it was integrated in the exact mode.
pub fn print_accuracy(renderer: &Renderer) {
    if let Some(accuracy) = renderer.accuracy() {
        println!("environment (exact): {accuracy}");
    }
}

/// A counter on standard error for a search whose length is not known ahead (a fit's models evaluated).
pub fn counter(what: &str, unit: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new_spinner();
    if let Ok(style) =
        indicatif::ProgressStyle::with_template(&format!("{{msg}} {{spinner}} {{pos}} {unit} ({{elapsed}})"))
    {
        bar.set_style(style);
    }
    bar.set_message(what.to_string());
    bar
}

/// A progress bar on standard error for a long command (sweeps, figures, fits, furnace tables, albedos):
/// drawn only when standard error is a terminal (indicatif draws nothing otherwise, so scripts and pipes see
/// no such output), cleared when dropped.
pub fn progress(len: usize, what: &str) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(len as u64);
    if let Ok(style) = indicatif::ProgressStyle::with_template("{msg} [{bar:32}] {pos}/{len} ({elapsed})") {
        bar.set_style(style.progress_chars("=> "));
    }
    bar.set_message(what.to_string());
    bar
}
