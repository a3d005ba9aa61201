//! The forward pass: shading every object against every light, with a pipeline per kind of object (meshes,
//! exact spheres), BRDF, shadow filter and sample count.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use super::gpu_types::GpuMaterial;
use super::passes::{begin_rendering, build_pipeline, CompiledShader, PassTargets};
use crate::error::Result;
use crate::mesh::PlacedMesh;
use crate::scene::{Object, Scene, ShadowFilter};
use crate::vulkan::{Device, Pipeline, PipelineLayout, ShaderCompiler};

/// The HDR colour format: 32-bit float, so that the course's truncation to 8 bits sees exact values.
pub const COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The forward pass's compiled shaders, and its pipelines, each built on first use.
pub struct ForwardPass {
    meshes: (CompiledShader, CompiledShader),
    spheres: (CompiledShader, CompiledShader),
    layout: Arc<PipelineLayout>,
    pipelines: HashMap<PipelineKey, Pipeline>,
    device: Arc<Device>,
}

/// What a forward pipeline is built for: the sample count, meshes or exact spheres, and the values of the
/// fragment shader's specialization constants, in the order of their `constant_id`s: the BRDF (brdf.glsl's
/// `BRDF_SPECIALIZED`), the shadow filter and the number of lights (shading.glsl's `SHADOW_FILTER` and
/// `LIGHT_COUNT`), and Cook-Torrance's diffuse lobe (brdf.glsl's `DIFFUSE_SPECIALIZED`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
struct PipelineKey {
    samples: vk::SampleCountFlags,
    exact_sphere: bool,
    constants: [u32; 4],
}

impl ForwardPass {
    /// Compiles the forward shaders.
    ///
    /// # Errors
    /// `Error::Shader` if a shader does not compile.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler, layout: &Arc<PipelineLayout>) -> Result<Self> {
        Ok(Self {
            meshes: (CompiledShader::new(compiler, "forward.vert")?, CompiledShader::new(compiler, "forward.frag")?),
            spheres: (
                CompiledShader::new(compiler, "forward_sphere.vert")?,
                CompiledShader::new(compiler, "forward_sphere.frag")?,
            ),
            layout: layout.clone(),
            pipelines: HashMap::new(),
            device: device.clone(),
        })
    }

    /// The pipeline that draws `placed` with `object`'s BRDF into the targets of `scene`'s image.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the pipeline.
    pub fn pipeline(&mut self, scene: &Scene, object: &Object, placed: &PlacedMesh) -> Result<vk::Pipeline> {
        let material = GpuMaterial::from(&object.brdf);
        let shadow_filter = match scene.image.shadow_filter {
            ShadowFilter::Hard => 0,
            ShadowFilter::Pcf => 1,
        };
        let key = PipelineKey {
            samples: vk::SampleCountFlags::from_raw(scene.image.samples),
            exact_sphere: placed.exact_sphere,
            constants: [material.brdf, shadow_filter, scene.lights.len() as u32, material.diffuse],
        };
        if let Some(pipeline) = self.pipelines.get(&key) {
            return Ok(pipeline.raw);
        }
        let (vertex, fragment) = if key.exact_sphere { &self.spheres } else { &self.meshes };
        let pipeline = build_pipeline(
            &self.device,
            &self.layout,
            (vertex, fragment),
            (COLOR_FORMAT, key.samples),
            &key.constants,
        )?;
        log::debug!("built the forward pipeline for {key:?}");
        let raw = pipeline.raw;
        self.pipelines.insert(key, pipeline);
        Ok(raw)
    }
}

/// Begins dynamic rendering into the colour target (cleared to the background; resolved to `resolved`
/// when multisampled, the float resolve averaging the samples as the course averages its pixel samples)
/// and the depth target.
pub fn begin(device: &Device, cmd: vk::CommandBuffer, targets: &PassTargets, background: [f32; 4]) {
    let mut color = vk::RenderingAttachmentInfo::default()
        .image_view(targets.color)
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue { color: vk::ClearColorValue { float32: background } });
    if let Some(resolved) = targets.resolve {
        color = color
            .resolve_mode(vk::ResolveModeFlags::AVERAGE)
            .resolve_image_view(resolved)
            .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
            .store_op(vk::AttachmentStoreOp::DONT_CARE);
    }
    begin_rendering(device, cmd, targets, color);
}
