//! The BRDF probe pass: `brdf_eval` of the GLSL evaluated on the GPU for a list of cases (to be compared with
//! the Rust mirror, and plotted), or integrated over cells of the hemisphere (albedos), read back as float32.

use std::collections::{BTreeMap, HashMap};
use std::sync::Arc;

use ash::vk;
use cubature::{Cell, CellEstimate};
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use super::analytic::{analytic_shader, AnalyticShader};
use super::gpu_types::{brdf_id, GpuMaterial, MaterialData};
use crate::brdf::Brdf;
use crate::error::{Error, Result};
use crate::vulkan::{Buffer, BufferDesc, Descriptor, Device, Pipeline, PipelineLayout, ShaderCompiler, ShaderModule};

/// One evaluation: f_r(wi, wo) of a material at a surface with normal n.
#[derive(Clone, Debug, PartialEq)]
pub struct ProbeCase {
    /// The material evaluated.
    pub brdf: Brdf,
    /// The surface's unit normal.
    pub n: Vec3,
    /// The unit direction towards the light, away from the surface.
    pub wi: Vec3,
    /// The unit direction towards the viewer, away from the surface.
    pub wo: Vec3,
}

/// A list's case in `AllDirections` of `shaders/brdf_probe.comp`: n, wi and wo, packed.
type ListDirections = [f32; 9];

/// A grid's case there: wi and wo (n = +z).
type GridDirections = [f32; 6];

/// The shader's result of a case: f_r's three channels, packed.
type GpuResult = [f32; 3];

fn list_directions(n: Vec3, wi: Vec3, wo: Vec3) -> ListDirections {
    [n.x, n.y, n.z, wi.x, wi.y, wi.z, wo.x, wo.y, wo.z]
}

fn grid_directions(wi: Vec3, wo: Vec3) -> GridDirections {
    [wi.x, wi.y, wi.z, wo.x, wo.y, wo.z]
}

/// One job of the albedo probe: a material seen from `wo`, in the frame n = +z, wo in the xz-plane.
#[derive(Clone, Debug, PartialEq)]
pub struct AlbedoJob {
    /// The material seen.
    pub brdf: Brdf,
    /// The unit direction towards the viewer, in the xz-plane (z up the normal).
    pub wo: Vec3,
}

/// `AlbedoJob` of `shaders/brdf_albedo.comp` (std430).
#[repr(C)]
#[derive(Clone, Copy)]
pub(super) struct GpuAlbedoJob {
    pub(super) material: GpuMaterial,
    pub(super) wo: [f32; 4],
}

/// `AlbedoCell` of `shaders/brdf_albedo.comp` (std430): a cell of crates/cubature in single precision.
#[repr(C)]
#[derive(Clone, Copy)]
struct GpuAlbedoCell {
    bounds: [f32; 4],
    job: u32,
    pad: [u32; 3],
}

const WORKGROUP_SIZE: u32 = 64;

/// The most BRDF evaluations one dispatch makes: each dispatch is waited for within the device's timeout,
/// and an albedo's refinement of a sharp lobe (Ashikhmin-Shirley's of exponent 100) made 2^20 cells of 225
/// evaluations each, over the 30 s a wait may take on lavapipe. 2^20 evaluations of the Disney BRDF take
/// about 0.1 s there; the memory a dispatch holds at once stays small.
pub(super) const EVALUATIONS_PER_DISPATCH: usize = 1 << 20;

/// The probe shaders and their pipelines: `brdf_eval` at given cases, and integrated over cells, one pipeline
/// per BRDF, built when first needed.
///
/// Each pipeline fixes its BRDF (brdf.glsl's `BRDF_SPECIALIZED`), as the forward pass's do: lavapipe compiles
/// every case of a switch on a value it does not know, and runs them all with the lanes that do not take
/// them masked off: one pipeline reading the id from the material would compile the measured lookup too, in
/// every process that probes, whatever it probes.
/// An analytic model's pipelines are built from the shader compiled at run time with its GLSL.
pub struct ProbePass {
    eval: Shader,
    albedo: Shader,
    pub(super) sampler: Shader,
    /// `brdf_density64.comp`, made when first used on a device with doubles.
    pub(super) density64: Option<Shader>,
    /// The analytic models whose double form did not compile (see [`brdf_file::wrap_double`]).
    pub(super) without_double: std::collections::HashSet<AnalyticShader>,
    pub(super) device: Arc<Device>,
}

/// What a probe pipeline fixes: the BRDF id, and for an analytic model the model it is compiled with.
pub(super) type Variant = (u32, Option<AnalyticShader>);

/// The variant that evaluates `brdf`.
pub(super) fn variant(brdf: &Brdf) -> Variant {
    (brdf_id(brdf), analytic_shader(brdf))
}

/// A probe shader: its module and layout, each analytic model's module, and its pipeline for each variant
/// built so far.
pub(super) struct Shader {
    file: &'static str,
    /// Whether an analytic model is compiled in double precision (its `glsl_double`).
    double: bool,
    /// The BRDF evaluations an item takes (a case one, a cell 15 x 15).
    evaluations: usize,
    module: ShaderModule,
    analytic_modules: HashMap<AnalyticShader, ShaderModule>,
    layout: Arc<PipelineLayout>,
    pipelines: HashMap<Variant, Pipeline>,
}

impl Shader {
    /// Compiles `file`, whose layout has `bindings` storage buffers and `push_constants` u32 of push constants.
    pub(super) fn new(
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        (file, evaluations): (&'static str, usize),
        (bindings, push_constants): (u32, u32),
    ) -> Result<Self> {
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
        let push =
            [vk::PushConstantRange { stage_flags: vk::ShaderStageFlags::COMPUTE, offset: 0, size: 4 * push_constants }];
        let layout = device.create_pipeline_layout(&[&bindings], &push, &format!("{file} layout"))?;
        let analytic_modules = HashMap::new();
        Ok(Self { file, double: false, evaluations, module, analytic_modules, layout, pipelines: HashMap::new() })
    }

    /// The same shader, its analytic models compiled in double precision (for `brdf_density64.comp`).
    pub(super) fn with_double_models(self) -> Self {
        Self { double: true, ..self }
    }

    /// The pipeline for `variant`, built on first use (an analytic model's shader compiled by `compiler`).
    pub(super) fn pipeline(
        &mut self,
        device: &Arc<Device>,
        compiler: &ShaderCompiler,
        variant: &Variant,
    ) -> Result<&Pipeline> {
        if !self.pipelines.contains_key(variant) {
            let (brdf, analytic) = variant;
            let module = match analytic {
                None => &self.module,
                Some(model) => {
                    if !self.analytic_modules.contains_key(model) {
                        let glsl = if self.double { model.0.glsl_double() } else { model.0.glsl() };
                        let spirv = compiler.compile_analytic(self.file, glsl)?;
                        let name = format!("{} of {}", self.file, model.0.name());
                        self.analytic_modules.insert(model.clone(), device.create_shader_module(&spirv, &name)?);
                    }
                    &self.analytic_modules[model]
                }
            };
            let name = format!("{} for BRDF {brdf}", self.file);
            let pipeline = device.create_compute_pipeline(module, &self.layout, &[*brdf], &name)?;
            self.pipelines.insert(variant.clone(), pipeline);
        }
        Ok(&self.pipelines[variant])
    }
}

/// What every dispatch of the probe binds besides its own buffers, the materials' data (its last bindings:
/// the analytic models' reports add up over the dispatches), and the compiler of the analytic models'
/// shaders.
#[derive(Clone, Copy)]
pub struct ProbeContext<'a> {
    pub data: MaterialData<'a>,
    pub compiler: &'a ShaderCompiler,
}

impl ProbePass {
    /// Compiles `brdf_probe.comp`, `brdf_albedo.comp` and `brdf_sample.comp`; their pipelines are built when
    /// first used.
    ///
    /// # Errors
    /// `Error::Shader` or `Error::Vulkan`.
    pub fn new(device: &Arc<Device>, compiler: &ShaderCompiler) -> Result<Self> {
        Ok(Self {
            eval: Shader::new(device, compiler, ("brdf_probe.comp", 1), (6, 3))?,
            albedo: Shader::new(device, compiler, ("brdf_albedo.comp", 15 * 15), (6, 1))?,
            sampler: Shader::new(device, compiler, ("brdf_sample.comp", 1), (6, 4))?,
            density64: None,
            without_double: std::collections::HashSet::new(),
            device: device.clone(),
        })
    }

    /// Evaluates every case on the GPU, their materials' data in `context`.
    ///
    /// # Errors
    /// `Error::Shader` if an analytic model's shader does not compile, `Error::Vulkan` or `Error::Allocation`.
    pub fn run(&mut self, cases: &[ProbeCase], context: ProbeContext) -> Result<Vec<Vec3>> {
        let mut results = vec![Vec3::ZERO; cases.len()];
        // A list holds a material and directions a case, each buffer within the device's range.
        let per_buffer = per_buffer::<GpuMaterial>(&self.device).min(per_buffer::<ListDirections>(&self.device));
        for (variant, indices) in by_variant(cases.iter().map(|c| &c.brdf)) {
            for chunk in indices.chunks(per_buffer) {
                let materials: Vec<_> = chunk.iter().map(|&i| GpuMaterial::new(&cases[i].brdf, context.data)).collect();
                let directions: Vec<_> =
                    chunk.iter().map(|&i| list_directions(cases[i].n, cases[i].wi, cases[i].wo)).collect();
                let directions = self.directions_buffer(&directions)?;
                let values = self.evaluate(&variant, &materials, (&directions, None), context)?;
                for (&i, value) in chunk.iter().zip(values) {
                    results[i] = value;
                }
            }
        }
        Ok(results)
    }

    /// f_r of every material of `brdfs` at every (wi, wo) of `pairs`, in the frame n = +z: material m's at pair
    /// d is element m * pairs.len() + d. As [`ProbePass::run`] of every combination, but the directions are
    /// uploaded once and each material once, which a fit's lobes at one set of directions asks for.
    ///
    /// # Errors
    /// As [`ProbePass::run`].
    pub fn run_grid(&mut self, brdfs: &[Brdf], pairs: &[(Vec3, Vec3)], context: ProbeContext) -> Result<Vec<Vec3>> {
        let mut results = vec![Vec3::ZERO; brdfs.len() * pairs.len()];
        let groups = by_variant(brdfs.iter());
        let mut done = 0;
        for part in pairs.chunks(per_buffer::<GridDirections>(&self.device)) {
            let directions: Vec<_> = part.iter().map(|&(wi, wo)| grid_directions(wi, wo)).collect();
            let directions = self.directions_buffer(&directions)?;
            for (variant, indices) in &groups {
                let materials: Vec<_> = indices.iter().map(|&m| GpuMaterial::new(&brdfs[m], context.data)).collect();
                let values = self.evaluate(variant, &materials, (&directions, Some(part.len())), context)?;
                for (&m, lobe) in indices.iter().zip(values.chunks_exact(part.len())) {
                    let at = m * pairs.len() + done;
                    results[at..at + part.len()].copy_from_slice(lobe);
                }
            }
            done += part.len();
        }
        Ok(results)
    }

    fn directions_buffer<T: Copy>(&self, directions: &[T]) -> Result<Buffer> {
        self.device.create_buffer_with_data(directions, vk::BufferUsageFlags::STORAGE_BUFFER, "probe directions")
    }

    /// `brdf_probe.comp` with `variant`'s pipeline: each of `materials` at its own directions of the buffer (a
    /// list: `grid` None), or at each of the buffer's `grid` directions, in dispatches of at most
    /// [`EVALUATIONS_PER_DISPATCH`] cases.
    fn evaluate(
        &mut self,
        variant: &Variant,
        materials: &[GpuMaterial],
        (directions, grid): (&Buffer, Option<usize>),
        context: ProbeContext,
    ) -> Result<Vec<Vec3>> {
        let total = materials.len() * grid.unwrap_or(1);
        if total == 0 {
            return Ok(Vec::new());
        }
        let grid = push_constant(grid.unwrap_or(0))?;
        let materials =
            self.device.create_buffer_with_data(materials, vk::BufferUsageFlags::STORAGE_BUFFER, "probe materials")?;
        let per_dispatch = EVALUATIONS_PER_DISPATCH.min(per_buffer::<GpuResult>(&self.device));
        let pipeline = self.eval.pipeline(&self.device, context.compiler, variant)?;
        let size = std::mem::size_of::<GpuResult>();
        let mut values = Vec::with_capacity(total);
        for first in (0..total).step_by(per_dispatch) {
            let count = per_dispatch.min(total - first);
            let push = [push_constant(count)?, push_constant(first)?, grid];
            let bytes = dispatch(&self.device, pipeline, &[&materials, directions], context.data, size, &push)?;
            values.extend(read_vec3s(&bytes, size));
        }
        Ok(values)
    }

    /// Integrates f_r cos(theta_i) over every cell on the GPU, the jobs' materials' data in `context`.
    ///
    /// # Errors
    /// As [`ProbePass::run`].
    pub fn integrate(
        &mut self,
        jobs: &[AlbedoJob],
        cells: &[Cell],
        context: ProbeContext,
    ) -> Result<Vec<CellEstimate>> {
        let gpu_jobs: Vec<GpuAlbedoJob> = jobs
            .iter()
            .map(|job| GpuAlbedoJob {
                material: GpuMaterial::new(&job.brdf, context.data),
                wo: job.wo.extend(0.0).into(),
            })
            .collect();
        let jobs_buffer =
            self.device.create_buffer_with_data(&gpu_jobs, vk::BufferUsageFlags::STORAGE_BUFFER, "albedo jobs")?;
        let brdf_of = |cell: &Cell| &jobs[cell.job].brdf;
        let element = |cell: &Cell| GpuAlbedoCell {
            bounds: [cell.theta.0, cell.theta.1, cell.phi.0, cell.phi.1].map(|bound| bound as f32),
            job: cell.job as u32,
            pad: [0; 3],
        };
        let bytes = run_by_brdf(&self.device, &mut self.albedo, cells, brdf_of, element, &[&jobs_buffer], context, 32)?;
        let estimates = read_vec3s(&bytes, 16);
        Ok(estimates
            .chunks_exact(2)
            .map(|pair| CellEstimate { kronrod: pair[0].to_array(), gauss: pair[1].to_array() })
            .collect())
    }
}

/// Runs `shader` once per item: the items of each BRDF (`brdf_of`) with that BRDF's pipeline, in chunks of
/// what one storage buffer may hold (`maxStorageBufferRange`: 128 MiB on lavapipe) and of at most
/// [`EVALUATIONS_PER_DISPATCH`] BRDF evaluations, each chunk's elements (`element`) bound after `inputs`.
/// Returns every item's `result_size` bytes of results, in the items' order.
#[allow(clippy::too_many_arguments)] // one dispatch's whole description, for either probe
fn run_by_brdf<'a, T, G: Copy>(
    device: &Arc<Device>,
    shader: &mut Shader,
    items: &[T],
    brdf_of: impl Fn(&T) -> &'a Brdf,
    element: impl Fn(&T) -> G,
    inputs: &[&Buffer],
    context: ProbeContext,
    result_size: usize,
) -> Result<Vec<u8>> {
    let groups = by_variant(items.iter().map(brdf_of));
    let per_dispatch = per_buffer::<G>(device).min(EVALUATIONS_PER_DISPATCH / shader.evaluations).max(1);
    let mut results = vec![0u8; items.len() * result_size];
    for (brdf, indices) in groups {
        for chunk in indices.chunks(per_dispatch) {
            let elements: Vec<G> = chunk.iter().map(|&i| element(&items[i])).collect();
            let input = device.create_buffer_with_data(&elements, vk::BufferUsageFlags::STORAGE_BUFFER, shader.file)?;
            let buffers: Vec<&Buffer> = inputs.iter().copied().chain([&input]).collect();
            let pipeline = shader.pipeline(device, context.compiler, &brdf)?;
            let bytes =
                dispatch(device, pipeline, &buffers, context.data, result_size, &[push_constant(chunk.len())?])?;
            for (&i, result) in chunk.iter().zip(bytes.chunks_exact(result_size)) {
                results[i * result_size..(i + 1) * result_size].copy_from_slice(result);
            }
        }
    }
    Ok(results)
}

/// Runs `pipeline` `push[0]` times (its push constants `push`, the first of which is the count) over `inputs`
/// (its first bindings), a results buffer of `result_size` bytes per run (the next), the measured tables, and
/// the analytic values and report (the last), and returns the results' bytes.
pub(super) fn dispatch(
    device: &Arc<Device>,
    pipeline: &Pipeline,
    inputs: &[&Buffer],
    data: MaterialData,
    result_size: usize,
    push: &[u32],
) -> Result<Vec<u8>> {
    let count = push[0] as usize;
    if count == 0 {
        return Ok(Vec::new());
    }
    let output = device.create_buffer(
        BufferDesc {
            size: (count * result_size) as u64,
            usage: vk::BufferUsageFlags::STORAGE_BUFFER,
            location: MemoryLocation::GpuToCpu,
        },
        "probe results",
    )?;
    let buffers: Vec<&Buffer> = inputs
        .iter()
        .copied()
        .chain([&output, data.measured.buffer(), data.analytic.values(), data.analytic.reports()])
        .collect();
    let pool = device.create_descriptor_pool(
        1,
        &[vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: buffers.len() as u32 }],
    )?;
    let layout = &pipeline.layout;
    let descriptors: Vec<Descriptor> =
        buffers.iter().map(|buffer| Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, buffer)).collect();
    let set = pool.allocate_set(layout.set_layouts[0], &descriptors)?;
    let push_bytes: Vec<u8> = push.iter().flat_map(|v| v.to_ne_bytes()).collect();
    device.submit_and_wait(|cmd| {
        // SAFETY: every handle recorded here lives until submit_and_wait has waited for the work.
        unsafe {
            device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::COMPUTE, pipeline.raw);
            device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::COMPUTE, layout.raw, 0, &[set], &[]);
            device.raw.cmd_push_constants(cmd, layout.raw, vk::ShaderStageFlags::COMPUTE, 0, &push_bytes);
            device.raw.cmd_dispatch(cmd, push[0].div_ceil(WORKGROUP_SIZE), 1, 1);
        }
        output.record_host_read_barrier(
            cmd,
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        data.analytic.record_host_read_barrier(cmd, vk::PipelineStageFlags2::COMPUTE_SHADER);
        Ok(())
    })?;
    Ok(output.bytes()?.to_vec())
}

/// How many elements of `T` one storage buffer may hold (`maxStorageBufferRange`: 128 MiB on lavapipe).
pub(super) fn per_buffer<T>(device: &Device) -> usize {
    (device.limits.max_storage_buffer_range as usize / std::mem::size_of::<T>()).max(1)
}

/// `n` as a push constant, which is 32 bits: a count past them is more than any buffer holds.
pub(super) fn push_constant(n: usize) -> Result<u32> {
    u32::try_from(n).map_err(|_| Error::Vulkan(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY))
}

/// The indices of `brdfs` by the variant that evaluates each.
fn by_variant<'a>(brdfs: impl Iterator<Item = &'a Brdf>) -> BTreeMap<Variant, Vec<usize>> {
    let mut groups: BTreeMap<Variant, Vec<usize>> = BTreeMap::new();
    for (index, brdf) in brdfs.enumerate() {
        groups.entry(variant(brdf)).or_default().push(index);
    }
    groups
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
