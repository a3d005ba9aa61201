//! The BRDF probe pass: `brdf_eval` of the GLSL evaluated on the GPU for a list of cases (to be compared with
//! the Rust mirror, and plotted), or integrated over cells of the hemisphere (albedos), read back as float32.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use super::gpu_types::GpuMaterial;
use super::measured::MeasuredTables;
use crate::brdf::Brdf;
use crate::error::{Error, Result};
use crate::vulkan::{Buffer, BufferDesc, Descriptor, Device, Pipeline, ShaderCompiler};

/// One evaluation: f_r(wi, wo) of a material at a surface with normal n.
#[derive(Clone, Debug, PartialEq)]
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

/// One job of the albedo probe: a material seen from `wo`, in the frame n = +z, wo in the xz-plane.
#[derive(Clone, Debug, PartialEq)]
pub struct AlbedoJob {
    pub brdf: Brdf,
    pub wo: Vec3,
}

/// One cell of the hemisphere of wi for a job: theta_i and phi_i from the first bound to the second
/// (radians).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct AlbedoCell {
    pub job: u32,
    pub theta: (f32, f32),
    pub phi: (f32, f32),
}

/// The integral of f_r cos(theta_i) over a cell by the 15-point Gauss-Kronrod rule in both angles, and by
/// the 7-point Gauss rule embedded in it: their difference bounds the error of the coarser one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CellIntegral {
    pub kronrod: Vec3,
    pub gauss: Vec3,
}

/// `AlbedoJob` of `shaders/brdf_albedo.comp` (std430).
#[repr(C)]
#[derive(Clone, Copy)]
struct GpuAlbedoJob {
    material: GpuMaterial,
    wo: [f32; 4],
}

/// `AlbedoCell` of `shaders/brdf_albedo.comp` (std430).
#[repr(C)]
#[derive(Clone, Copy)]
struct GpuAlbedoCell {
    bounds: [f32; 4],
    job: u32,
    pad: [u32; 3],
}

const WORKGROUP_SIZE: u32 = 64;

/// The probe shaders and their pipelines: `brdf_eval` at given cases, and integrated over cells.
pub struct ProbePass {
    eval: Pipeline,
    albedo: Pipeline,
    device: Arc<Device>,
}

impl ProbePass {
    /// Compiles `brdf_probe.comp` and `brdf_albedo.comp` and builds their pipelines.
    ///
    /// # Errors
    /// `Error::Shader` or `Error::Vulkan`.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler) -> Result<Self> {
        Ok(Self {
            eval: storage_pipeline(device, compiler, "brdf_probe.comp", 3)?,
            albedo: storage_pipeline(device, compiler, "brdf_albedo.comp", 4)?,
            device: device.clone(),
        })
    }

    /// Evaluates every case on the GPU, their measured tables in `tables`.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn run(&self, cases: &[ProbeCase], tables: &MeasuredTables) -> Result<Vec<Vec3>> {
        let mut values = Vec::with_capacity(cases.len());
        for chunk in cases.chunks(self.per_dispatch::<GpuProbeCase>()) {
            let gpu_cases: Vec<GpuProbeCase> = chunk
                .iter()
                .map(|c| GpuProbeCase {
                    material: GpuMaterial::new(&c.brdf, tables),
                    n: c.n.extend(0.0).into(),
                    wi: c.wi.extend(0.0).into(),
                    wo: c.wo.extend(0.0).into(),
                })
                .collect();
            let input = self.input(&gpu_cases, "probe cases")?;
            values.extend(read_vec3s(&self.dispatch(&self.eval, &[&input], tables, chunk.len(), 16)?, 16));
        }
        Ok(values)
    }

    /// How many elements of `T` one dispatch takes: as many as a storage buffer may hold
    /// (`maxStorageBufferRange`: 128 MiB on lavapipe), at most 2^20 (the memory a dispatch holds at once).
    fn per_dispatch<T>(&self) -> usize {
        (self.device.limits.max_storage_buffer_range as usize / std::mem::size_of::<T>()).clamp(1, 1 << 20)
    }

    /// Integrates f_r cos(theta_i) over every cell on the GPU, the jobs' measured tables in `tables`.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn integrate(
        &self,
        jobs: &[AlbedoJob],
        cells: &[AlbedoCell],
        tables: &MeasuredTables,
    ) -> Result<Vec<CellIntegral>> {
        let gpu_jobs: Vec<GpuAlbedoJob> = jobs
            .iter()
            .map(|job| GpuAlbedoJob { material: GpuMaterial::new(&job.brdf, tables), wo: job.wo.extend(0.0).into() })
            .collect();
        let jobs_buffer = self.input(&gpu_jobs, "albedo jobs")?;
        let mut integrals = Vec::with_capacity(cells.len());
        for chunk in cells.chunks(self.per_dispatch::<GpuAlbedoCell>()) {
            let gpu_cells: Vec<GpuAlbedoCell> = chunk
                .iter()
                .map(|cell| GpuAlbedoCell {
                    bounds: [cell.theta.0, cell.theta.1, cell.phi.0, cell.phi.1],
                    job: cell.job,
                    pad: [0; 3],
                })
                .collect();
            let cells_buffer = self.input(&gpu_cells, "albedo cells")?;
            let bytes = self.dispatch(&self.albedo, &[&jobs_buffer, &cells_buffer], tables, chunk.len(), 32)?;
            let estimates = read_vec3s(&bytes, 16);
            integrals.extend(estimates.chunks_exact(2).map(|pair| CellIntegral { kronrod: pair[0], gauss: pair[1] }));
        }
        Ok(integrals)
    }

    fn input<T: Copy>(&self, data: &[T], name: &str) -> Result<Buffer> {
        self.device.create_buffer_with_data(data, vk::BufferUsageFlags::STORAGE_BUFFER, name)
    }

    /// Runs `pipeline` once per element over `inputs` (its first bindings), a results buffer of `result_size`
    /// bytes per element (the next) and the measured tables (the last), and returns the results' bytes.
    fn dispatch(
        &self,
        pipeline: &Pipeline,
        inputs: &[&Buffer],
        tables: &MeasuredTables,
        count: usize,
        result_size: usize,
    ) -> Result<Vec<u8>> {
        if count == 0 {
            return Ok(Vec::new());
        }
        let device = &self.device;
        let output = device.create_buffer(
            BufferDesc {
                size: (count * result_size) as u64,
                usage: vk::BufferUsageFlags::STORAGE_BUFFER,
                location: MemoryLocation::GpuToCpu,
            },
            "probe results",
        )?;
        let buffers: Vec<&Buffer> = inputs.iter().copied().chain([&output, tables.buffer()]).collect();
        let pool = device.create_descriptor_pool(
            1,
            &[vk::DescriptorPoolSize {
                ty: vk::DescriptorType::STORAGE_BUFFER,
                descriptor_count: buffers.len() as u32,
            }],
        )?;
        let layout = &pipeline.layout;
        let descriptors: Vec<Descriptor> =
            buffers.iter().map(|buffer| Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, buffer)).collect();
        let set = pool.allocate_set(layout.set_layouts[0], &descriptors)?;
        let count = u32::try_from(count).map_err(|_| Error::Vulkan(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY))?;
        device.submit_and_wait(|cmd| {
            // SAFETY: every handle recorded here lives until submit_and_wait has waited for the work.
            unsafe {
                device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
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
        Ok(output.bytes()?.to_vec())
    }
}

/// A compute pipeline over `bindings` storage buffers with the element count as its push constant.
fn storage_pipeline(device: &Arc<Device>, compiler: &ShaderCompiler, file: &str, bindings: u32) -> Result<Pipeline> {
    let spirv = compiler.compile(file)?;
    let module = device.create_shader_module(&spirv, file)?;
    let bindings: Vec<_> = (0..bindings)
        .map(|index| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(index)
                .descriptor_type(vk::DescriptorType::STORAGE_BUFFER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::COMPUTE)
        })
        .collect();
    let push = [vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: 4 }];
    let layout = device.create_pipeline_layout(&[&bindings], &push, &format!("{file} layout"))?;
    device.create_compute_pipeline(&module, &layout, file)
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
