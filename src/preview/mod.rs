//! `vk-render preview`: the offscreen renderer's images shown live in a window, with an orbit camera, keys
//! to change the selected object's material, and hot reloading of the scene file and the shaders.
//!
//! Each frame is the very image `vk-render render` makes (same renderer, shaders and pipelines, same
//! output transform), copied into a swapchain image and presented: what the window shows is what a render
//! writes, byte for byte.

mod controls;

use std::collections::VecDeque;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::{Duration, Instant, SystemTime};

use ash::vk;
use gpu_allocator::MemoryLocation;
use raw_window_handle::{HasDisplayHandle, HasWindowHandle};
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::Key;
use winit::window::{Window, WindowId};

use crate::render::interactive as frames;
pub use crate::render::interactive::{
    draw_motion_frame, motion_scene, scale_up, MOTION_SAMPLES, MOTION_SCALE, SETTLE_FRAMES,
};
pub use controls::{key_action, parse_script, Action, Controls, Orbit, ScriptStep, ORBIT_STEP_PIXELS};

use crate::analysis::lobe3d::lobe_on_object;
use crate::error::{Error, Result};
use crate::pictures::output::TexelOrder;
use crate::scene::{Camera, Object, Override, Scene};
use crate::vulkan::{
    layer_range, layout_transition, whole_image_copy, Access, Buffer, BufferDesc, Instance, ShaderSources, Surface,
    Swapchain,
};
use crate::{Renderer, RendererOptions};

/// How to run the preview.
pub struct PreviewOptions {
    /// The scene file shown, reloaded when it changes.
    pub scene: PathBuf,
    /// `--set` overrides applied on every load.
    pub overrides: Vec<Override>,
    /// How to make the renderer (device, validation); the preview adds the window's extensions.
    pub renderer: RendererOptions,
    /// Stop after this many presented frames (for headless checks).
    pub frames: Option<u64>,
    /// Stop after this long (a test hook, for hot reloading).
    pub duration: Option<Duration>,
    /// Save the last presented frame here on exit.
    pub screenshot: Option<PathBuf>,
    /// Keys pressed (and resizes) one per frame from the first: a test hook standing in for the keyboard,
    /// handled as the keyboard's events are.
    pub script: Vec<ScriptStep>,
    /// A shaders/ folder watched and reloaded on change (the source tree's, when it is there).
    pub shaders: Option<PathBuf>,
}

/// Why no window could be opened, in one line that says how to get a display (winit's own message names
/// its source files; it is logged for -v).
fn no_window(error: &winit::error::EventLoopError) -> Error {
    log::info!("winit: {error}");
    let set = |name: &str| std::env::var(name).ok().filter(|v| !v.is_empty());
    let hint = "run it in a desktop session, or under a virtual X server: xvfb-run -a vk-render preview SCENE \
                (Debian package xvfb)";
    Error::Preview(match (set("DISPLAY"), set("WAYLAND_DISPLAY").or_else(|| set("WAYLAND_SOCKET"))) {
        (None, None) => format!("no display: neither DISPLAY nor WAYLAND_DISPLAY is set; {hint}"),
        (Some(display), None) => format!("cannot open a window: no X server answers on DISPLAY={display}; {hint}"),
        (_, Some(wayland)) => format!("cannot open a window on the Wayland display {wayland}; {hint}"),
    })
}

/// Opens the window and runs until it is closed, Esc is pressed or `frames` frames were presented.
///
/// # Errors
/// The scene's error before the window opens; `Error::Preview` when no window can be made; Vulkan and
/// validation errors while rendering. A scene or shader broken while the preview runs is logged, and the
/// last good one kept.
pub fn run(options: PreviewOptions) -> Result<()> {
    let scene = Scene::load(&options.scene, &options.overrides)?;
    let event_loop = EventLoop::new().map_err(|e| no_window(&e))?;
    let mut app = App { options, scene: Some(scene), running: None, error: None, pace: FramePace::default() };
    event_loop.run_app(&mut app).map_err(|e| Error::Preview(format!("the window's event loop failed: {e}")))?;
    if let Some(error) = app.error {
        return Err(error);
    }
    if app.options.frames.is_some() {
        eprintln!("{}", app.pace);
    }
    Ok(())
}

/// When frames were presented: how many, and the first and the last one's time; how many were motion
/// frames, and the time from the frame before each of them to it.
#[derive(Clone, Copy, Debug, Default)]
struct FramePace {
    presented: u64,
    first: Option<Instant>,
    last: Option<Instant>,
    moving: u64,
    moving_time: Duration,
}

impl FramePace {
    fn presented_one(&mut self, moving: bool) {
        let now = Instant::now();
        if let (true, Some(before)) = (moving, self.last) {
            self.moving += 1;
            self.moving_time += now - before;
        }
        self.presented += 1;
        self.first.get_or_insert(now);
        self.last = Some(now);
    }
}

impl std::fmt::Display for FramePace {
    /// "presented N frames in T s (F frames/s)", T from the first frame presented to the last, so that
    /// start-up is not in it, and F the N - 1 frames after the first over T; then, if some were motion
    /// frames, "; M moving frames, X ms each" (each from the frame before it).
    fn fmt(&self, f: &mut std::fmt::Formatter) -> std::fmt::Result {
        let seconds = match (self.first, self.last) {
            (Some(first), Some(last)) => (last - first).as_secs_f64(),
            _ => 0.0,
        };
        let rate = if seconds > 0.0 { (self.presented - 1) as f64 / seconds } else { 0.0 };
        write!(f, "presented {} frames in {seconds:.3} s ({rate:.1} frames/s)", self.presented)?;
        if self.moving > 0 {
            let each = self.moving_time.as_secs_f64() * 1e3 / self.moving as f64;
            write!(f, "; {} moving frames, {each:.2} ms each", self.moving)?;
        }
        Ok(())
    }
}

struct App {
    options: PreviewOptions,
    /// The scene until the window opens.
    scene: Option<Scene>,
    running: Option<Running>,
    error: Option<Error>,
    /// Kept past the window, for the line printed at exit.
    pace: FramePace,
}

impl App {
    fn fail(&mut self, event_loop: &ActiveEventLoop, error: Error) {
        self.error = Some(error);
        event_loop.exit();
    }
}

impl ApplicationHandler for App {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.running.is_some() {
            return;
        }
        let Some(scene) = self.scene.take() else { return };
        match Running::new(event_loop, &mut self.options, scene) {
            Ok(running) => self.running = Some(running),
            Err(e) => self.fail(event_loop, e),
        }
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _: WindowId, event: WindowEvent) {
        let Some(running) = self.running.as_mut() else { return };
        let outcome = match event {
            WindowEvent::CloseRequested => {
                event_loop.exit();
                Ok(())
            }
            WindowEvent::RedrawRequested => running.redraw(event_loop),
            WindowEvent::Resized(_) => {
                running.window.request_redraw();
                Ok(())
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed && !event.repeat => {
                running.key_pressed(&event.logical_key, event_loop)
            }
            WindowEvent::MouseInput { state, button: MouseButton::Left, .. } => {
                running.dragging = state == ElementState::Pressed;
                Ok(())
            }
            WindowEvent::CursorMoved { position, .. } => {
                if let (true, Some((x, y))) = (running.dragging, running.cursor) {
                    running.controls.orbit.drag((position.x - x) as f32, (position.y - y) as f32);
                    running.camera_moved();
                }
                running.cursor = Some((position.x, position.y));
                Ok(())
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => p.y as f32 / 40.0,
                };
                running.controls.orbit.zoom(lines);
                running.camera_moved();
                Ok(())
            }
            _ => Ok(()),
        };
        if let Err(e) = outcome {
            self.fail(event_loop, e);
        }
    }

    fn about_to_wait(&mut self, event_loop: &ActiveEventLoop) {
        let Some(running) = self.running.as_mut() else { return };
        running.hot_reload();
        let refining = running.frames.unfinished();
        if running.options_frames.is_some() || running.deadline.is_some() || !running.script.is_empty() || refining {
            // Headless runs draw frame after frame until done; a still image refines frame after frame.
            running.window.request_redraw();
            event_loop.set_control_flow(ControlFlow::Poll);
        } else {
            // Wake up twice a second to look for edited files.
            event_loop.set_control_flow(ControlFlow::WaitUntil(Instant::now() + RELOAD_INTERVAL));
        }
    }

    fn exiting(&mut self, _: &ActiveEventLoop) {
        if let Some(running) = &self.running {
            self.pace = running.pace;
        }
        // Vulkan objects go before the window they present to.
        self.running = None;
    }
}

/// How often the scene file and the shaders are looked at.
const RELOAD_INTERVAL: Duration = Duration::from_millis(500);

/// Everything the open window needs. Field order is drop order: the swapchain before its surface, both
/// before the renderer's device, and the window last.
struct Running {
    swapchain: Option<Swapchain>,
    surface: Arc<Surface>,
    renderer: Renderer,
    /// The host buffer each frame is encoded into and copied to the swapchain from, kept while the size holds.
    upload: Option<Buffer>,
    /// The scene as the user changed it, and the last one that rendered.
    scene: Scene,
    last_good: Scene,
    original_camera: Camera,
    controls: Controls,
    dragging: bool,
    cursor: Option<(f64, f64)>,
    script: VecDeque<ScriptStep>,
    options_frames: Option<u64>,
    deadline: Option<Instant>,
    pace: FramePace,
    screenshot_at_exit: Option<PathBuf>,
    screenshot_next: Option<PathBuf>,
    screenshots_saved: u32,
    scene_path: PathBuf,
    overrides: Vec<Override>,
    watched: Watched,
    window: Arc<Window>,
    /// The lobe shown (B): the scene and the object it was made for, and its objects, made again when either
    /// changes (the camera included: the lobe stands where the camera sees it best).
    lobe: Option<((Scene, usize), Vec<Object>)>,
    /// What the frames so far drew: motion or still, the environment's exact passes (refine.rs).
    frames: frames::Frames,
    /// What the last frame showed of the environment, for the title.
    shown: frames::Shown,
}

impl Running {
    fn new(event_loop: &ActiveEventLoop, options: &mut PreviewOptions, scene: Scene) -> Result<Self> {
        let window_error = |e: &dyn std::fmt::Display| Error::Preview(format!("cannot open a window: {e}"));
        let attributes = Window::default_attributes()
            .with_title("vk-render")
            .with_inner_size(PhysicalSize::new(scene.image.width, scene.image.height));
        let window = Arc::new(event_loop.create_window(attributes).map_err(|e| window_error(&e))?);
        let display = event_loop.display_handle().map_err(|e| window_error(&e))?.as_raw();
        let window_handle = window.window_handle().map_err(|e| window_error(&e))?.as_raw();
        let mut renderer_options = std::mem::take(&mut options.renderer);
        renderer_options.instance_extensions.extend(Surface::required_extensions(display)?);
        renderer_options.device_extensions.push(ash::khr::swapchain::NAME);
        // The surface first: the device must be one whose queue can present to this window.
        let instance = Arc::new(Instance::new(renderer_options.validate, &renderer_options.instance_extensions)?);
        let surface = Arc::new(Surface::new(&instance, display, window_handle)?);
        let renderer = Renderer::on_instance(instance, renderer_options, Some((&surface.loader, surface.raw)))?;
        let controls = Controls::new(&scene);
        let mut watched = Watched::new(&options.scene, options.shaders.clone());
        watched.watch_brdfs(&scene);
        Ok(Self {
            swapchain: None,
            upload: None,
            surface,
            renderer,
            last_good: scene.clone(),
            original_camera: scene.camera,
            scene,
            controls,
            dragging: false,
            cursor: None,
            script: options.script.drain(..).collect(),
            options_frames: options.frames,
            deadline: options.duration.map(|d| Instant::now() + d),
            pace: FramePace::default(),
            screenshot_at_exit: options.screenshot.clone(),
            screenshot_next: None,
            screenshots_saved: 0,
            scene_path: options.scene.clone(),
            overrides: options.overrides.clone(),
            watched,
            window,
            lobe: None,
            frames: frames::Frames::default(),
            shown: frames::Shown::Render,
        })
    }

    fn camera_moved(&mut self) {
        self.scene.camera.position = self.controls.orbit.position(self.scene.camera.look_at);
        self.window.request_redraw();
    }

    /// A key pressed, from the keyboard or a test script.
    fn key_pressed(&mut self, key: &Key, event_loop: &ActiveEventLoop) -> Result<()> {
        match key_action(key) {
            Some(action) => self.act(action, event_loop),
            None => Ok(()),
        }
    }

    fn act(&mut self, action: Action, event_loop: &ActiveEventLoop) -> Result<()> {
        match action {
            Action::Quit => event_loop.exit(),
            Action::Screenshot => {
                self.screenshots_saved += 1;
                self.screenshot_next =
                    Some(PathBuf::from(format!("vk-render-screenshot-{}.png", self.screenshots_saved)));
            }
            other => self.controls.apply(other, &mut self.scene, &self.original_camera),
        }
        self.window.request_redraw();
        Ok(())
    }

    /// Looks for edited files; a scene or shaders that fail keep the last good ones, with the error logged.
    fn hot_reload(&mut self) {
        let (scene_changed, shaders_changed) = self.watched.poll();
        if scene_changed {
            match Scene::load(&self.scene_path, &self.overrides) {
                Ok(scene) => {
                    log::info!("reloaded {}", self.scene_path.display());
                    self.watched.watch_brdfs(&scene);
                    self.original_camera = scene.camera;
                    self.scene = scene;
                    self.controls.selected = self.controls.selected.min(self.scene.objects.len().saturating_sub(1));
                    self.scene.camera.position = self.controls.orbit.position(self.scene.camera.look_at);
                }
                Err(e) => log::error!("{e} (keeping the last good scene)"),
            }
            self.window.request_redraw();
        }
        if let Some(folder) = shaders_changed {
            let reloaded = ShaderSources::from_directory(&folder)
                .map_err(|e| Error::Output { path: folder.clone(), message: format!("cannot read the shaders: {e}") })
                .and_then(|sources| self.renderer.set_shaders(sources));
            match reloaded {
                Ok(()) => log::info!("reloaded the shaders of {}", folder.display()),
                Err(e) => log::error!("{e} (keeping the last good shaders)"),
            }
            self.window.request_redraw();
        }
    }

    fn redraw(&mut self, event_loop: &ActiveEventLoop) -> Result<()> {
        match self.script.pop_front() {
            Some(ScriptStep::Key(key)) => self.key_pressed(&key, event_loop)?,
            Some(ScriptStep::Orbit) => {
                self.controls.orbit.drag(ORBIT_STEP_PIXELS, 0.0);
                self.camera_moved();
            }
            Some(ScriptStep::Resize(width, height)) => {
                let _ = self.window.request_inner_size(PhysicalSize::new(width, height));
            }
            None => {}
        }
        let size = self.window.inner_size();
        if size.width == 0 || size.height == 0 {
            return Ok(()); // minimised: nothing to draw into
        }
        let extent = self.swapchain.as_ref().map(|s| s.extent);
        if extent != Some(vk::Extent2D { width: size.width, height: size.height }) {
            self.swapchain = None;
            self.swapchain = Some(Swapchain::new(self.renderer.device(), &self.surface, size.width, size.height)?);
        }
        let started = Instant::now();
        let counted = self.options_frames.is_some_and(|n| self.pace.presented + 1 >= n);
        let timed_out = self.deadline.is_some_and(|deadline| Instant::now() >= deadline);
        let last = counted || timed_out;
        let screenshot =
            self.screenshot_next.take().or_else(|| if last { self.screenshot_at_exit.clone() } else { None });
        if !self.present(screenshot.as_deref())? {
            return Ok(()); // the swapchain went out of date: made anew on the next frame
        }
        self.pace.presented_one(self.shown == frames::Shown::Moving);
        if self.pace.presented == 1 {
            // With -v: from here on an edit is seen (the hot-reload test waits for this line).
            let shaders = self.watched.shaders.as_ref().map(|s| format!(" and the shaders of {}", s.display()));
            log::info!(
                "showing {}: edits to it{} are reloaded",
                self.scene_path.display(),
                shaders.unwrap_or_default()
            );
        }
        let frame_ms = started.elapsed().as_secs_f64() * 1e3;
        self.window.set_title(&format!("{}{}", self.controls.title(&self.scene, frame_ms), self.shown.describe()));
        // A counted run ends on a still frame, its screenshot the exact image: past its count, the motion
        // frames go on (each saved over the last) until the scene has settled.
        if timed_out || (counted && self.shown != frames::Shown::Moving) {
            event_loop.exit();
        }
        Ok(())
    }

    /// The scene with the selected object's lobe added, when B asks for it (None: the scene alone). The lobe
    /// is made again only when the scene changed (its mesh is uploaded once while it stays).
    fn scene_with_lobe(&mut self) -> Result<Option<Scene>> {
        if !self.controls.show_lobe {
            return Ok(None);
        }
        let selected = self.controls.selected;
        let current = self.lobe.as_ref().is_some_and(|((scene, index), _)| *index == selected && *scene == self.scene);
        if !current {
            let objects = lobe_on_object(&mut self.renderer, &self.scene, selected)?.unwrap_or_default();
            self.lobe = Some(((self.scene.clone(), selected), objects));
        }
        let mut scene = self.scene.clone();
        scene.objects.extend(self.lobe.as_ref().map(|(_, objects)| objects.clone()).unwrap_or_default());
        Ok(Some(scene))
    }

    /// Renders the scene at the swapchain's size and presents it, saving it to `screenshot` if given.
    /// Returns false when the swapchain was out of date (it is dropped, to be made anew).
    fn present(&mut self, screenshot: Option<&Path>) -> Result<bool> {
        let Some(extent) = self.swapchain.as_ref().map(|s| s.extent) else { return Ok(false) };
        let (width, height) = (extent.width, extent.height);
        self.scene.image.width = width;
        self.scene.image.height = height;
        let shown = self.scene_with_lobe()?;
        let Some(swapchain) = self.swapchain.as_ref() else { return Ok(false) };
        let device = self.renderer.device().clone();
        let size = u64::from(width) * u64::from(height) * 4;
        let upload = match self.upload.take().filter(|b| b.desc.size == size) {
            Some(upload) => upload,
            None => device.create_buffer(
                BufferDesc { size, usage: vk::BufferUsageFlags::TRANSFER_SRC, location: MemoryLocation::CpuToGpu },
                "frame upload",
            )?,
        };
        let upload = self.upload.insert(upload);
        let bgra = swapchain.format == vk::Format::B8G8R8A8_UNORM;
        let order = if bgra { TexelOrder::Bgra } else { TexelOrder::Rgba };
        let frame = shown.as_ref().unwrap_or(&self.scene);
        match frames::render_frame(&mut self.renderer, &mut self.frames, frame, order, upload.bytes_mut()?) {
            Ok(shown) => {
                self.shown = shown;
                self.last_good = self.scene.clone();
            }
            Err(e @ (Error::Scene { .. } | Error::Mesh { .. })) => {
                log::error!("{e} (keeping the last good scene)");
                self.scene = self.last_good.clone();
                return Ok(true);
            }
            Err(e) => return Err(e),
        }
        let staging = &*upload;
        let readback = match screenshot {
            Some(path) if !swapchain.readable => {
                return Err(Error::Output {
                    path: path.to_path_buf(),
                    message: "this window's swapchain images cannot be read back for a screenshot".into(),
                })
            }
            Some(_) => Some(device.create_buffer(
                BufferDesc { size, usage: vk::BufferUsageFlags::TRANSFER_DST, location: MemoryLocation::GpuToCpu },
                "screenshot",
            )?),
            None => None,
        };

        // The presentation engine has the device's timeout to hand an image over, as every wait does.
        let timeout = u64::try_from(device.timeout().as_nanos()).unwrap_or(u64::MAX);
        // SAFETY: the swapchain and its semaphore are alive.
        let acquired = unsafe {
            swapchain.loader.acquire_next_image(swapchain.raw, timeout, swapchain.acquired, vk::Fence::null())
        };
        let index = match acquired {
            Ok((index, _suboptimal)) => index as usize,
            Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => {
                self.swapchain = None;
                return Ok(false);
            }
            Err(vk::Result::TIMEOUT | vk::Result::NOT_READY) => {
                return Err(crate::error::Error::Timeout {
                    seconds: device.timeout().as_secs_f64(),
                    models: Vec::new(),
                });
            }
            Err(e) => return Err(e.into()),
        };
        let image = swapchain.images[index];
        let region = whole_image_copy(width, height);
        let transition = |old, new, src: Access, dst: Access| {
            layout_transition(image, layer_range(vk::ImageAspectFlags::COLOR, 0, 1), old, new, src, dst)
        };
        let copy_write = (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_WRITE);
        let copy_read = (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_READ);
        let present = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
        device.submit_and_wait_with(
            &[(swapchain.acquired, vk::PipelineStageFlags2::COPY)],
            &[swapchain.rendered[index]],
            |cmd| {
                let record = |barrier: vk::ImageMemoryBarrier2| {
                    let barriers = [barrier];
                    // SAFETY: the command buffer is recording; the image is acquired.
                    unsafe {
                        device.raw.cmd_pipeline_barrier2(
                            cmd,
                            &vk::DependencyInfo::default().image_memory_barriers(&barriers),
                        );
                    }
                };
                record(transition(
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                    (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::NONE),
                    copy_write,
                ));
                // SAFETY: as above; the staging buffer outlives the submission.
                unsafe {
                    device.raw.cmd_copy_buffer_to_image(
                        cmd,
                        staging.raw,
                        image,
                        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
                        &[region],
                    );
                }
                let mut layout = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
                if let Some(readback) = &readback {
                    // Read the swapchain image itself: the screenshot is what is presented.
                    record(transition(layout, vk::ImageLayout::TRANSFER_SRC_OPTIMAL, copy_write, copy_read));
                    layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
                    // SAFETY: as above.
                    unsafe {
                        device.raw.cmd_copy_image_to_buffer(cmd, image, layout, readback.raw, &[region]);
                    }
                    readback.record_host_read_barrier(
                        cmd,
                        vk::PipelineStageFlags2::COPY,
                        vk::AccessFlags2::TRANSFER_WRITE,
                    );
                }
                record(transition(layout, vk::ImageLayout::PRESENT_SRC_KHR, copy_write, present));
                Ok(())
            },
        )?;
        let waits = [swapchain.rendered[index]];
        let swapchains = [swapchain.raw];
        let indices = [index as u32];
        let info =
            vk::PresentInfoKHR::default().wait_semaphores(&waits).swapchains(&swapchains).image_indices(&indices);
        // SAFETY: the image was acquired and its copy submitted, signalling the semaphore presentation waits for.
        match unsafe { swapchain.loader.queue_present(device.queue, &info) } {
            Ok(false) => {}
            Ok(true) | Err(vk::Result::ERROR_OUT_OF_DATE_KHR) => self.swapchain = None,
            Err(e) => return Err(e.into()),
        }
        if let (Some(path), Some(readback)) = (screenshot, &readback) {
            save_screenshot(readback.bytes()?, width, height, bgra, path)?;
        }
        Ok(true)
    }
}

/// Writes a swapchain image's bytes (BGRA or RGBA) as an RGB PNG.
fn save_screenshot(bytes: &[u8], width: u32, height: u32, bgra: bool, path: &Path) -> Result<()> {
    let rgb: Vec<u8> =
        bytes.chunks_exact(4).flat_map(|t| if bgra { [t[2], t[1], t[0]] } else { [t[0], t[1], t[2]] }).collect();
    let image = image::RgbImage::from_raw(width, height, rgb).ok_or_else(|| Error::Output {
        path: path.to_path_buf(),
        message: "the screenshot has the wrong size".into(),
    })?;
    crate::pictures::output::write_png(&image, path)?;
    log::info!("saved {}", path.display());
    Ok(())
}

/// The scene file's and the shaders' modification times, to notice edits.
struct Watched {
    scene: PathBuf,
    scene_stamp: Option<SystemTime>,
    /// The scene's .brdf files, each with its last modification time: an edit reloads the scene.
    brdfs: Vec<(PathBuf, Option<SystemTime>)>,
    shaders: Option<PathBuf>,
    shaders_stamp: Option<SystemTime>,
    last_look: Instant,
}

impl Watched {
    fn new(scene: &Path, shaders: Option<PathBuf>) -> Self {
        let scene_stamp = modified(scene);
        let shaders_stamp = shaders.as_deref().and_then(newest_in);
        let last_look = Instant::now();
        Self { scene: scene.to_path_buf(), scene_stamp, brdfs: Vec::new(), shaders, shaders_stamp, last_look }
    }

    /// Watches the .brdf files of `scene` (those of the scene as last loaded, good or not, stay watched).
    fn watch_brdfs(&mut self, scene: &Scene) {
        for brdf in scene.materials.values() {
            if let crate::brdf::Brdf::Analytic(material) = brdf {
                let path = &material.model().path;
                if !self.brdfs.iter().any(|(p, _)| p == path) {
                    self.brdfs.push((path.clone(), modified(path)));
                }
            }
        }
    }

    /// Whether the scene changed, and the shaders' folder if a shader did, since the last look.
    fn poll(&mut self) -> (bool, Option<PathBuf>) {
        if self.last_look.elapsed() < RELOAD_INTERVAL {
            return (false, None);
        }
        self.last_look = Instant::now();
        let scene_stamp = modified(&self.scene);
        let mut scene_changed = scene_stamp != self.scene_stamp;
        self.scene_stamp = scene_stamp;
        for (path, stamp) in &mut self.brdfs {
            let now = modified(path);
            scene_changed |= now != *stamp;
            *stamp = now;
        }
        let shaders_stamp = self.shaders.as_deref().and_then(newest_in);
        let shaders_changed = shaders_stamp != self.shaders_stamp;
        self.shaders_stamp = shaders_stamp;
        (scene_changed, if shaders_changed { self.shaders.clone() } else { None })
    }
}

fn modified(path: &Path) -> Option<SystemTime> {
    std::fs::metadata(path).and_then(|m| m.modified()).ok()
}

/// The newest modification time of the files under a folder.
fn newest_in(folder: &Path) -> Option<SystemTime> {
    let mut newest = None;
    for entry in std::fs::read_dir(folder).ok()?.flatten() {
        let path = entry.path();
        let stamp = if path.is_dir() { newest_in(&path) } else { modified(&path) };
        newest = newest.max(stamp);
    }
    newest
}
