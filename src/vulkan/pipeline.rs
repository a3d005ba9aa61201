//! Pipeline layouts (with their descriptor set layouts) and graphics pipelines.

use std::sync::Arc;

use ash::vk;

use super::{Device, ShaderModule};
use crate::error::Result;

/// A pipeline layout and the descriptor set layouts it was made from, destroyed together in Drop.
pub struct PipelineLayout {
    /// The Vulkan handle.
    pub raw: vk::PipelineLayout,
    /// One descriptor set layout per set, in set order.
    pub set_layouts: Vec<vk::DescriptorSetLayout>,
    device: Arc<Device>,
}

/// A pipeline, destroyed in Drop; it keeps its layout alive.
pub struct Pipeline {
    /// The Vulkan handle.
    pub raw: vk::Pipeline,
    /// The layout it was made with.
    pub layout: Arc<PipelineLayout>,
    device: Arc<Device>,
}

/// What a graphics pipeline draws with and into (dynamic rendering, dynamic viewport and scissor).
pub struct GraphicsPipelineDesc<'a> {
    /// The vertex stage, entry point `main`.
    pub vertex: &'a ShaderModule,
    /// The fragment stage, entry point `main`.
    pub fragment: &'a ShaderModule,
    /// The vertex buffers' strides and rates.
    pub vertex_bindings: &'a [vk::VertexInputBindingDescription],
    /// The vertex shader's inputs: location, binding, format and offset.
    pub vertex_attributes: &'a [vk::VertexInputAttributeDescription],
    /// One colour attachment per format, in location order, written without blending.
    pub color_formats: &'a [vk::Format],
    /// The depth attachment's format.
    pub depth_format: vk::Format,
    /// The depth test (the forward pass's reverse-Z is `GREATER_OR_EQUAL`); depth is always written.
    pub depth_compare: vk::CompareOp,
    /// Samples per pixel of every attachment.
    pub samples: vk::SampleCountFlags,
    /// The layout of its descriptor sets and push constants.
    pub layout: &'a Arc<PipelineLayout>,
    /// The fragment shader's specialization constants: entry i is the value of `constant_id = i`.
    pub fragment_constants: &'a [u32],
}

impl Device {
    /// Creates one descriptor set layout per entry of `sets`, and a layout with them and the push constants.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses a layout.
    pub fn create_pipeline_layout(
        self: &Arc<Self>,
        sets: &[&[vk::DescriptorSetLayoutBinding]],
        push_constants: &[vk::PushConstantRange],
        name: &str,
    ) -> Result<Arc<PipelineLayout>> {
        // Built field by field so that Drop frees whatever was made if a later step fails.
        let mut layout =
            PipelineLayout { raw: vk::PipelineLayout::null(), set_layouts: Vec::new(), device: self.clone() };
        for bindings in sets {
            let info = vk::DescriptorSetLayoutCreateInfo::default().bindings(bindings);
            // SAFETY: the device is alive.
            layout.set_layouts.push(unsafe { self.raw.create_descriptor_set_layout(&info, None)? });
        }
        let info = vk::PipelineLayoutCreateInfo::default()
            .set_layouts(&layout.set_layouts)
            .push_constant_ranges(push_constants);
        // SAFETY: the set layouts are alive.
        layout.raw = unsafe { self.raw.create_pipeline_layout(&info, None)? };
        self.set_name(layout.raw, name);
        Ok(Arc::new(layout))
    }

    /// Creates a graphics pipeline for dynamic rendering, triangle lists, opaque output; viewport, scissor,
    /// cull mode and front face are set while recording.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the pipeline.
    pub fn create_graphics_pipeline(self: &Arc<Self>, desc: &GraphicsPipelineDesc, name: &str) -> Result<Pipeline> {
        let entries: Vec<vk::SpecializationMapEntry> = (0..desc.fragment_constants.len() as u32)
            .map(|id| vk::SpecializationMapEntry { constant_id: id, offset: 4 * id, size: 4 })
            .collect();
        let constant_bytes: Vec<u8> = desc.fragment_constants.iter().flat_map(|v| v.to_ne_bytes()).collect();
        let specialization = vk::SpecializationInfo::default().map_entries(&entries).data(&constant_bytes);
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(desc.vertex.raw)
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(desc.fragment.raw)
                .name(c"main")
                .specialization_info(&specialization),
        ];
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
            .vertex_binding_descriptions(desc.vertex_bindings)
            .vertex_attribute_descriptions(desc.vertex_attributes);
        let input_assembly =
            vk::PipelineInputAssemblyStateCreateInfo::default().topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default().viewport_count(1).scissor_count(1);
        let rasterization =
            vk::PipelineRasterizationStateCreateInfo::default().polygon_mode(vk::PolygonMode::FILL).line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default().rasterization_samples(desc.samples);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true)
            .depth_compare_op(desc.depth_compare);
        let attachments: Vec<_> = desc
            .color_formats
            .iter()
            .map(|_| vk::PipelineColorBlendAttachmentState::default().color_write_mask(vk::ColorComponentFlags::RGBA))
            .collect();
        let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&attachments);
        let dynamic_states = [
            vk::DynamicState::VIEWPORT,
            vk::DynamicState::SCISSOR,
            vk::DynamicState::CULL_MODE,
            vk::DynamicState::FRONT_FACE,
        ];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(desc.color_formats)
            .depth_attachment_format(desc.depth_format);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&input_assembly)
            .viewport_state(&viewport)
            .rasterization_state(&rasterization)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blend)
            .dynamic_state(&dynamic)
            .layout(desc.layout.raw)
            .push_next(&mut rendering);
        // SAFETY: every structure the info points to lives until the call returns.
        let raw = unsafe { self.raw.create_graphics_pipelines(vk::PipelineCache::null(), &[info], None) }
            .map_err(|(_, e)| e)?[0];
        self.set_name(raw, name);
        Ok(Pipeline { raw, layout: desc.layout.clone(), device: self.clone() })
    }
}

impl Device {
    /// Creates a compute pipeline running `main` of `shader`, its specialization constants set: entry i of
    /// `constants` is the value of `constant_id = i`.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the pipeline.
    pub fn create_compute_pipeline(
        self: &Arc<Self>,
        shader: &ShaderModule,
        layout: &Arc<PipelineLayout>,
        constants: &[u32],
        name: &str,
    ) -> Result<Pipeline> {
        let entries: Vec<vk::SpecializationMapEntry> = (0..constants.len() as u32)
            .map(|id| vk::SpecializationMapEntry { constant_id: id, offset: 4 * id, size: 4 })
            .collect();
        let constant_bytes: Vec<u8> = constants.iter().flat_map(|v| v.to_ne_bytes()).collect();
        let specialization = vk::SpecializationInfo::default().map_entries(&entries).data(&constant_bytes);
        let stage = vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::COMPUTE)
            .module(shader.raw)
            .name(c"main")
            .specialization_info(&specialization);
        let info = vk::ComputePipelineCreateInfo::default().stage(stage).layout(layout.raw);
        // SAFETY: the module and layout are alive for the call.
        let raw = unsafe { self.raw.create_compute_pipelines(vk::PipelineCache::null(), &[info], None) }
            .map_err(|(_, e)| e)?[0];
        self.set_name(raw, name);
        Ok(Pipeline { raw, layout: layout.clone(), device: self.clone() })
    }
}

impl Drop for PipelineLayout {
    fn drop(&mut self) {
        if self.device.is_given_up() {
            return; // work that never ended may still use it (Device::give_up)
        }
        // SAFETY: no pipeline made with this layout is left (each holds an Arc of it).
        unsafe {
            self.device.raw.destroy_pipeline_layout(self.raw, None);
            for &set_layout in &self.set_layouts {
                self.device.raw.destroy_descriptor_set_layout(set_layout, None);
            }
        }
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        if self.device.is_given_up() {
            return; // work that never ended may still use it (Device::give_up)
        }
        // SAFETY: renders wait for their work before returning, so the GPU no longer uses the pipeline.
        unsafe { self.device.raw.destroy_pipeline(self.raw, None) };
    }
}
