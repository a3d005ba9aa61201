//! The commands of `vk-render`, one module each: its arguments and what it does. `main.rs` is the table of
//! them; what several share (the scene overrides, warnings, output paths) is here.

pub mod devices;
pub mod figures;
#[cfg(feature = "preview")]
pub mod preview;
pub mod reference;
pub mod render;
mod sheets;
pub mod sweep;

use std::path::Path;

use clap::Args;

use vk_render::{Override, Scene};

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

    /// Override one scene value by its dotted path, e.g. material.grey.kd=0.8 or light.0.power=30.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    overrides: Vec<Override>,
}

impl ImageArgs {
    /// The shorthands as overrides, then the --set ones.
    pub fn overrides(&self) -> Vec<Override> {
        let mut overrides = Vec::new();
        for (key, value) in [("width", self.width), ("height", self.height), ("samples", self.samples)] {
            if let Some(value) = value {
                overrides.push(Override::new(format!("image.{key}"), value));
            }
        }
        overrides.extend(self.overrides.iter().cloned());
        overrides
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
