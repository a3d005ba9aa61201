//! The offscreen renderer: a scene in, a linear HDR image out, through Vulkan.

pub mod albedo;
mod analytic;
mod environment;
pub mod exact;
mod forward;
mod frame;
pub mod gpu_types;
pub mod interactive;
mod measured;
mod occluders;
mod passes;
mod picture;
mod probe;
mod resolve;
mod sampler;
mod scene_data;
mod shadow;
mod targets;
pub mod webgl;

use std::borrow::Cow;
use std::sync::Arc;

use ash::vk;
use glam::Vec3;

use crate::brdf::Brdf;
use crate::environment::EnvironmentMap;
use crate::error::{Error, Result};
use crate::mesh::{place_objects, PlacedMesh};
use crate::pictures::output::{encode_texels, HdrImage, TexelOrder};
use crate::scene::{EnvironmentMode, Scene};
use crate::vulkan::{Device, DeviceInfo, Instance, PipelineLayout, Sampler, ShaderCompiler, ShaderSources};
use analytic::AnalyticValues;
pub use analytic::InvalidValues;
use environment::{EnvironmentTextures, MAP_FORMAT};
use exact::{Accuracy, Passes};
use forward::{Background, ForwardPass, PipelineKey, COLOR_FORMAT};
use frame::background_of;
use gpu_types::GpuAlbedoEntry;
use gpu_types::MaterialData;
use measured::MeasuredTables;
use passes::MeshUploads;
use passes::DEPTH_FORMAT;
pub use picture::Picture;
use probe::{read_vec3s, ProbeContext, ProbePass};
pub use probe::{AlbedoJob, ProbeCase};
use resolve::{Readout, ResolvePass};
pub use sampler::{BrdfSample, SamplerDensity};
use scene_data::SceneData;
pub use shadow::cube_face_views;
use shadow::{ShadowCubes, ShadowPass, DISTANCE_FORMAT};
use targets::{Targets, BYTES_PER_PIXEL};

/// The near plane's distance: with reverse-Z float depth the precision does not depend on it.
pub const NEAR_PLANE: f32 = 1e-3;

/// How to open the renderer.
#[derive(Clone, Debug, Default)]
pub struct RendererOptions {
    /// A device index or part of its name (see `vk-render devices`); `None` picks the best.
    pub device: Option<String>,
    /// Turn the Khronos validation layer on; every render then fails on any message.
    pub validate: bool,
    /// The GLSL to compile; the sources embedded at build time by default.
    pub shaders: ShaderSources,
    /// Extra instance extensions (a window surface's, for the preview).
    pub instance_extensions: Vec<&'static std::ffi::CStr>,
    /// Extra device extensions (the swapchain's, for the preview).
    pub device_extensions: Vec<&'static std::ffi::CStr>,
    /// How long a wait for the device may last before its work is given up (`--timeout`):
    /// [`DEFAULT_TIMEOUT`] when `None`.
    pub timeout: Option<std::time::Duration>,
}

pub use crate::vulkan::DEFAULT_TIMEOUT;

/// A Vulkan device with the forward pass's shaders compiled and pipelines built once, reused for every image.
pub struct Renderer {
    /// The one descriptor set layout and push constants of the shadow and forward passes.
    layout: Arc<PipelineLayout>,
    shadow: ShadowPass,
    shadow_sampler: Sampler,
    forward: ForwardPass,
    resolve: ResolvePass,
    /// The sample counts at which the resolve writes a constant background (resolve.rs).
    background_counts: vk::SampleCountFlags,
    /// Built on first use: only the BRDF tests need it.
    probe: Option<ProbePass>,
    compiler: ShaderCompiler,
    /// The passes of the shader sets used before, the most recent last.
    kept_shaders: Vec<ShaderSet>,
    // Kept from image to image while they hold, by lifetime: the meshes per scene geometry, the shadow
    // cubes per lighting, the targets per image size; the scene data is rewritten every image.
    meshes: MeshUploads,
    shadow_cubes: Option<ShadowCubes>,
    targets: Option<Targets>,
    scene_data: Option<SceneData>,
    /// The environment of the last scene that had one (per scene), or black placeholders.
    environment: EnvironmentTextures,
    environment_sampler: Sampler,
    /// The measured materials' tables of the last work that had any.
    measured: MeasuredTables,
    /// The analytic materials' values of the last work, and its reports of invalid values.
    analytic: AnalyticValues,
    /// What the analytic models gave that no BRDF may, over the work since it was last taken.
    invalid: Option<InvalidValues>,
    /// The fast mode's albedo tables, by material (they depend on the material alone), the newest
    /// [`ALBEDO_TABLES_KEPT`].
    albedo_tables: Vec<(Brdf, Vec<GpuAlbedoEntry>)>,
    /// How exact the last image's environment light was, when it was integrated in the exact mode.
    accuracy: Option<Accuracy>,
    device: Arc<Device>,
}

/// Entries of an albedo table: cos(theta_o) = (k + 1/2) / ALBEDO_TABLE_SIZE for entry k, read linearly
/// between (environment.glsl's `environment_albedo_at`).
pub const ALBEDO_TABLE_SIZE: usize = 32;

/// The passes of one set of shader sources.
struct ShaderSet {
    compiler: ShaderCompiler,
    shadow: ShadowPass,
    forward: ForwardPass,
    resolve: ResolvePass,
}

/// The shader sets a renderer keeps besides the one in use: one for each of `check`'s mistakes of the
/// shaders (15) and the embedded shaders, with room to spare.
pub const SHADER_SETS_KEPT: usize = 20;

/// The albedo tables kept: a material explored in an environment's fast mode makes one per value its
/// controls take.
const ALBEDO_TABLES_KEPT: usize = 64;

/// The error bound asked of each entry: far below what the fast mode's split sum itself approximates.
const ALBEDO_TABLE_TOLERANCE: f64 = 1e-4;

impl Renderer {
    /// Opens Vulkan, chooses the device and compiles the shaders.
    ///
    /// # Errors
    /// `Error::NoVulkan` with installation advice, `Error::Device`, `Error::Shader` or `Error::Vulkan`.
    pub fn new(options: RendererOptions) -> Result<Self> {
        let instance = Arc::new(Instance::new(options.validate, &options.instance_extensions)?);
        Self::on_instance(instance, options, None)
    }

    /// As [`Renderer::new`], on an instance already made (the preview's, which made its window's surface
    /// with it); with `present_to`, the device chosen is one whose queue can also present to that surface.
    ///
    /// # Errors
    /// As [`Renderer::new`].
    pub fn on_instance(
        instance: Arc<Instance>,
        options: RendererOptions,
        present_to: Option<(&ash::khr::surface::Instance, vk::SurfaceKHR)>,
    ) -> Result<Self> {
        let device = Device::new(instance, options.device.as_deref(), &options.device_extensions, present_to)?;
        device.set_timeout(options.timeout.unwrap_or(DEFAULT_TIMEOUT));
        device.require_format(
            COLOR_FORMAT,
            vk::FormatFeatureFlags::COLOR_ATTACHMENT | vk::FormatFeatureFlags::SAMPLED_IMAGE,
            "the forward pass's colour target",
        )?;
        device.require_format(DEPTH_FORMAT, vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT, "depth")?;
        device.require_format(
            DISTANCE_FORMAT,
            vk::FormatFeatureFlags::COLOR_ATTACHMENT | vk::FormatFeatureFlags::SAMPLED_IMAGE,
            "the shadow cubes' distances",
        )?;
        let compiler = ShaderCompiler::new(options.shaders)?;
        let layout = scene_layout(&device)?;
        let shadow = ShadowPass::new(&device, &compiler, &layout)?;
        let forward = ForwardPass::new(&device, &compiler, &layout)?;
        let resolve = ResolvePass::new(&device, &compiler)?;
        device.require_format(
            MAP_FORMAT,
            vk::FormatFeatureFlags::SAMPLED_IMAGE | vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR,
            "environment maps",
        )?;
        let shadow_sampler = device.create_nearest_sampler("shadow cubes")?;
        let environment = EnvironmentTextures::placeholder(&device)?;
        let environment_sampler = device.create_environment_sampler("environment maps")?;
        let renderer = Self {
            layout,
            shadow,
            shadow_sampler,
            forward,
            resolve,
            background_counts: resolve::background_sample_counts(&device),
            probe: None,
            compiler,
            kept_shaders: Vec::new(),
            meshes: MeshUploads::default(),
            shadow_cubes: None,
            targets: None,
            scene_data: None,
            environment,
            environment_sampler,
            measured: MeasuredTables::new(&device)?,
            analytic: AnalyticValues::new(&device)?,
            invalid: None,
            albedo_tables: Vec::new(),
            accuracy: None,
            device,
        };
        renderer.check_validation()?;
        Ok(renderer)
    }

    /// Keeps at most `count` forward pipelines (at least 1; 256 by default), destroying those asked for least
    /// recently: a server that renders whatever its clients ask keeps its memory bounded.
    pub fn keep_pipelines(&mut self, count: usize) {
        self.forward.kept_at_most = count.max(1);
    }

    /// How many forward pipelines are kept now.
    pub fn pipelines_kept(&self) -> usize {
        self.forward.kept()
    }

    /// The device, for what shares it (the preview's swapchain).
    pub fn device(&self) -> &Arc<Device> {
        &self.device
    }

    /// Draws with the passes of `shaders` from now on: compiled from them, or taken back from the last
    /// [`SHADER_SETS_KEPT`] sets used before (with the pipelines they built), so that switching between a
    /// few sets (`check`'s mistakes, render after render) compiles each once. On any error the passes in use
    /// are kept.
    ///
    /// # Errors
    /// `Error::Shader` naming the file and line, or `Error::Vulkan`.
    pub fn set_shaders(&mut self, shaders: ShaderSources) -> Result<()> {
        if *self.compiler.sources() == shaders {
            return Ok(());
        }
        let kept = self.kept_shaders.iter().position(|set| *set.compiler.sources() == shaders);
        let mut next = match kept {
            Some(index) => self.kept_shaders.remove(index),
            None => {
                let compiler = ShaderCompiler::new(shaders)?;
                let shadow = ShadowPass::new(&self.device, &compiler, &self.layout)?;
                let forward = ForwardPass::new(&self.device, &compiler, &self.layout)?;
                let resolve = ResolvePass::new(&self.device, &compiler)?;
                ShaderSet { compiler, shadow, forward, resolve }
            }
        };
        next.forward.kept_at_most = self.forward.kept_at_most;
        // Pipelines of the passes set aside may still be referenced by work in flight: renders wait for theirs.
        std::mem::swap(&mut self.compiler, &mut next.compiler);
        std::mem::swap(&mut self.shadow, &mut next.shadow);
        std::mem::swap(&mut self.forward, &mut next.forward);
        std::mem::swap(&mut self.resolve, &mut next.resolve);
        self.kept_shaders.push(next);
        if self.kept_shaders.len() > SHADER_SETS_KEPT {
            self.kept_shaders.remove(0);
        }
        self.probe = None;
        // The cubes were drawn by the old shadow shaders.
        if let Some(cubes) = &mut self.shadow_cubes {
            cubes.set_drawn(None);
        }
        self.check_validation()
    }

    /// The device in use.
    pub fn device_info(&self) -> &DeviceInfo {
        &self.device.info
    }

    /// The MSAA sample counts this device can render the forward pass with.
    pub fn supported_sample_counts(&self) -> Vec<u32> {
        let limits = &self.device.limits;
        // The resolve pass samples the colour target.
        let counts = limits.framebuffer_color_sample_counts
            & limits.framebuffer_depth_sample_counts
            & limits.sampled_image_color_sample_counts;
        // SAFETY: a plain query on a live physical device.
        let format_counts = unsafe {
            self.device.instance.raw.get_physical_device_image_format_properties(
                self.device.physical,
                COLOR_FORMAT,
                vk::ImageType::TYPE_2D,
                vk::ImageTiling::OPTIMAL,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                vk::ImageCreateFlags::empty(),
            )
        }
        .map_or(vk::SampleCountFlags::TYPE_1, |p| p.sample_counts);
        (0..7).map(|bit| 1u32 << bit).filter(|n| (counts & format_counts).as_raw() & n != 0).collect()
    }

    /// The largest image width and height this device renders.
    pub fn max_image_size(&self) -> u32 {
        let limits = &self.device.limits;
        limits.max_image_dimension2_d.min(limits.max_framebuffer_width).min(limits.max_framebuffer_height)
    }

    /// Checks the scene's `[image]` against the device: size and sample count.
    ///
    /// # Errors
    /// `Error::Scene` naming the scene file, the key and the value.
    pub fn check_image_settings(&self, scene: &Scene) -> Result<()> {
        let error = |message: String| Error::Scene { file: scene.source.clone(), message };
        let device = format!("device {} ({})", self.device.info.index, self.device.info.name);
        let max = self.max_image_size();
        for (key, value) in [("width", scene.image.width), ("height", scene.image.height)] {
            if value > max {
                return Err(error(format!("image.{key} = {value}: above the limit of {max} pixels of {device}")));
            }
        }
        let max_cube = self.device.limits.max_image_dimension_cube;
        if scene.image.shadow_map_size > max_cube {
            return Err(error(format!(
                "image.shadow_map_size = {}: above the limit of {max_cube} texels of {device}",
                scene.image.shadow_map_size
            )));
        }
        let supported = self.supported_sample_counts();
        if !supported.contains(&scene.image.samples) {
            let list: Vec<_> = supported.iter().map(u32::to_string).collect();
            return Err(error(format!(
                "image.samples = {}: not supported by {device} (it supports {})",
                scene.image.samples,
                list.join(", ")
            )));
        }
        Ok(())
    }

    /// Renders the scene to a linear HDR image (the resolved average of the MSAA samples).
    ///
    /// # Errors
    /// `Error::Scene` for settings the device cannot honour, `Error::Mesh` for an unloadable OBJ,
    /// `Error::Vulkan`/`Error::Allocation` from the device, `Error::Validation` if the layer complained.
    pub fn render(&mut self, scene: &Scene) -> Result<HdrImage> {
        let bytes = self.draw_and_read_back(scene, Readout::Radiance)?;
        let (width, height) = (scene.image.width, scene.image.height);
        Ok(HdrImage { width, height, pixels: read_vec3s(&bytes, BYTES_PER_PIXEL as usize) })
    }

    /// Renders the scene and writes it after the whole output transform into `texels`, laid out as `order`
    /// says: what [`HdrImage::to_rgb8`] of [`Renderer::render`]'s image holds, byte for byte, without the
    /// image in between (the preview's frames, PNGs).
    ///
    /// # Errors
    /// As [`Renderer::render`]; `Error::Vulkan(ERROR_MEMORY_MAP_FAILED)` when `texels` has the wrong size.
    pub fn render_texels(&mut self, scene: &Scene, order: TexelOrder, texels: &mut [u8]) -> Result<()> {
        let pixels = scene.image.width as usize * scene.image.height as usize;
        if texels.len() != pixels * order.bytes() {
            return Err(Error::Vulkan(vk::Result::ERROR_MEMORY_MAP_FAILED));
        }
        // The course's output transform is computed by the resolve pass, to the bit (see resolve.comp).
        let readout = Readout::levels_of(scene, order);
        let bytes = self.draw_and_read_back(scene, readout.unwrap_or(Readout::Radiance))?;
        let Some(levels) = readout else {
            encode_texels(&bytes, &scene.image, order, texels);
            return Ok(());
        };
        let (width, row_bytes) = (scene.image.width as usize, levels.row_bytes(scene.image.width));
        for (row, texel_row) in bytes.chunks_exact(row_bytes).zip(texels.chunks_exact_mut(width * order.bytes())) {
            match order {
                TexelOrder::Rgb => {
                    for (texel, level) in texel_row.chunks_exact_mut(3).zip(row.chunks_exact(4)) {
                        texel.copy_from_slice(&level[..3]);
                    }
                }
                TexelOrder::Rgba | TexelOrder::Bgra => texel_row.copy_from_slice(&row[..4 * width]),
            }
        }
        Ok(())
    }

    /// Renders the scene to 8-bit RGB after the whole output transform (a PNG's pixels): what
    /// [`HdrImage::to_rgb8`] of [`Renderer::render`]'s image holds.
    ///
    /// # Errors
    /// As [`Renderer::render`].
    pub fn render_rgb8(&mut self, scene: &Scene) -> Result<image::RgbImage> {
        let (width, height) = (scene.image.width, scene.image.height);
        let mut pixels = vec![0; width as usize * height as usize * 3];
        self.render_texels(scene, TexelOrder::Rgb, &mut pixels)?;
        image::RgbImage::from_raw(width, height, pixels).ok_or(Error::Vulkan(vk::Result::ERROR_MEMORY_MAP_FAILED))
    }

    /// Checks the scene against the device, draws it and returns the read-back buffer's bytes as `readout`
    /// says, rows from the top. An environment in the exact mode is integrated pass after pass until it is
    /// as exact as [`exact::TARGET_LEVELS`] says ([`Renderer::accuracy`] says how exact it came out): its
    /// passes are read back as radiance.
    fn draw_and_read_back(&mut self, scene: &Scene, readout: Readout) -> Result<Cow<'_, [u8]>> {
        self.check_image_settings(scene)?;
        let placed = place_objects(scene)?;
        self.accuracy = None;
        if scene.environment_light() == Some(EnvironmentMode::Exact) {
            let mut passes = Passes::new(scene.image.width, scene.image.height);
            while !passes.done(&scene.image) {
                crate::interrupt::check()?;
                self.add_pass(scene, &placed, &mut passes)?;
            }
            self.accuracy = Some(passes.accuracy(&scene.image));
            return Ok(Cow::Owned(passes.mean_bytes()));
        }
        self.draw(scene, &placed, 0, readout)?;
        self.check_validation()?;
        let length = scene.image.height as usize * readout.row_bytes(scene.image.width);
        match &self.targets {
            Some(targets) => Ok(Cow::Borrowed(&targets.readback.bytes()?[..length])),
            None => Err(Error::Vulkan(vk::Result::ERROR_MEMORY_MAP_FAILED)),
        }
    }

    /// How exact the last image's environment light was, if it was integrated in the exact mode.
    pub fn accuracy(&self) -> Option<Accuracy> {
        self.accuracy
    }

    /// Draws one more pass of the exact mode into `passes` (the preview refines a still image so).
    ///
    /// # Errors
    /// As [`Renderer::render`].
    pub fn refine(&mut self, scene: &Scene, passes: &mut Passes) -> Result<()> {
        self.check_image_settings(scene)?;
        let placed = place_objects(scene)?;
        self.add_pass(scene, &placed, passes)
    }

    fn add_pass(&mut self, scene: &Scene, placed: &[PlacedMesh], passes: &mut Passes) -> Result<()> {
        self.draw(scene, placed, passes.next_first_sample(), Readout::Radiance)?;
        self.check_validation()?;
        match &self.targets {
            Some(targets) => passes.add(targets.readback.bytes()?),
            None => return Err(Error::Vulkan(vk::Result::ERROR_MEMORY_MAP_FAILED)),
        }
        Ok(())
    }

    /// Loads and uploads the scene's environment where it is not the one held, prefilters it for the fast
    /// mode, and returns the objects' albedo tables (the fast mode's; one unused entry otherwise).
    fn prepare_environment(&mut self, scene: &Scene) -> Result<Vec<GpuAlbedoEntry>> {
        let Some(environment) = &scene.environment else { return Ok(vec![GpuAlbedoEntry::default()]) };
        if self.environment.source.as_ref() != Some(&environment.source) {
            let map = EnvironmentMap::of(scene, environment)?;
            let max = self.device.limits.max_image_dimension2_d;
            if map.width > max {
                let value = match &environment.source {
                    crate::scene::EnvironmentSource::Map(path) => path.display().to_string(),
                    crate::scene::EnvironmentSource::Builtin(builtin) => builtin.name().to_string(),
                };
                return Err(Error::Map {
                    scene: scene.source.clone(),
                    value,
                    message: format!(
                        "the map is {} texels wide, above the limit of {max} of device {} ({})",
                        map.width, self.device.info.index, self.device.info.name
                    ),
                });
            }
            self.environment = EnvironmentTextures::new(&self.device, Some(environment.source.clone()), map)?;
        }
        if scene.environment_light() != Some(EnvironmentMode::Fast) {
            return Ok(vec![GpuAlbedoEntry::default()]);
        }
        self.environment.prefilter(&self.device)?;
        let mut entries = Vec::with_capacity(scene.objects.len() * ALBEDO_TABLE_SIZE);
        for object in &scene.objects {
            entries.extend(self.albedo_table(&object.brdf)?);
        }
        Ok(entries)
    }

    /// The directional albedo of `brdf`'s diffuse and specular lobes at each cos(theta_o) of an albedo
    /// table (`ALBEDO_TABLE_SIZE` entries of the environment's fast mode, common/environment.glsl), by the
    /// albedo probe (`brdf_eval` itself); kept for the process. The browser's fast mode reads the same
    /// (`vk-render serve`).
    ///
    /// # Errors
    /// As the albedo probe's work: `Error::Vulkan`, `Error::Shader` for an analytic model's.
    pub fn albedo_table(&mut self, brdf: &Brdf) -> Result<Vec<GpuAlbedoEntry>> {
        if let Some((_, table)) = self.albedo_tables.iter().find(|(b, _)| b == brdf) {
            return Ok(table.clone());
        }
        let theta_o: Vec<f64> =
            (0..ALBEDO_TABLE_SIZE).map(|k| ((k as f64 + 0.5) / ALBEDO_TABLE_SIZE as f64).acos()).collect();
        let total = albedo::directional_albedos(self, brdf, &theta_o, ALBEDO_TABLE_TOLERANCE)?;
        let specular = match brdf.specular_only() {
            Some(lobe) => albedo::directional_albedos(self, &lobe, &theta_o, ALBEDO_TABLE_TOLERANCE)?,
            None => vec![albedo::Albedo { rho: [0.0; 3], error_bound: 0.0 }; ALBEDO_TABLE_SIZE],
        };
        let rgba = |rho: [f64; 3]| [rho[0] as f32, rho[1] as f32, rho[2] as f32, 0.0];
        let table: Vec<GpuAlbedoEntry> = total
            .iter()
            .zip(&specular)
            .map(|(t, s)| GpuAlbedoEntry {
                diffuse: rgba([0, 1, 2].map(|c| (t.rho[c] - s.rho[c]).max(0.0))),
                specular: rgba(s.rho),
            })
            .collect();
        if self.albedo_tables.len() >= ALBEDO_TABLES_KEPT {
            self.albedo_tables.remove(0);
        }
        self.albedo_tables.push((brdf.clone(), table.clone()));
        Ok(table)
    }

    /// A renderer for `scenes`, their meshes read and their pipelines built ([`Renderer::prepare`]): the
    /// meshes are read on another core while the device is made (each on one core: 25 ms for the bunny,
    /// 40 ms for lavapipe's start).
    ///
    /// # Errors
    /// As [`Renderer::new`] and [`Renderer::prepare`].
    pub fn for_scenes(options: RendererOptions, scenes: &[&Scene]) -> Result<Self> {
        let renderer = std::thread::scope(|scope| {
            // What fails to load fails again, and is reported, in `prepare`.
            scope.spawn(|| scenes.iter().for_each(|scene| drop(place_objects(scene))));
            Self::new(options)
        });
        let mut renderer = renderer?;
        renderer.prepare(scenes)?;
        Ok(renderer)
    }

    /// Builds every pipeline the scenes will need before they are rendered one after the other (`figures`,
    /// `sweep`), and loads their meshes: rendering builds what it lacks as it goes.
    ///
    /// # Errors
    /// `Error::Scene` for settings the device cannot honour, `Error::Mesh` for an unloadable OBJ,
    /// `Error::Vulkan` if the driver refuses a pipeline.
    pub fn prepare(&mut self, scenes: &[&Scene]) -> Result<()> {
        let mut keys = Vec::new();
        for scene in scenes {
            self.check_image_settings(scene)?;
            let placed = place_objects(scene)?;
            keys.push(PipelineKey::background(scene));
            keys.extend(scene.objects.iter().zip(&placed).map(|(object, p)| PipelineKey::for_object(scene, object, p)));
        }
        // The resolve pipelines for the PNGs' readouts, on a thread of their own beside the forward pass's.
        let (forward, resolve, background_counts) = (&mut self.forward, &mut self.resolve, self.background_counts);
        let compiler = &self.compiler;
        std::thread::scope(|scope| {
            let resolved = scope.spawn(|| {
                scenes.iter().try_for_each(|scene| {
                    let readout = Readout::levels_of(scene, TexelOrder::Rgb).unwrap_or(Readout::Radiance);
                    let background = background_of(scene, background_counts) == Background::Resolved;
                    resolve.build(scene.image.samples, readout, background)
                })
            });
            let built = forward.pipelines(compiler, &keys).map(drop);
            let resolved = resolved.join().unwrap_or_else(|panic| std::panic::resume_unwind(panic));
            built.and(resolved)
        })
    }

    /// Evaluates `brdf_eval` of the GLSL on the GPU for every case (the probe pass), as float32.
    ///
    /// # Errors
    /// `Error::Shader`, `Error::Vulkan` or `Error::Allocation`; `Error::Validation` if the layer complained.
    pub fn probe_brdfs(&mut self, cases: &[ProbeCase]) -> Result<Vec<Vec3>> {
        self.with_probe(cases.iter().map(|c| &c.brdf), |probe, context| probe.run(cases, context))
    }

    /// `brdf_eval` of every material of `brdfs` at every (wi, wo) of `pairs`, in the frame n = +z (the probe
    /// pass, as float32): material m's at pair d is element m * pairs.len() + d. The same values as
    /// [`Renderer::probe_brdfs`] of every combination, each material and direction uploaded once.
    ///
    /// # Errors
    /// As [`Renderer::probe_brdfs`].
    pub fn probe_brdf_grid(&mut self, brdfs: &[Brdf], pairs: &[(Vec3, Vec3)]) -> Result<Vec<Vec3>> {
        self.with_probe(brdfs.iter(), |probe, context| probe.run_grid(brdfs, pairs, context))
    }

    /// Integrates f_r cos(theta_i) of `brdf_eval` over every cell of the hemisphere on the GPU (the albedo
    /// probe), as float32.
    ///
    /// # Errors
    /// As [`Renderer::probe_brdfs`].
    pub fn probe_albedo_cells(
        &mut self,
        jobs: &[AlbedoJob],
        cells: &[cubature::Cell],
    ) -> Result<Vec<cubature::CellEstimate>> {
        self.with_probe(jobs.iter().map(|j| &j.brdf), |probe, context| probe.integrate(jobs, cells, context))
    }

    /// Runs `work` with the probe pass, built on first use and kept, and the data of the materials `brdfs`
    /// (their measured tables and analytic values); what the analytic models gave that no BRDF may is added
    /// to [`Renderer::take_invalid_values`]'s.
    fn with_probe<'a, T>(
        &mut self,
        brdfs: impl Iterator<Item = &'a Brdf> + Clone,
        work: impl FnOnce(&mut ProbePass, ProbeContext) -> Result<T>,
    ) -> Result<T> {
        self.measured.hold(&self.device, brdfs.clone())?;
        let brdfs_again = brdfs.clone();
        self.analytic.write(&self.device, brdfs, 1)?;
        let mut probe = match self.probe.take() {
            Some(probe) => probe,
            None => ProbePass::new(&self.device, &self.compiler)?,
        };
        let context = ProbeContext {
            data: MaterialData { measured: &self.measured, analytic: &self.analytic },
            compiler: &self.compiler,
        };
        let results = work(&mut probe, context).map_err(|e| naming_models(e, brdfs_again));
        self.probe = Some(probe);
        let results = results?;
        self.note_invalid_values()?;
        self.check_validation()?;
        Ok(results)
    }

    /// Adds what the analytic models' reports say since they were last read to [`Renderer::take_invalid_values`]'s.
    fn note_invalid_values(&mut self) -> Result<()> {
        let report = self.analytic.take_report()?;
        self.invalid = InvalidValues::merged(self.invalid.take(), report);
        Ok(())
    }

    /// Where the analytic models of the work since the last call gave NaN, an infinity or a negative value
    /// (renders count them as 0; the probe returns them as they are), if they did.
    pub fn take_invalid_values(&mut self) -> Option<InvalidValues> {
        self.invalid.take()
    }

    /// Takes the validation layer's messages so far (always empty without validation).
    pub fn take_validation_messages(&self) -> Vec<String> {
        self.device.instance.take_validation_messages()
    }

    fn check_validation(&self) -> Result<()> {
        let messages = self.take_validation_messages();
        if messages.is_empty() {
            Ok(())
        } else {
            Err(Error::Validation(messages))
        }
    }
}

/// `error`, a timeout naming the analytic models among `brdfs` (each file once), whose BRDF may never end.
fn naming_models<'a>(error: Error, brdfs: impl Iterator<Item = &'a Brdf>) -> Error {
    match error {
        Error::Timeout { seconds, .. } => {
            let mut models: Vec<std::path::PathBuf> = Vec::new();
            for brdf in brdfs {
                if let Brdf::Analytic(material) = brdf {
                    if !models.contains(&material.model().path) {
                        models.push(material.model().path.clone());
                    }
                }
            }
            Error::Timeout { seconds, models }
        }
        other => other,
    }
}

/// The descriptor set layout and push constants shared by the shadow and forward passes: the frame (0),
/// lights (1), objects (2), the shadow cubes' face matrices (3), the shadow cubes (4), the environment's map
/// (5), its prefiltered layers (6), its sampling table (7), the objects' albedo tables (8), the measured
/// tables (9), the analytic materials' values (10) and each object's report of them (11, dynamic); the push
/// constants
/// name the object drawn and, in the shadow pass, the light and the cube face.
fn scene_layout(device: &Arc<Device>) -> Result<Arc<PipelineLayout>> {
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    let binding = |index: u32, kind: vk::DescriptorType| {
        vk::DescriptorSetLayoutBinding::default()
            .binding(index)
            .descriptor_type(kind)
            .descriptor_count(1)
            .stage_flags(stages)
    };
    let bindings = [
        binding(0, vk::DescriptorType::UNIFORM_BUFFER),
        binding(1, vk::DescriptorType::STORAGE_BUFFER),
        binding(2, vk::DescriptorType::STORAGE_BUFFER),
        binding(3, vk::DescriptorType::STORAGE_BUFFER),
        binding(4, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
        binding(5, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
        binding(6, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
        binding(7, vk::DescriptorType::STORAGE_BUFFER),
        binding(8, vk::DescriptorType::STORAGE_BUFFER),
        binding(9, vk::DescriptorType::STORAGE_BUFFER),
        binding(10, vk::DescriptorType::STORAGE_BUFFER),
        binding(11, vk::DescriptorType::STORAGE_BUFFER_DYNAMIC),
    ];
    let push = [vk::PushConstantRange { stage_flags: stages, offset: 0, size: 12 }];
    device.create_pipeline_layout(&[&bindings], &push, "scene layout")
}

#[cfg(test)]
mod tests {
    /// The constants the shaders and the Rust side share by value.
    #[test]
    fn the_shaders_constants_match_the_rust_ones() {
        let environment = include_str!("../../shaders/common/environment.glsl");
        let lobes = crate::environment::prefilter::LOBE_LAYERS;
        assert!(environment.contains(&format!("const float PREFILTERED_LOBES = {lobes}.0;")));
        let size = super::ALBEDO_TABLE_SIZE;
        assert!(environment.contains(&format!("const uint ALBEDO_TABLE_SIZE = {size}u;")));
    }
}
