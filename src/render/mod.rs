//! The offscreen renderer: a scene in, a linear HDR image out, through Vulkan.

mod forward;
pub mod gpu_types;
mod probe;

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::mesh::{place_objects, Mesh, PlacedMesh};
use crate::output::HdrImage;
use crate::scene::Scene;
use crate::vulkan::{
    subresource_range, Buffer, BufferDesc, Device, DeviceInfo, Image, ImageDesc, Instance, ShaderCompiler,
    ShaderSources,
};
use forward::{ForwardPass, COLOR_FORMAT, DEPTH_FORMAT};
use gpu_types::{GpuFrame, GpuObject, GpuPointLight};
pub use probe::ProbeCase;
use probe::{read_vec3s, ProbePass};

/// The near plane's distance: with reverse-Z float depth the precision does not depend on it.
const NEAR_PLANE: f32 = 1e-3;

/// How to open the renderer.
#[derive(Clone, Debug, Default)]
pub struct RendererOptions {
    /// A device index or part of its name (see `vk-render devices`); `None` picks the best.
    pub device: Option<String>,
    /// Turn the Khronos validation layer on; every render then fails on any message.
    pub validate: bool,
    /// The GLSL to compile; the sources embedded at build time by default.
    pub shaders: ShaderSources,
}

/// A Vulkan device with the forward pass's shaders compiled and pipelines built once, reused for every image.
pub struct Renderer {
    forward: ForwardPass,
    /// Built on first use: only the BRDF tests need it.
    probe: Option<ProbePass>,
    compiler: ShaderCompiler,
    device: Arc<Device>,
}

impl Renderer {
    /// Opens Vulkan, chooses the device and compiles the shaders.
    ///
    /// # Errors
    /// `Error::NoVulkan` with installation advice, `Error::Device`, `Error::Shader` or `Error::Vulkan`.
    pub fn new(options: RendererOptions) -> Result<Self> {
        let instance = Arc::new(Instance::new(options.validate)?);
        let device = Device::new(instance, options.device.as_deref())?;
        let compiler = ShaderCompiler::new(options.shaders)?;
        let forward = ForwardPass::new(&device, &compiler)?;
        let renderer = Self { forward, probe: None, compiler, device };
        renderer.check_validation()?;
        Ok(renderer)
    }

    /// The device in use.
    pub fn device_info(&self) -> &DeviceInfo {
        &self.device.info
    }

    /// The MSAA sample counts this device can render the forward pass with.
    pub fn supported_sample_counts(&self) -> Vec<u32> {
        let limits = &self.device.limits;
        let counts = limits.framebuffer_color_sample_counts & limits.framebuffer_depth_sample_counts;
        // SAFETY: a plain query on a live physical device.
        let format_counts = unsafe {
            self.device.instance.raw.get_physical_device_image_format_properties(
                self.device.physical,
                COLOR_FORMAT,
                vk::ImageType::TYPE_2D,
                vk::ImageTiling::OPTIMAL,
                vk::ImageUsageFlags::COLOR_ATTACHMENT,
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
        self.check_image_settings(scene)?;
        let placed = place_objects(scene)?;
        let image = self.draw(scene, &placed)?;
        self.check_validation()?;
        Ok(image)
    }

    /// Evaluates `brdf_eval` of the GLSL on the GPU for every case (the probe pass), as float32.
    ///
    /// # Errors
    /// `Error::Shader`, `Error::Vulkan` or `Error::Allocation`; `Error::Validation` if the layer complained.
    pub fn probe_brdfs(&mut self, cases: &[ProbeCase]) -> Result<Vec<Vec3>> {
        let probe = match self.probe.take() {
            Some(probe) => probe,
            None => ProbePass::new(&self.device, &self.compiler)?,
        };
        let results = probe.run(cases);
        self.probe = Some(probe);
        let results = results?;
        self.check_validation()?;
        Ok(results)
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

    fn draw(&mut self, scene: &Scene, placed: &[PlacedMesh]) -> Result<HdrImage> {
        let device = self.device.clone();
        let (width, height) = (scene.image.width, scene.image.height);
        let samples = vk::SampleCountFlags::from_raw(scene.image.samples);
        let multisampled = samples != vk::SampleCountFlags::TYPE_1;

        // Scene data.
        let frame = GpuFrame::new(&scene.camera, width as f32 / height as f32, &scene.lights, NEAR_PLANE);
        let lights: Vec<GpuPointLight> = scene.lights.iter().map(GpuPointLight::from).collect();
        let objects: Vec<GpuObject> =
            scene.objects.iter().zip(placed).map(|(object, p)| GpuObject::new(object, p.model)).collect();
        let frame_buffer = device.create_buffer_with_data(&[frame], vk::BufferUsageFlags::UNIFORM_BUFFER, "frame")?;
        // An empty storage buffer is not allowed: a scene without lights still binds one (unread) element.
        let lights_buffer = device.create_buffer_with_data(
            if lights.is_empty() { &[GpuPointLight { position: [0.0; 4], radiance: [0.0; 4] }] } else { &lights },
            vk::BufferUsageFlags::STORAGE_BUFFER,
            "lights",
        )?;
        let objects_buffer = if objects.is_empty() {
            device.create_buffer(
                BufferDesc {
                    size: std::mem::size_of::<GpuObject>() as u64,
                    usage: vk::BufferUsageFlags::STORAGE_BUFFER,
                    location: MemoryLocation::CpuToGpu,
                },
                "objects",
            )?
        } else {
            device.create_buffer_with_data(&objects, vk::BufferUsageFlags::STORAGE_BUFFER, "objects")?
        };
        let meshes = upload_meshes(&device, placed)?;

        let pool = device.create_descriptor_pool(
            1,
            &[
                vk::DescriptorPoolSize { ty: vk::DescriptorType::UNIFORM_BUFFER, descriptor_count: 1 },
                vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: 2 },
            ],
        )?;
        let set = pool.allocate_buffer_set(
            self.forward.layout.set_layouts[0],
            &[
                (vk::DescriptorType::UNIFORM_BUFFER, &frame_buffer),
                (vk::DescriptorType::STORAGE_BUFFER, &lights_buffer),
                (vk::DescriptorType::STORAGE_BUFFER, &objects_buffer),
            ],
        )?;

        // Targets: the multisampled colour and depth, and the single-sample image they resolve to.
        let attachment = |format, samples, usage, aspect| ImageDesc { width, height, format, samples, usage, aspect };
        let resolved = device.create_image(
            attachment(
                COLOR_FORMAT,
                vk::SampleCountFlags::TYPE_1,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                vk::ImageAspectFlags::COLOR,
            ),
            "resolved colour",
        )?;
        let multisampled_color = if multisampled {
            Some(device.create_image(
                attachment(COLOR_FORMAT, samples, vk::ImageUsageFlags::COLOR_ATTACHMENT, vk::ImageAspectFlags::COLOR),
                "multisampled colour",
            )?)
        } else {
            None
        };
        let depth = device.create_image(
            attachment(
                DEPTH_FORMAT,
                samples,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                vk::ImageAspectFlags::DEPTH,
            ),
            "depth",
        )?;
        let readback = device.create_buffer(
            BufferDesc {
                size: u64::from(width) * u64::from(height) * 16,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
            },
            "readback",
        )?;

        let pipeline = self.forward.pipeline(samples)?;
        let layout = pipeline.layout.raw;
        let pipeline = pipeline.raw;
        let background = scene.image.background;
        device.submit_and_wait(|cmd| {
            let raw = &device.raw;
            let color_target = multisampled_color.as_ref().unwrap_or(&resolved);
            let mut to_attachment = vec![
                image_barrier(
                    &resolved,
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                    (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
                    (vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT, vk::AccessFlags2::COLOR_ATTACHMENT_WRITE),
                ),
                image_barrier(
                    &depth,
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                    (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
                    (
                        vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                        vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                    ),
                ),
            ];
            if let Some(msaa) = &multisampled_color {
                to_attachment.push(image_barrier(
                    msaa,
                    vk::ImageLayout::UNDEFINED,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                    (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
                    (vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT, vk::AccessFlags2::COLOR_ATTACHMENT_WRITE),
                ));
            }
            // SAFETY: every handle recorded here lives until submit_and_wait has waited for the work.
            unsafe {
                raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_attachment));

                let mut color = vk::RenderingAttachmentInfo::default()
                    .image_view(color_target.view)
                    .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::STORE)
                    .clear_value(vk::ClearValue {
                        color: vk::ClearColorValue { float32: [background.x, background.y, background.z, 1.0] },
                    });
                if multisampled {
                    // The float resolve averages the samples, as the course averages its pixel samples.
                    color = color
                        .resolve_mode(vk::ResolveModeFlags::AVERAGE)
                        .resolve_image_view(resolved.view)
                        .resolve_image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
                        .store_op(vk::AttachmentStoreOp::DONT_CARE);
                }
                let colors = [color];
                let depth_attachment = vk::RenderingAttachmentInfo::default()
                    .image_view(depth.view)
                    .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
                    .load_op(vk::AttachmentLoadOp::CLEAR)
                    .store_op(vk::AttachmentStoreOp::DONT_CARE)
                    .clear_value(vk::ClearValue {
                        depth_stencil: vk::ClearDepthStencilValue { depth: 0.0, stencil: 0 },
                    });
                let area = vk::Rect2D { offset: vk::Offset2D::default(), extent: vk::Extent2D { width, height } };
                let rendering = vk::RenderingInfo::default()
                    .render_area(area)
                    .layer_count(1)
                    .color_attachments(&colors)
                    .depth_attachment(&depth_attachment);
                raw.cmd_begin_rendering(cmd, &rendering);
                raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, pipeline);
                raw.cmd_set_viewport(
                    cmd,
                    0,
                    &[vk::Viewport {
                        x: 0.0,
                        y: 0.0,
                        width: width as f32,
                        height: height as f32,
                        min_depth: 0.0,
                        max_depth: 1.0,
                    }],
                );
                raw.cmd_set_scissor(cmd, 0, &[area]);
                raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, layout, 0, &[set], &[]);
                for (index, p) in placed.iter().enumerate() {
                    let mesh = &meshes[&mesh_key(&p.mesh)];
                    raw.cmd_bind_vertex_buffers(cmd, 0, &[mesh.vertices.raw], &[0]);
                    raw.cmd_bind_index_buffer(cmd, mesh.indices.raw, 0, vk::IndexType::UINT32);
                    raw.cmd_push_constants(
                        cmd,
                        layout,
                        vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT,
                        0,
                        &(index as u32).to_ne_bytes(),
                    );
                    raw.cmd_draw_indexed(cmd, mesh.index_count, 1, 0, 0, 0);
                }
                raw.cmd_end_rendering(cmd);

                let to_transfer = [image_barrier(
                    &resolved,
                    vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    (vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT, vk::AccessFlags2::COLOR_ATTACHMENT_WRITE),
                    (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_READ),
                )];
                raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().image_memory_barriers(&to_transfer));
                let region = vk::BufferImageCopy::default()
                    .image_subresource(vk::ImageSubresourceLayers {
                        aspect_mask: vk::ImageAspectFlags::COLOR,
                        mip_level: 0,
                        base_array_layer: 0,
                        layer_count: 1,
                    })
                    .image_extent(vk::Extent3D { width, height, depth: 1 });
                raw.cmd_copy_image_to_buffer(
                    cmd,
                    resolved.raw,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    readback.raw,
                    &[region],
                );
            }
            readback.record_host_read_barrier(cmd, vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_WRITE);
            Ok(())
        })?;

        Ok(HdrImage { width, height, pixels: read_vec3s(readback.bytes()?, 16) })
    }
}

/// A mesh's vertex and index buffers on the device.
struct GpuMesh {
    vertices: Buffer,
    indices: Buffer,
    index_count: u32,
}

/// Meshes are shared between objects (every sphere uses the one unit sphere): key them by address.
fn mesh_key(mesh: &Arc<Mesh>) -> usize {
    Arc::as_ptr(mesh) as usize
}

fn upload_meshes(device: &Arc<Device>, placed: &[PlacedMesh]) -> Result<HashMap<usize, GpuMesh>> {
    let mut meshes = HashMap::new();
    for p in placed {
        if meshes.contains_key(&mesh_key(&p.mesh)) {
            continue;
        }
        let vertices =
            device.create_buffer_with_data(&p.mesh.vertices, vk::BufferUsageFlags::VERTEX_BUFFER, "vertices")?;
        let indices = device.create_buffer_with_data(&p.mesh.indices, vk::BufferUsageFlags::INDEX_BUFFER, "indices")?;
        let index_count =
            u32::try_from(p.mesh.indices.len()).map_err(|_| Error::Vulkan(vk::Result::ERROR_OUT_OF_DEVICE_MEMORY))?;
        meshes.insert(mesh_key(&p.mesh), GpuMesh { vertices, indices, index_count });
    }
    Ok(meshes)
}

/// A layout transition of a whole single-mip image, with its source and destination (stage, access).
fn image_barrier(
    image: &Image,
    old: vk::ImageLayout,
    new: vk::ImageLayout,
    src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)
        .old_layout(old)
        .new_layout(new)
        .image(image.raw)
        .subresource_range(subresource_range(image.desc.aspect))
}
