//! vk-render's errors as Python exceptions, and the one way the binding runs Rust work: with the GIL
//! released, a panic caught, and Ctrl-C heard within a tenth of a second.

use std::panic::AssertUnwindSafe;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

use pyo3::exceptions::PyKeyboardInterrupt;
use pyo3::prelude::*;
use vk_render::Error;

/// How often a waiting call looks for Ctrl-C (Python's signal handlers run only when asked).
const SIGNAL_POLL: Duration = Duration::from_millis(100);

/// The exception classes of `vk_render._errors` (pure Python, so that SceneError can also be a
/// ValueError and DeviceError a RuntimeError).
fn exception(py: Python<'_>, class: &str, message: String) -> PyErr {
    match py.import("vk_render._errors").and_then(|module| module.getattr(class)) {
        Ok(class) => PyErr::from_type(class.downcast_into().expect("an exception class"), message),
        Err(e) => e,
    }
}

/// A vk-render error as its exception: a bad scene, key or value is a SceneError, whose message is the
/// command line's one line; anything of Vulkan or the device a DeviceError; the rest vk_render.Error.
pub fn to_py(py: Python<'_>, error: Error) -> PyErr {
    let class = match &error {
        Error::Interrupted => return PyKeyboardInterrupt::new_err("interrupted"),
        Error::Scene { .. } | Error::Mesh { .. } | Error::Map { .. } => "SceneError",
        Error::NoVulkan(_)
        | Error::Device(_)
        | Error::Vulkan(_)
        | Error::Allocation(_)
        | Error::Validation(_)
        | Error::Shader { .. }
        | Error::Timeout { .. } => "DeviceError",
        Error::Input { .. } | Error::Output { .. } | Error::Preview(_) => "Error",
    };
    exception(py, class, error.to_string())
}

/// A SceneError with `message` (for what the binding itself finds wrong in a scene's words).
pub fn scene_error(py: Python<'_>, message: String) -> PyErr {
    exception(py, "SceneError", message)
}

/// Issues each of the scene's warnings as a `vk_render.SceneWarning` (Python's warnings module shows each
/// once per place, as `vk-render` prints them once per command).
pub fn warn(py: Python<'_>, warnings: Vec<String>) -> PyResult<()> {
    if warnings.is_empty() {
        return Ok(());
    }
    let category = py.import("vk_render._errors")?.getattr("SceneWarning")?;
    for warning in warnings {
        let text = std::ffi::CString::new(warning.replace('\0', " ")).unwrap_or_default();
        PyErr::warn(py, &category, &text, 1)?;
    }
    Ok(())
}

/// vk_render.Error with `message`.
pub fn error(py: Python<'_>, message: String) -> PyErr {
    exception(py, "Error", message)
}

/// Runs `work` on a thread of its own with the GIL released, so that other Python threads (and other
/// renderers) go on meanwhile. This thread waits for it, and every [`SIGNAL_POLL`] runs Python's signal
/// handlers: on Ctrl-C it asks the work to stop (`vk_render::interrupt`, checked between passes, rows and
/// renders), waits for it, and raises KeyboardInterrupt. A panic in the work is vk_render.Error, not an
/// abort.
pub fn detached<T: Send>(py: Python<'_>, work: impl FnOnce() -> vk_render::Result<T> + Send) -> PyResult<T> {
    let (outcome, interrupted) = py.allow_threads(|| {
        std::thread::scope(|scope| {
            let (done, finished) = mpsc::channel();
            scope.spawn(move || {
                let _ = done.send(std::panic::catch_unwind(AssertUnwindSafe(work)));
            });
            let mut interrupted: Option<PyErr> = None;
            loop {
                match finished.recv_timeout(SIGNAL_POLL) {
                    Ok(outcome) => break (Some(outcome), interrupted),
                    Err(RecvTimeoutError::Disconnected) => break (None, interrupted),
                    Err(RecvTimeoutError::Timeout) if interrupted.is_none() => {
                        if let Err(signal) = Python::with_gil(|py| py.check_signals()) {
                            vk_render::interrupt::request();
                            interrupted = Some(signal);
                        }
                    }
                    Err(RecvTimeoutError::Timeout) => {}
                }
            }
        })
    });
    if let Some(signal) = interrupted {
        vk_render::interrupt::clear();
        return Err(signal);
    }
    match outcome {
        Some(Ok(Ok(value))) => Ok(value),
        Some(Ok(Err(e))) => Err(to_py(py, e)),
        Some(Err(panic)) => {
            let what = panic
                .downcast_ref::<&str>()
                .map(|s| s.to_string())
                .or_else(|| panic.downcast_ref::<String>().cloned())
                .unwrap_or_else(|| "a panic without a message".into());
            Err(error(py, format!("vk-render panicked (a bug: please report it): {what}")))
        }
        None => Err(error(py, "vk-render's worker thread ended without a result".into())),
    }
}
