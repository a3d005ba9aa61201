//! The forward pass: its pipeline layout, one pipeline per sample count, and the recording of a frame.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use crate::error::Result;
use crate::mesh::Vertex;
use crate::vulkan::{Device, GraphicsPipelineDesc, Pipeline, PipelineLayout, ShaderCompiler};

/// The HDR colour format: 32-bit float, so that the course's truncation to 8 bits sees exact values.
pub const COLOR_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The forward pass's compiled shaders, layout and pipelines, made once per renderer.
pub struct ForwardPass {
    vertex_spirv: Vec<u32>,
    fragment_spirv: Vec<u32>,
    pub layout: Arc<PipelineLayout>,
    pipelines: HashMap<vk::SampleCountFlags, Pipeline>,
    device: Arc<Device>,
}

impl ForwardPass {
    /// Compiles the forward shaders and makes the pipeline layout.
    ///
    /// # Errors
    /// `Error::Shader` if a shader does not compile, `Error::Vulkan` if the layout is refused.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler) -> Result<Self> {
        let vertex_spirv = compiler.compile("forward.vert")?;
        let fragment_spirv = compiler.compile("forward.frag")?;
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
        ];
        let push = [vk::PushConstantRange { stage_flags: stages, offset: 0, size: 4 }];
        let layout = device.create_pipeline_layout(&[&bindings], &push, "forward layout")?;
        Ok(Self { vertex_spirv, fragment_spirv, layout, pipelines: HashMap::new(), device: device.clone() })
    }

    /// The pipeline for `samples`, built the first time that count is asked for.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the pipeline.
    pub fn pipeline(&mut self, samples: vk::SampleCountFlags) -> Result<&Pipeline> {
        if !self.pipelines.contains_key(&samples) {
            let vertex = self.device.create_shader_module(&self.vertex_spirv, "forward.vert")?;
            let fragment = self.device.create_shader_module(&self.fragment_spirv, "forward.frag")?;
            let bindings = [vk::VertexInputBindingDescription {
                binding: 0,
                stride: std::mem::size_of::<Vertex>() as u32,
                input_rate: vk::VertexInputRate::VERTEX,
            }];
            let attributes = [
                vk::VertexInputAttributeDescription {
                    location: 0,
                    binding: 0,
                    format: vk::Format::R32G32B32A32_SFLOAT,
                    offset: std::mem::offset_of!(Vertex, position) as u32,
                },
                vk::VertexInputAttributeDescription {
                    location: 1,
                    binding: 0,
                    format: vk::Format::R32G32B32_SFLOAT,
                    offset: std::mem::offset_of!(Vertex, normal) as u32,
                },
            ];
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
