//! The frames of a scene that changes, as the preview and the server's explore page draw them. While
//! anything moves (the camera, a material, the window's size) a motion frame: the scene at a fraction of the
//! window's size with one sample (and the environment's fast mode), scaled up, cheap enough to keep up. Once
//! nothing has moved for [`SETTLE_FRAMES`] frames, the exact frame: the very image `vk-render render` makes.
//! With an environment, the still image is first the fast mode, then one pass of the exact mode added per
//! frame, shown once there are enough of them to judge, until the exact mode's own bound says it is done: the
//! image `vk-render render` makes in the exact mode.

use super::Renderer;
use crate::error::Result;
use crate::pictures::output::{encode_texels, TexelOrder};
use crate::render::exact::{Passes, MIN_PASSES};
use crate::scene::{Environment, EnvironmentMode, Scene};

/// Frames a scene must stay unchanged before the exact frame replaces the motion frames: a drag pauses
/// between mouse events, and an exact frame drawn in such a pause would make the next motion frame late.
pub const SETTLE_FRAMES: u32 = 3;

/// A motion frame is drawn at 1/MOTION_SCALE of the window's width and height, with MOTION_SAMPLES samples
/// a pixel, and scaled up bilinearly (measured in docs/performance.md's benchmark: the orbiting bunny's frame).
pub const MOTION_SCALE: u32 = 2;
/// Samples a pixel of a motion frame: see [`MOTION_SCALE`].
pub const MOTION_SAMPLES: u32 = 1;

/// What the frames so far were of: the scene of the last one, and for how many frames it has not changed.
#[derive(Default)]
pub struct Frames {
    last: Option<Scene>,
    still: u32,
    /// The exact passes of the still image's environment.
    refinement: Option<Refinement>,
    /// The motion frame before it is scaled up (kept while the size holds).
    small: Vec<u8>,
}

impl Frames {
    /// Whether frames should follow without waiting for an event: the scene is settling after a motion, or
    /// its still image refines.
    pub fn unfinished(&self) -> bool {
        self.last.is_some() && self.still < SETTLE_FRAMES || self.refinement.as_ref().is_some_and(|r| !r.done)
    }
}

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
    /// Something moved: a motion frame.
    Moving,
    /// A scene without an environment: the render itself.
    Render,
    /// The fast mode (something moved, or too few exact passes yet).
    Fast,
    /// The mean of the exact passes so far.
    Exact {
        /// The environment's samples a pixel so far, over every pass.
        samples: u32,
        /// Whether the exact mode's bound says the image is done.
        done: bool,
    },
}

impl Shown {
    /// For the window's title.
    pub fn describe(self) -> String {
        match self {
            Shown::Moving => format!(" - moving: 1/{MOTION_SCALE} size, {MOTION_SAMPLES} sample"),
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

/// Renders the frame of `scene` into `texels`: a motion frame while the scene keeps changing (from its
/// first change on: the very first frame is a still one), the still image once it has not changed for
/// [`SETTLE_FRAMES`] frames. The still image is the render itself without an environment; with one, the fast
/// mode when `scene` is not the one refined so far (refinement then starts over), else one more exact pass
/// and, from MIN_PASSES on, their mean.
///
/// # Errors
/// As [`Renderer::render_texels`].
pub fn render_frame(
    renderer: &mut Renderer,
    frames: &mut Frames,
    scene: &Scene,
    order: TexelOrder,
    texels: &mut [u8],
) -> Result<Shown> {
    match &frames.last {
        Some(last) if last == scene => frames.still = frames.still.saturating_add(1),
        Some(_) => {
            frames.last = Some(scene.clone());
            frames.still = 0;
        }
        None => {
            frames.last = Some(scene.clone());
            frames.still = SETTLE_FRAMES;
        }
    }
    if frames.still < SETTLE_FRAMES {
        draw_motion_frame(renderer, &mut frames.small, scene, order, texels)?;
        return Ok(Shown::Moving);
    }
    let refinement = &mut frames.refinement;
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

/// The scene a motion frame draws: 1/MOTION_SCALE of its size (at least a pixel), MOTION_SAMPLES samples,
/// its environment in the fast mode.
pub fn motion_scene(scene: &Scene) -> Scene {
    let mut small = scene.clone();
    small.image.width = scene.image.width.div_ceil(MOTION_SCALE);
    small.image.height = scene.image.height.div_ceil(MOTION_SCALE);
    small.image.samples = MOTION_SAMPLES;
    if let Some(environment) = &scene.environment {
        small.environment = Some(Environment { mode: EnvironmentMode::Fast, ..environment.clone() });
    }
    small
}

/// Draws the motion frame of `scene` into `texels` (at the scene's size): [`motion_scene`] rendered into
/// `small`, then scaled up.
///
/// # Errors
/// As [`Renderer::render_texels`].
pub fn draw_motion_frame(
    renderer: &mut Renderer,
    small: &mut Vec<u8>,
    scene: &Scene,
    order: TexelOrder,
    texels: &mut [u8],
) -> Result<()> {
    let motion = motion_scene(scene);
    let (width, height) = (motion.image.width, motion.image.height);
    small.resize(width as usize * height as usize * order.bytes(), 0);
    renderer.render_texels(&motion, order, small)?;
    scale_up(small, (width, height), texels, (scene.image.width, scene.image.height), order.bytes());
    Ok(())
}

/// Scales an image of `bytes`-byte texels up from `from` to `to` pixels, bilinearly between the small
/// image's pixel centres (clamped at its edges), so that a motion frame is not blocky. Separably: each source
/// row the target rows read is blended across once (weights of 1/256), then each target row blends two of
/// those (a profile of the orbiting bunny showed the direct per-texel form at 15% of the preview's time).
pub fn scale_up(small: &[u8], from: (u32, u32), texels: &mut [u8], to: (u32, u32), bytes: usize) {
    let (fw, fh) = (from.0 as usize, from.1 as usize);
    let (tw, th) = (to.0 as usize, to.1 as usize);
    if fw == 0 || fh == 0 || tw == 0 || th == 0 {
        return;
    }
    // Where each target pixel's centre falls between two source pixel centres, and how far (of 256).
    let taps = |target: usize, source: usize| -> Vec<(usize, usize, u32)> {
        (0..target)
            .map(|i| {
                let x = ((i as f32 + 0.5) * source as f32 / target as f32 - 0.5).max(0.0);
                let left = (x as usize).min(source - 1);
                let right = (left + 1).min(source - 1);
                (left, right, ((x - left as f32) * 256.0).round().min(256.0) as u32)
            })
            .collect()
    };
    let columns = taps(tw, fw);
    // Source row y blended across to the target's width.
    let across = |y: usize, row: &mut Vec<u32>| {
        row.clear();
        let source = &small[y * fw * bytes..(y + 1) * fw * bytes];
        for &(left, right, t) in &columns {
            let (a, b) = (&source[left * bytes..(left + 1) * bytes], &source[right * bytes..(right + 1) * bytes]);
            row.extend(a.iter().zip(b).map(|(&a, &b)| u32::from(a) * (256 - t) + u32::from(b) * t));
        }
    };
    let (mut upper, mut lower) = (Vec::with_capacity(tw * bytes), Vec::with_capacity(tw * bytes));
    let mut held: Option<(usize, usize)> = None;
    for ((top, bottom, t), target) in taps(th, fh).into_iter().zip(texels.chunks_exact_mut(tw * bytes)) {
        if held != Some((top, bottom)) {
            match held {
                Some((_, previous)) if previous == top => std::mem::swap(&mut upper, &mut lower),
                _ => across(top, &mut upper),
            }
            across(bottom, &mut lower);
            held = Some((top, bottom));
        }
        for ((out, &u), &l) in target.iter_mut().zip(&upper).zip(&lower) {
            *out = ((u * (256 - t) + l * t + (1 << 15)) >> 16) as u8;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::scale_up;

    #[test]
    fn scaling_up_keeps_flat_regions_and_blends_between_pixel_centres() {
        // Two pixels, black and white, doubled: the outer pixels keep their value, the inner ones blend.
        let small = [0u8, 255];
        let mut big = [0u8; 4];
        scale_up(&small, (2, 1), &mut big, (4, 1), 1);
        assert_eq!(big, [0, 64, 191, 255]);
        // A flat image stays flat at any size, and every channel is scaled alike.
        let flat = [10u8, 20, 30, 255].repeat(6);
        let mut out = vec![0u8; 4 * 7 * 5];
        scale_up(&flat, (3, 2), &mut out, (7, 5), 4);
        assert!(out.chunks(4).all(|t| t == [10, 20, 30, 255]));
    }
}
