//! The BRDF probe pass: `brdf_eval` of the GLSL evaluated on the GPU for a list of cases, read back as
//! float32, to be compared with the Rust mirror.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use super::gpu_types::GpuMaterial;
use crate::brdf::Brdf;
use crate::error::Result;
use crate::vulkan::{BufferDesc, Descriptor, Device, Pipeline, ShaderCompiler};

/// One evaluation: f_r(wi, wo) of a material at a surface with normal n.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeCase {
    pub brdf: Brdf,
    pub n: Vec3,
    pub wi: Vec3,
    pub wo: Vec3,
}

/// `ProbeCase` of `shaders/brdf_probe.comp` (std430).
#[repr(C)]
#[derive(Clone, Copy)]
struct GpuProbeCase {
    material: GpuMaterial,
    n: [f32; 4],
    wi: [f32; 4],
    wo: [f32; 4],
}

const WORKGROUP_SIZE: u32 = 64;

/// The compiled probe shader and its pipeline.
pub struct ProbePass {
    pipeline: Pipeline,
    device: Arc<Device>,
}

impl ProbePass {
    /// Compiles `brdf_probe.comp` and builds its pipeline.
    ///
    /// # Errors
    /// `Error::Shader` or `Error::Vulkan`.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler) -> Result<Self> {
        let spirv = compiler.compile("brdf_probe.comp")?;
        let module = device.create_shader_module(&spirv, "brdf_probe.comp")?;
        let binding = |index: u32| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(index)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        };
        let push = [vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: 4 }];
        let layout = device.create_pipeline_layout(&[&[binding(0), binding(1)]], &push, "probe layout")?;
        let pipeline = device.create_compute_pipeline(&module, &layout, "brdf probe")?;
        Ok(Self { pipeline, device: device.clone() })
    }

    /// Evaluates every case on the GPU.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn run(&self, cases: &[ProbeCase]) -> Result<Vec<Vec3>> {
        if cases.is_empty() {
            return Ok(Vec::new());
        }
        let device = &self.device;
        let gpu_cases: Vec<GpuProbeCase> = cases
            .iter()
            .map(|c| GpuProbeCase {
                material: GpuMaterial::from(&c.brdf),
                n: c.n.extend(0.0).into(),
                wi: c.wi.extend(0.0).into(),
                wo: c.wo.extend(0.0).into(),
            })
            .collect();
        let input = device.create_buffer_with_data(&gpu_cases, vk::BufferUsageFlags::STORAGE_BUFFER, "probe cases")?;
        let output = device.create_buffer(
            BufferDesc {
                size: (cases.len() * 16) as u64,
                usage: vk::BufferUsageFlags::STORAGE_BUFFER,
                location: MemoryLocation::GpuToCpu,
            },
            "probe results",
        )?;
        let pool = device.create_descriptor_pool(
            1,
            &[vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: 2 }],
        )?;
        let layout = &self.pipeline.layout;
        let set = pool.allocate_set(
            layout.set_layouts[0],
            &[
                Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &input),
                Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &output),
            ],
        )?;
        let count = cases.len() as u32;
        device.submit_and_wait(|cmd| {
            // SAFETY: every handle recorded here lives until submit_and_wait has waited for the work.
            unsafe {
                device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, self.pipeline.raw);
                device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout.raw, 0, &[set], &[]);
                device.raw.cmd_push_constants(cmd, layout.raw, vk::ShaderStageFlags::COMPUTE, 0, &count.to_ne_bytes());
                device.raw.cmd_dispatch(cmd, count.div_ceil(WORKGROUP_SIZE), 1, 1);
            }
            output.record_host_read_barrier(
                cmd,
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_WRITE,
            );
            Ok(())
        })?;
        Ok(read_vec3s(output.bytes()?, 16))
    }
}

/// The first three f32 of each `stride`-byte element.
pub(super) fn read_vec3s(bytes: &[u8], stride: usize) -> Vec<Vec3> {
    bytes
        .chunks_exact(stride)
        .map(|element| {
            let channel = |i: usize| f32::from_ne_bytes([element[i], element[i + 1], element[i + 2], element[i + 3]]);
            Vec3::new(channel(0), channel(4), channel(8))
        })
        .collect()
}
