//! The library's error type: every failure a user can cause names the file, the key and the value.

use std::path::PathBuf;

use ash::vk;

/// Everything that can go wrong while loading a scene, talking to Vulkan or writing an image.
#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// The scene file is unreadable, malformed or out of range; `message` names the key and the value.
    #[error("{}: {message}", file.display())]
    Scene {
        /// The scene file (or the file that `--set` overrides were applied to).
        file: PathBuf,
        /// What is wrong: the key as a `--set` path and its value, e.g. `image.width = 0: must be ...`.
        message: String,
    },

    /// A mesh file referenced by a scene could not be loaded.
    #[error("{}: {key} = {value:?}: {message}", scene.display())]
    Mesh {
        /// The scene file that names the mesh.
        scene: PathBuf,
        /// The object's key, `object.N.path`.
        key: String,
        /// The mesh's path as resolved (or `(triangles)` for triangles a command made).
        value: String,
        /// Why it could not be loaded (or traced by the reference).
        message: String,
    },

    /// The environment map of a scene could not be used.
    #[error("{}: environment.map = {value:?}: {message}", scene.display())]
    Map {
        /// The scene file whose `[environment]` names the map.
        scene: PathBuf,
        /// The map's path as resolved, or a built-in's name.
        value: String,
        /// Why it is unusable: unreadable, not an image, not 2:1, a texel negative or not finite, or wider than
        /// the device allows.
        message: String,
    },

    /// A GLSL file failed to compile; `log` is shaderc's message (file:line: error).
    #[error("shader {path} failed to compile:\n{log}")]
    Shader {
        /// The entry file under `shaders/` (`FILE+MACRO` for a variant), `(shaderc)` when shaderc cannot start,
        /// or the name of a `check` mistake whose edit does not apply.
        path: String,
        /// The compiler's message, or why the source could not be made.
        log: String,
    },

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
    Input {
        /// The image file (or the name given where a file or model was expected).
        path: PathBuf,
        /// What is wrong with it.
        message: String,
    },

    /// The device did not finish a piece of work within the timeout (`--timeout`), and was given up: the
    /// analytic models the work evaluated, which may never end (a `while (true)`), are named.
    #[error("the device did not finish its work within {seconds} s (--timeout){}", suspects(models))]
    Timeout {
        /// The timeout that passed, in seconds.
        seconds: f64,
        /// The `.brdf` files of the analytic models the work evaluated (empty when none).
        models: Vec<PathBuf>,
    },

    /// The computation was asked to stop before it was done (see `interrupt`).
    #[error("interrupted")]
    Interrupted,

    /// The output image could not be written.
    #[error("{}: {message}", path.display())]
    Output {
        /// The file that was being written.
        path: PathBuf,
        /// Why it failed.
        message: String,
    },
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
