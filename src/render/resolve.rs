//! The resolve pass (`shaders/resolve.comp`): the forward pass's samples averaged into pixels by a compute
//! shader that writes the read-back buffer itself, as linear radiance or as the course's 8-bit levels.
//!
//! Measured on Debian 13's lavapipe, Figure 1 at 600 x 400 x 4 (each part left out in turn, medians): the
//! render pass's own resolve into a float image and that image's copy to the buffer were 2.7 ms of a
//! 10 ms image, and the host's encoding of the floats about a millisecond more, on the main thread while the
//! device stood idle. This pass takes their place: the image went from 10.4 to 8.4 ms. Its stores are most
//! of its cost (llvmpipe stores to a buffer lane by lane): one 16-byte store an invocation, four pixels' levels
//! or one pixel's radiance, saved 0.5 ms on one word a pixel. A fragment shader writing a single-sample
//! target that was then copied was slower (9.9 ms).

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use super::passes::DEPTH_FORMAT;
use super::targets::{Targets, BYTES_PER_PIXEL};
use crate::error::Result;
use crate::pictures::output::TexelOrder;
use crate::scene::{Encoding, EnvironmentMode, Scene, Tonemap};
use crate::vulkan::{
    Descriptor, DescriptorPool, Device, Pipeline, PipelineLayout, Sampler, ShaderCompiler, ShaderModule,
};

/// What the resolve writes into the read-back buffer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Readout {
    /// The mean radiance: four native-endian f32 a pixel (alpha unread).
    Radiance,
    /// The course's output transform (this exposure, clamped, x255 and truncated): four bytes a pixel, R, G,
    /// B, 255, or B, G, R, 255 with `bgra`, each row padded to a multiple of four pixels.
    Levels { exposure: f32, bgra: bool },
}

impl Readout {
    /// The levels of `order` for a scene whose output transform the resolve computes exactly (the course's:
    /// clamped, linear; the radiance seen) in one pass, or `None` where the host must encode the radiance
    /// (an environment in the exact mode is integrated over passes of radiance).
    pub fn levels_of(scene: &Scene, order: TexelOrder) -> Option<Self> {
        let settings = &scene.image;
        let course = settings.tonemap == Tonemap::Clamp && settings.encoding == Encoding::Linear;
        let one_pass = scene.environment_light() != Some(EnvironmentMode::Exact);
        (course && settings.view.is_radiance() && one_pass)
            .then_some(Self::Levels { exposure: settings.exposure, bgra: order == TexelOrder::Bgra })
    }

    /// Bytes a row of `width` pixels takes in the read-back buffer.
    pub fn row_bytes(self, width: u32) -> usize {
        match self {
            Self::Radiance => BYTES_PER_PIXEL as usize * width as usize,
            Self::Levels { .. } => TEXEL_BYTES * width.div_ceil(4) as usize,
        }
    }
}

const WORKGROUP_SIZE: u32 = 64;

/// What each invocation of resolve.comp stores (a uvec4): one pixel's radiance, or four pixels' levels.
const TEXEL_BYTES: usize = 16;

/// The resolve shader's builds (a multisampled target or a single-sample one; writing the background or
/// not), its pipelines by sample count, readout and background (built when first used), and the one set
/// that points at the targets.
pub struct ResolvePass {
    /// By `2 * background + single_sample`.
    modules: Vec<ShaderModule>,
    layout: Arc<PipelineLayout>,
    pipelines: HashMap<PipelineKey, Pipeline>,
    sampler: Sampler,
    pool: DescriptorPool,
    set: Option<vk::DescriptorSet>,
    device: Arc<Device>,
}

/// A resolve pipeline: its sample count, levels rather than radiance, B, G, R order, and whether it writes
/// the background.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct PipelineKey {
    samples: u32,
    levels: bool,
    bgra: bool,
    background: bool,
}

/// What one image's resolve records (every handle owned by the pass or the targets).
#[derive(Clone, Copy)]
pub struct ResolveRecording {
    pipeline: vk::Pipeline,
    layout: vk::PipelineLayout,
    set: vk::DescriptorSet,
    /// resolve.comp's push constants: width, height, exposure, a pad, and the background's colour.
    push: [u32; 8],
    /// Invocations a row: a pixel each, or four (levels).
    row_invocations: u32,
}

/// The sample counts at which the resolve can write the background (forward.rs's `Background::Resolved`):
/// none unless the depth may be cleared below 0 and sampled.
pub fn background_sample_counts(device: &Device) -> vk::SampleCountFlags {
    // SAFETY: a plain query on a live physical device.
    let features = unsafe {
        device.instance.raw.get_physical_device_format_properties(device.physical, DEPTH_FORMAT).optimal_tiling_features
    };
    if device.depth_range_unrestricted && features.contains(vk::FormatFeatureFlags::SAMPLED_IMAGE) {
        device.limits.sampled_image_depth_sample_counts
    } else {
        vk::SampleCountFlags::empty()
    }
}

impl ResolvePass {
    /// Compiles the builds of `resolve.comp`; the pipelines are built when first used.
    ///
    /// # Errors
    /// `Error::Shader` or `Error::Vulkan`.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler) -> Result<Self> {
        let module = |entry: &str| device.create_shader_module(&compiler.compile(entry)?, entry);
        let binding = |index: u32, kind| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(index)
                .descriptor_type(kind)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        };
        let bindings = [
            binding(0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
            binding(1, vk::DescriptorType::STORAGE_BUFFER),
            binding(2, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
        ];
        let push = [vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: 32 }];
        let pool = device.create_descriptor_pool(
            1,
            &[
                vk::DescriptorPoolSize { ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER, descriptor_count: 2 },
                vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: 1 },
            ],
        )?;
        let builds = [
            "resolve.comp",
            "resolve.comp+SINGLE_SAMPLE",
            "resolve.comp+BACKGROUND",
            "resolve.comp+BACKGROUND+SINGLE_SAMPLE",
        ];
        Ok(Self {
            modules: builds.into_iter().map(module).collect::<Result<_>>()?,
            layout: device.create_pipeline_layout(&[&bindings], &push, "resolve layout")?,
            pipelines: HashMap::new(),
            sampler: device.create_nearest_sampler("resolve")?,
            pool,
            set: None,
            device: device.clone(),
        })
    }

    /// Builds the pipeline for images of `samples` read back as `readout`, writing the background or not,
    /// unless it is built.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the pipeline.
    pub fn build(&mut self, samples: u32, readout: Readout, background: bool) -> Result<()> {
        let key = Self::key(samples, readout, background);
        if !self.pipelines.contains_key(&key) {
            let module = &self.modules[2 * usize::from(background) + usize::from(samples == 1)];
            let name = format!("{key:?}");
            let constants = [samples, u32::from(key.levels), u32::from(key.bgra)];
            let pipeline = self.device.create_compute_pipeline(module, &self.layout, &constants, &name)?;
            log::debug!("built the resolve pipeline for {name}");
            self.pipelines.insert(key, pipeline);
        }
        Ok(())
    }

    fn key(samples: u32, readout: Readout, background: bool) -> PipelineKey {
        let (levels, bgra) = match readout {
            Readout::Radiance => (false, false),
            Readout::Levels { bgra, .. } => (true, bgra),
        };
        PipelineKey { samples, levels, bgra, background }
    }

    /// Points the set at `targets` (no submitted work may still use it: renders wait for theirs) and returns
    /// what to record for `readout`; with `background`, its colour where the depth says no object is.
    ///
    /// # Errors
    /// `Error::Vulkan` if the set cannot be allocated or the pipeline built.
    pub fn prepare(
        &mut self,
        targets: &Targets,
        readout: Readout,
        background: Option<[f32; 4]>,
    ) -> Result<ResolveRecording> {
        let samples = targets.samples();
        self.build(samples, readout, background.is_some())?;
        let read_only = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        // Every binding is written, the depth's with the colour when no background is written (then unread):
        // Mesa 22's lavapipe reads every descriptor of a set it binds, and crashed on an unwritten one.
        let depth = if background.is_some() { targets.depth.view } else { targets.color.view };
        let descriptors = [
            Descriptor::SampledImage(targets.color.view, &self.sampler, read_only),
            Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &targets.readback),
            Descriptor::SampledImage(depth, &self.sampler, read_only),
        ];
        let set = match self.set {
            Some(set) => {
                self.pool.write_set(set, &descriptors);
                set
            }
            None => *self.set.insert(self.pool.allocate_set(self.layout.set_layouts[0], &descriptors)?),
        };
        let exposure = match readout {
            Readout::Radiance => 1.0,
            Readout::Levels { exposure, .. } => exposure,
        };
        let (width, height) = targets.size();
        let [r, g, b, a] = background.unwrap_or_default().map(f32::to_bits);
        Ok(ResolveRecording {
            pipeline: self.pipelines[&Self::key(samples, readout, background.is_some())].raw,
            layout: self.layout.raw,
            set,
            push: [width, height, exposure.to_bits(), 0, r, g, b, a],
            row_invocations: (readout.row_bytes(width) / TEXEL_BYTES) as u32,
        })
    }
}

impl ResolveRecording {
    /// Records the resolve: the colour target (and the depth, when it writes the background) must be
    /// readable by the compute shader; the read-back buffer is then made readable by the host.
    pub fn record(&self, device: &Device, cmd: vk::CommandBuffer, targets: &Targets) {
        let push: Vec<u8> = self.push.iter().flat_map(|word| word.to_ne_bytes()).collect();
        // SAFETY: the command buffer is recording; the pipeline, set and targets outlive the submission.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline);
            device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, self.layout, 0, &[self.set], &[]);
            device.raw.cmd_push_constants(cmd, self.layout, vk::ShaderStageFlags::COMPUTE, 0, &push);
            device.raw.cmd_dispatch(cmd, self.row_invocations.div_ceil(WORKGROUP_SIZE), self.push[1], 1);
        }
        targets.readback.record_host_read_barrier(
            cmd,
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
    }
}
