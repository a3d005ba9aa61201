//! The forward pass: one pipeline per sample count, shading every object against every light.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use super::passes::{begin_rendering, vertex_input, PassTargets};
use crate::error::Result;
use crate::vulkan::{Device, GraphicsPipelineDesc, Pipeline, PipelineLayout, ShaderCompiler};

/// The HDR colour format: 32-bit float, so that the course's truncation to 8 bits sees exact values.
pub const COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The forward pass's compiled shaders and pipelines, made once per renderer.
pub struct ForwardPass {
    vertex_spirv: Vec<u32>,
    fragment_spirv: Vec<u32>,
    layout: Arc<PipelineLayout>,
    pipelines: HashMap<vk::SampleCountFlags, Pipeline>,
    device: Arc<Device>,
}

impl ForwardPass {
    /// Compiles the forward shaders.
    ///
    /// # Errors
    /// `Error::Shader` if a shader does not compile.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler, layout: &Arc<PipelineLayout>) -> Result<Self> {
        Ok(Self {
            vertex_spirv: compiler.compile("forward.vert")?,
            fragment_spirv: compiler.compile("forward.frag")?,
            layout: layout.clone(),
            pipelines: HashMap::new(),
            device: device.clone(),
        })
    }

    /// The pipeline for `samples`, built the first time that count is asked for.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the pipeline.
    pub fn pipeline(&mut self, samples: vk::SampleCountFlags) -> Result<&Pipeline> {
        if !self.pipelines.contains_key(&samples) {
            let vertex = self.device.create_shader_module(&self.vertex_spirv, "forward.vert")?;
            let fragment = self.device.create_shader_module(&self.fragment_spirv, "forward.frag")?;
            let (bindings, attributes) = vertex_input();
            let desc = GraphicsPipelineDesc {
                vertex: &vertex,
                fragment: &fragment,
                vertex_bindings: &bindings,
                vertex_attributes: &attributes,
                color_formats: &[COLOR_FORMAT],
                depth_format: DEPTH_FORMAT,
                // Reverse-Z: nearer is greater. Equal passes so that the plane's horizon (depth 0) is drawn.
                depth_compare: vk::CompareOp::GREATER_OR_EQUAL,
                samples,
                layout: &self.layout,
            };
            let pipeline = self.device.create_graphics_pipeline(&desc, &format!("forward x{}", samples.as_raw()))?;
            log::debug!("built the forward pipeline for {} sample(s)", samples.as_raw());
            self.pipelines.insert(samples, pipeline);
        }
        Ok(&self.pipelines[&samples])
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
