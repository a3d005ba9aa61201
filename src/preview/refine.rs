//! The preview's environment light: a frame in the fast mode whenever anything changed (the camera, a
//! material, the window's size), then, while nothing does, one pass of the exact mode added per frame,
//! shown once there are enough of them to judge, until the exact mode's own bound says it is done: the
//! still image becomes the very image `vk-render render` makes in the exact mode.

use crate::error::Result;
use crate::output::{encode_texels, TexelOrder};
use crate::render::exact::{Passes, MIN_PASSES};
use crate::scene::{Environment, EnvironmentMode, Scene};
use crate::Renderer;

/// The exact passes of the image now shown (one image's lifetime).
pub struct Refinement {
    exact: Scene,
    passes: Passes,
    /// Whether the passes are enough, as of the last one added (the check reads every pixel: once a pass).
    done: bool,
}

/// What a frame showed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Shown {
    /// A scene without an environment: the render itself.
    Render,
    /// The fast mode (something moved, or too few exact passes yet).
    Fast,
    /// The mean of the exact passes so far.
    Exact { samples: u32, done: bool },
}

impl Shown {
    /// For the window's title.
    pub fn describe(self) -> String {
        match self {
            Shown::Render => String::new(),
            Shown::Fast => " - environment: fast".into(),
            Shown::Exact { samples, done: false } => format!(" - environment: exact, {samples} samples..."),
            Shown::Exact { samples, done: true } => format!(" - environment: exact, {samples} samples"),
        }
    }
}

/// `scene` with its environment in `mode`.
fn in_mode(scene: &Scene, environment: &Environment, mode: EnvironmentMode) -> Scene {
    Scene { environment: Some(Environment { mode, ..environment.clone() }), ..scene.clone() }
}

/// Renders the frame of `scene` into `texels`: the render itself without an environment; with one, the fast
/// mode when `scene` is not the one refined so far (refinement then starts over), else one more exact pass
/// and, from MIN_PASSES on, their mean.
///
/// # Errors
/// As [`Renderer::render_texels`].
pub fn render_frame(
    renderer: &mut Renderer,
    refinement: &mut Option<Refinement>,
    scene: &Scene,
    order: TexelOrder,
    texels: &mut [u8],
) -> Result<Shown> {
    let Some(environment) = &scene.environment else {
        *refinement = None;
        renderer.render_texels(scene, order, texels)?;
        return Ok(Shown::Render);
    };
    let exact = in_mode(scene, environment, EnvironmentMode::Exact);
    let current = refinement.as_mut().filter(|r| r.exact == exact);
    let Some(current) = current else {
        renderer.render_texels(&in_mode(scene, environment, EnvironmentMode::Fast), order, texels)?;
        let passes = Passes::new(scene.image.width, scene.image.height);
        *refinement = Some(Refinement { passes, exact, done: false });
        return Ok(Shown::Fast);
    };
    if !current.done {
        renderer.refine(&current.exact, &mut current.passes)?;
        current.done = current.passes.done(&current.exact.image);
    }
    if current.passes.count < MIN_PASSES {
        renderer.render_texels(&in_mode(scene, environment, EnvironmentMode::Fast), order, texels)?;
        return Ok(Shown::Fast);
    }
    encode_texels(&current.passes.mean_bytes(), &current.exact.image, order, texels);
    Ok(Shown::Exact { samples: current.passes.samples(), done: current.done })
}

/// Whether the image shown still refines: frames should follow without waiting for an event.
pub fn refining(refinement: &Option<Refinement>) -> bool {
    refinement.as_ref().is_some_and(|r| !r.done)
}
