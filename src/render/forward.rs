//! The forward pass: shading every object against every light, with a pipeline per kind of object (meshes,
//! exact spheres), BRDF, shadow filter and sample count. An analytic model's fragment shaders are compiled
//! at run time with its GLSL, once per model and variant, when a pipeline first needs them.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use super::analytic::{analytic_shader, AnalyticShader};
use super::gpu_types::{brdf_id, diffuse_id};
use super::passes::{
    begin_rendering, build_pipeline, set_viewport_and_scissor, CompiledShader, DepthStart, PassTargets, DEPTH_FORMAT,
};
use crate::error::Result;
use crate::mesh::PlacedMesh;
use crate::scene::{EnvironmentMode, Object, Scene, ShadowFilter, View};
use crate::vulkan::{Device, GraphicsPipelineDesc, Pipeline, PipelineLayout, ShaderCompiler};

/// The HDR colour format: 32-bit float, so that the course's truncation to 8 bits sees exact values.
pub const COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// The forward pass's compiled shaders, and its pipelines, each built on first use.
pub struct ForwardPass {
    meshes: Stages,
    spheres: Stages,
    background: Stages,
    /// Each analytic model's fragment shaders compiled so far, by model, kind of object and variant.
    analytic: HashMap<(AnalyticShader, bool, usize), CompiledShader>,
    layout: Arc<PipelineLayout>,
    /// Each with the number of the last call of [`ForwardPass::pipelines`] that asked for it.
    pipelines: HashMap<PipelineKey, (Pipeline, u64)>,
    /// The calls of [`ForwardPass::pipelines`] so far.
    calls: u64,
    /// How many pipelines are kept at most.
    pub kept_at_most: usize,
    device: Arc<Device>,
}

/// A pass's vertex shader and its fragment shader's variants, with or without the environment's light and
/// the term views (the entry file's WITH_ENVIRONMENT and TERM_VIEWS: common/shading.glsl and
/// common/views.glsl say why apart), indexed by [`Stages::variant`].
struct Stages {
    vertex: CompiledShader,
    fragments: Vec<CompiledShader>,
}

/// The fragment variants a pass's entry file names, in the order of [`Stages::variant`].
const FRAGMENT_VARIANTS: [&str; 4] = ["", "+WITH_ENVIRONMENT", "+TERM_VIEWS", "+WITH_ENVIRONMENT+TERM_VIEWS"];

impl Stages {
    fn new(
        compiler: &ShaderCompiler,
        (vertex, fragment): (&'static str, &'static str),
        variants: usize,
    ) -> Result<Self> {
        Ok(Self {
            vertex: CompiledShader::new(compiler, vertex)?,
            fragments: FRAGMENT_VARIANTS[..variants]
                .iter()
                .map(|variant| CompiledShader::new(compiler, format!("{fragment}{variant}")))
                .collect::<Result<_>>()?,
        })
    }

    /// The index of the fragment variant with the environment's light or not, the term views or not.
    fn variant(environment: bool, term_views: bool) -> usize {
        usize::from(environment) + 2 * usize::from(term_views)
    }

    /// The vertex shader and one variant of the fragment shader.
    fn pick(&self, variant: usize) -> (&CompiledShader, &CompiledShader) {
        (&self.vertex, &self.fragments[variant])
    }
}

/// The most forward pipelines a renderer keeps by default (a figure needs a few; every combination of models, views,
/// sample counts and light counts would be thousands).
pub const MAX_PIPELINES_KEPT: usize = 256;

/// What a forward pipeline is built for.
#[derive(Clone, Debug, PartialEq, Eq, Hash)]
pub enum PipelineKey {
    /// The background of an image of `samples` (no vertex input, every depth test passing), showing the
    /// environment or not.
    Background { samples: vk::SampleCountFlags, environment: bool },
    /// Objects of one kind (meshes, or exact spheres) and the values of the fragment shader's specialization
    /// constants, in the order of their `constant_id`s: the BRDF (brdf.glsl's `BRDF_SPECIALIZED`), the shadow
    /// filter and the number of lights (shading.glsl's `SHADOW_FILTER` and `LIGHT_COUNT`), Cook-Torrance's
    /// diffuse lobe (brdf.glsl's `DIFFUSE_SPECIALIZED`), what the image shows (views.glsl's `VIEW`) and how
    /// the environment is integrated (environment.glsl's `ENVIRONMENT`), the samples per pixel
    /// (forward_sphere.frag's `SAMPLES`); and for an analytic model, the model its fragment shader is compiled
    /// with.
    Objects { samples: vk::SampleCountFlags, exact_sphere: bool, constants: [u32; 7], analytic: Option<AnalyticShader> },
}

impl PipelineKey {
    /// The pipeline that draws `placed` with `object`'s BRDF into the targets of `scene`'s image.
    pub fn for_object(scene: &Scene, object: &Object, placed: &PlacedMesh) -> Self {
        let shadow_filter = match scene.image.shadow_filter {
            ShadowFilter::Hard => 0,
            ShadowFilter::Pcf => 1,
        };
        Self::Objects {
            samples: vk::SampleCountFlags::from_raw(scene.image.samples),
            exact_sphere: placed.exact_sphere,
            constants: [
                brdf_id(&object.brdf),
                shadow_filter,
                scene.lights.len() as u32,
                diffuse_id(&object.brdf),
                scene.image.view.id(),
                environment_constant(scene),
                scene.image.samples,
            ],
            analytic: analytic_shader(&object.brdf),
        }
    }

    /// The background of `scene`'s image: the environment where it is visible and the image shows the
    /// radiance (a term view's background is black).
    pub fn background(scene: &Scene) -> Self {
        Self::Background {
            samples: vk::SampleCountFlags::from_raw(scene.image.samples),
            environment: scene.environment.as_ref().is_some_and(|e| e.visible) && scene.image.view == View::Radiance,
        }
    }
}

/// environment.glsl's `ENVIRONMENT` for `scene`: none, exact or fast.
fn environment_constant(scene: &Scene) -> u32 {
    match scene.environment_light() {
        None => 0,
        Some(EnvironmentMode::Exact) => 1,
        Some(EnvironmentMode::Fast) => 2,
    }
}

impl ForwardPass {
    /// Compiles the forward shaders.
    ///
    /// # Errors
    /// `Error::Shader` if a shader does not compile.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler, layout: &Arc<PipelineLayout>) -> Result<Self> {
        Ok(Self {
            meshes: Stages::new(compiler, ("forward.vert", "forward.frag"), 4)?,
            spheres: Stages::new(compiler, ("forward_sphere.vert", "forward_sphere.frag"), 4)?,
            // The background shows no term: only the environment's variant.
            background: Stages::new(compiler, ("background.vert", "background.frag"), 2)?,
            analytic: HashMap::new(),
            layout: layout.clone(),
            pipelines: HashMap::new(),
            calls: 0,
            kept_at_most: MAX_PIPELINES_KEPT,
            device: device.clone(),
        })
    }

    /// The pipelines for `keys`, in order: those not built yet are built first, side by side on the cores
    /// (lavapipe translates and optimizes a pipeline's shaders on the thread that asks, about 10 ms each on
    /// these machines, and `figures` asks for ten at once: 40 ms less on two cores), after the analytic
    /// models' fragment shaders they need are compiled by `compiler`.
    ///
    /// # Errors
    /// `Error::Shader` if an analytic model's shader does not compile, `Error::Vulkan` if the driver refuses
    /// a pipeline.
    pub fn pipelines(&mut self, compiler: &ShaderCompiler, keys: &[PipelineKey]) -> Result<Vec<vk::Pipeline>> {
        let mut missing: Vec<PipelineKey> = Vec::new();
        for key in keys {
            if !self.pipelines.contains_key(key) && !missing.contains(key) {
                missing.push(key.clone());
            }
        }
        for key in &missing {
            if let PipelineKey::Objects { exact_sphere, constants, analytic: Some(model), .. } = key {
                let variant = Stages::variant(constants[5] != 0, constants[4] != View::Radiance.id());
                if let std::collections::hash_map::Entry::Vacant(slot) =
                    self.analytic.entry((model.clone(), *exact_sphere, variant))
                {
                    let entry = if *exact_sphere { "forward_sphere.frag" } else { "forward.frag" };
                    let name = format!("{entry}{}", FRAGMENT_VARIANTS[variant]);
                    let spirv = compiler.compile_analytic(&name, model.0.glsl())?;
                    slot.insert(CompiledShader { name: format!("{name} of {}", model.0.name()), spirv });
                }
            }
        }
        let built = crate::parallel::rows(missing.len() as u32, |i| vec![self.build(&missing[i as usize])]);
        self.calls += 1;
        for (key, pipeline) in missing.into_iter().zip(built) {
            let pipeline = pipeline?;
            log::debug!("built the forward pipeline for {key:?}");
            self.pipelines.insert(key, (pipeline, self.calls));
        }
        let raw = keys
            .iter()
            .map(|key| {
                let (pipeline, used) = self.pipelines.get_mut(key).expect("built above");
                *used = self.calls;
                pipeline.raw
            })
            .collect();
        self.forget_least_recently_used();
        Ok(raw)
    }

    /// How many pipelines are kept now.
    pub fn kept(&self) -> usize {
        self.pipelines.len()
    }

    /// Destroys the pipelines asked for least recently while more than `kept_at_most` are kept
    /// (never those of this call: every earlier render has finished with its pipelines, as each waits for
    /// its work). A server whose clients ask for every view, sample count and model in turn keeps a bounded
    /// set.
    fn forget_least_recently_used(&mut self) {
        while self.pipelines.len() > self.kept_at_most {
            let oldest =
                self.pipelines.iter().filter(|(_, (_, used))| *used != self.calls).min_by_key(|(_, (_, used))| *used);
            let Some(key) = oldest.map(|(key, _)| key.clone()) else { return };
            self.pipelines.remove(&key);
        }
    }

    fn build(&self, key: &PipelineKey) -> Result<Pipeline> {
        match key {
            PipelineKey::Objects { samples, exact_sphere, constants, analytic } => {
                let stages = if *exact_sphere { &self.spheres } else { &self.meshes };
                let variant = Stages::variant(constants[5] != 0, constants[4] != View::Radiance.id());
                let (vertex, fragment) = stages.pick(variant);
                let fragment = match analytic {
                    Some(model) => &self.analytic[&(model.clone(), *exact_sphere, variant)],
                    None => fragment,
                };
                build_pipeline(&self.device, &self.layout, (vertex, fragment), (COLOR_FORMAT, *samples), constants)
            }
            &PipelineKey::Background { samples, environment } => {
                let (vertex, fragment) = self.background.pick(Stages::variant(environment, false));
                let vertex_module = self.device.create_shader_module(&vertex.spirv, &vertex.name)?;
                let fragment_module = self.device.create_shader_module(&fragment.spirv, &fragment.name)?;
                let desc = GraphicsPipelineDesc {
                    vertex: &vertex_module,
                    fragment: &fragment_module,
                    vertex_bindings: &[],
                    vertex_attributes: &[],
                    color_formats: &[COLOR_FORMAT],
                    depth_format: DEPTH_FORMAT,
                    depth_compare: vk::CompareOp::ALWAYS,
                    samples,
                    layout: &self.layout,
                    fragment_constants: &[0, 0, 0, 0, 0, u32::from(environment)],
                };
                self.device.create_graphics_pipeline(&desc, &format!("background x{}", samples.as_raw()))
            }
        }
    }
}

/// Draws the background (its pipeline that of [`PipelineKey::Background`]) over the whole target:
/// the first draw of the forward pass.
pub fn draw_background(device: &Device, cmd: vk::CommandBuffer, pipeline: vk::Pipeline, targets: &PassTargets) {
    // SAFETY: the command buffer is recording inside the forward pass; the pipeline outlives the submission.
    unsafe {
        set_viewport_and_scissor(device, cmd, targets);
        device.raw.cmd_set_cull_mode(cmd, vk::CullModeFlags::NONE);
        device.raw.cmd_set_front_face(cmd, vk::FrontFace::COUNTER_CLOCKWISE);
        device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
        device.raw.cmd_draw(cmd, 3, 1, 0, 0);
    }
}

/// What writes the samples no object covers.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Background {
    /// The background's triangle ([`draw_background`]), drawn first over every sample, colour and depth:
    /// what clearing them would do, cheaper (see background.vert).
    Drawn,
    /// The resolve pass, where the depth is still [`UNCOVERED_DEPTH`]: the depth is cleared to it before
    /// the pass (by the transfer: lavapipe's clear as the pass begins cost the orbiting bunny 3 ms a frame)
    /// and kept, and the colour of those samples never written. On Debian 13's lavapipe the background's
    /// triangle was 1.3 ms of Figure 1's 7.2 ms image; the resolve reads each sample's depth for a fraction
    /// of that. A constant colour only, and a device whose depth may be cleared below 0
    /// (VK_EXT_depth_range_unrestricted).
    Resolved,
}

/// The depth the forward pass's samples keep where no object is drawn with [`Background::Resolved`]: below
/// every depth an object can have (reverse-Z: 1 at the near plane, 0 at infinity).
pub const UNCOVERED_DEPTH: f32 = -1.0;

/// Begins dynamic rendering into the colour target, whose samples are kept for the resolve pass
/// (`resolve.rs`, which averages them as the course averages its pixel samples), and the depth target:
/// neither loaded nor cleared when the background's triangle is drawn first (it writes every sample), else
/// loaded (cleared to [`UNCOVERED_DEPTH`] before) and kept for the resolve.
pub fn begin(device: &Device, cmd: vk::CommandBuffer, targets: &PassTargets, background: Background) {
    let color = vk::RenderingAttachmentInfo::default()
        .image_view(targets.color)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::DONT_CARE)
        .store_op(vk::AttachmentStoreOp::STORE);
    match background {
        Background::Drawn => begin_rendering(device, cmd, targets, color, DepthStart::Written, false),
        Background::Resolved => begin_rendering(device, cmd, targets, color, DepthStart::Loaded, true),
    }
}
