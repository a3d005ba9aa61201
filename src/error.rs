//! The library's error type: every failure a user can cause names the file, the key and the value.

use std::path::PathBuf;

use ash::vk;

/// Everything that can go wrong while loading a scene, talking to Vulkan or writing an image.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene file is unreadable, malformed or out of range; `message` names the key and the value.
    #[error("{}: {message}", file.display())]
    Scene { file: PathBuf, message: String },

    /// A mesh file referenced by a scene could not be loaded.
    #[error("{}: {key} = {value:?}: {message}", scene.display())]
    Mesh { scene: PathBuf, key: String, value: String, message: String },

    /// The environment map of a scene could not be used.
    #[error("{}: environment.map = {value:?}: {message}", scene.display())]
    Map { scene: PathBuf, value: String, message: String },

    /// A GLSL file failed to compile; `log` is shaderc's message (file:line: error).
    #[error("shader {path} failed to compile:\n{log}")]
    Shader { path: String, log: String },

    /// No Vulkan loader or no usable device: the message says what to install.
    #[error("{0}")]
    NoVulkan(String),

    /// `--device` named no device, or the chosen device lacks what the renderer needs.
    #[error("{0}")]
    Device(String),

    /// The validation layer reported problems (only when validation is on).
    #[error("the Vulkan validation layer reported {} message(s):\n{}", .0.len(), .0.join("\n"))]
    Validation(Vec<String>),

    /// A Vulkan call failed.
    #[error("Vulkan call failed: {0}")]
    Vulkan(#[from] vk::Result),

    /// GPU memory could not be allocated.
    #[error("GPU memory allocation failed: {0}")]
    Allocation(#[from] gpu_allocator::AllocationError),

    /// The preview's window could not be opened or run.
    #[error("{0}")]
    Preview(String),

    /// An input image (one to check or fit against) could not be read.
    #[error("{}: {message}", path.display())]
    Input { path: PathBuf, message: String },

    /// The device did not finish a piece of work within the timeout (`--timeout`), and was given up: the
    /// analytic models the work evaluated, which may never end (a `while (true)`), are named.
    #[error("the device did not finish its work within {seconds} s (--timeout){}", suspects(models))]
    Timeout { seconds: f64, models: Vec<PathBuf> },

    /// The computation was asked to stop before it was done (see `interrupt`).
    #[error("interrupted")]
    Interrupted,

    /// The output image could not be written.
    #[error("{}: {message}", path.display())]
    Output { path: PathBuf, message: String },
}

/// What a timeout's message says of the analytic models the work evaluated.
fn suspects(models: &[PathBuf]) -> String {
    match models {
        [] => ": the device is given up".to_string(),
        models => {
            let names: Vec<String> = models.iter().map(|m| m.display().to_string()).collect();
            format!(": the BRDF of {} may never end; the device is given up", names.join(", "))
        }
    }
}

/// The library's result type.
pub type Result<T, E = Error> = std::result::Result<T, E>;
