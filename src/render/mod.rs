//! The offscreen renderer: a scene in, a linear HDR image out, through Vulkan.

mod forward;
pub mod gpu_types;
mod passes;
mod probe;
mod shadow;

use std::sync::Arc;

use ash::vk;
use glam::Vec3;
use gpu_allocator::MemoryLocation;

use crate::error::{Error, Result};
use crate::mesh::{place_objects, PlacedMesh};
use crate::output::HdrImage;
use crate::scene::Scene;
use crate::vulkan::{
    whole_image_copy, Access, BufferDesc, Descriptor, Device, DeviceInfo, ImageDesc, Instance, PipelineLayout, Sampler,
    ShaderCompiler, ShaderSources,
};
use forward::{ForwardPass, COLOR_FORMAT, DEPTH_FORMAT};
use gpu_types::{GpuFrame, GpuObject, GpuPointLight};
use passes::{barriers, draw_objects, image_barrier, upload_meshes, PassTargets};
pub use probe::ProbeCase;
use probe::{read_vec3s, ProbePass};
use shadow::{cube_face_views, ShadowPass, DISTANCE_FORMAT};

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
    /// Extra instance extensions (a window surface's, for the preview).
    pub instance_extensions: Vec<&'static std::ffi::CStr>,
    /// Extra device extensions (the swapchain's, for the preview).
    pub device_extensions: Vec<&'static std::ffi::CStr>,
}

/// A Vulkan device with the forward pass's shaders compiled and pipelines built once, reused for every image.
pub struct Renderer {
    /// The one descriptor set layout and push constants of the shadow and forward passes.
    layout: Arc<PipelineLayout>,
    shadow: ShadowPass,
    shadow_sampler: Sampler,
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
        let instance = Arc::new(Instance::new(options.validate, &options.instance_extensions)?);
        Self::on_instance(instance, options, None)
    }

    /// As [`Renderer::new`], on an instance already made (the preview's, which made its window's surface
    /// with it); with `present_to`, the device chosen is one whose queue can also present to that surface.
    ///
    /// # Errors
    /// As [`Renderer::new`].
    pub fn on_instance(
        instance: Arc<Instance>,
        options: RendererOptions,
        present_to: Option<(&ash::khr::surface::Instance, vk::SurfaceKHR)>,
    ) -> Result<Self> {
        let device = Device::new(instance, options.device.as_deref(), &options.device_extensions, present_to)?;
        device.require_format(
            COLOR_FORMAT,
            vk::FormatFeatureFlags::COLOR_ATTACHMENT | vk::FormatFeatureFlags::TRANSFER_SRC,
            "the forward pass's colour target",
        )?;
        device.require_format(DEPTH_FORMAT, vk::FormatFeatureFlags::DEPTH_STENCIL_ATTACHMENT, "depth")?;
        device.require_format(
            DISTANCE_FORMAT,
            vk::FormatFeatureFlags::COLOR_ATTACHMENT | vk::FormatFeatureFlags::SAMPLED_IMAGE,
            "the shadow cubes' distances",
        )?;
        let compiler = ShaderCompiler::new(options.shaders)?;
        let layout = scene_layout(&device)?;
        let shadow = ShadowPass::new(&device, &compiler, &layout)?;
        let forward = ForwardPass::new(&device, &compiler, &layout)?;
        let shadow_sampler = device.create_nearest_sampler("shadow cubes")?;
        let renderer = Self { layout, shadow, shadow_sampler, forward, probe: None, compiler, device };
        renderer.check_validation()?;
        Ok(renderer)
    }

    /// The device, for what shares it (the preview's swapchain).
    pub fn device(&self) -> &Arc<Device> {
        &self.device
    }

    /// Recompiles every pass from `shaders`; on any error the passes in use are kept.
    ///
    /// # Errors
    /// `Error::Shader` naming the file and line, or `Error::Vulkan`.
    pub fn set_shaders(&mut self, shaders: ShaderSources) -> Result<()> {
        let compiler = ShaderCompiler::new(shaders)?;
        let shadow = ShadowPass::new(&self.device, &compiler, &self.layout)?;
        let forward = ForwardPass::new(&self.device, &compiler, &self.layout)?;
        // Pipelines of the old passes may still be referenced by work in flight: renders wait for theirs.
        self.shadow = shadow;
        self.forward = forward;
        self.probe = None;
        self.compiler = compiler;
        self.check_validation()
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
        let max_cube = self.device.limits.max_image_dimension_cube;
        if scene.image.shadow_map_size > max_cube {
            return Err(error(format!(
                "image.shadow_map_size = {}: above the limit of {max_cube} texels of {device}",
                scene.image.shadow_map_size
            )));
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

        // Scene data. Each light that casts shadows gets the next cube of the shadow cube array.
        let shadow_casters: Vec<usize> = (0..scene.lights.len()).filter(|&i| scene.lights[i].shadows).collect();
        let frame =
            GpuFrame::new(&scene.camera, width as f32 / height as f32, &scene.image, scene.lights.len(), NEAR_PLANE);
        let lights: Vec<GpuPointLight> = scene
            .lights
            .iter()
            .enumerate()
            .map(|(i, light)| GpuPointLight::new(light, shadow_casters.iter().position(|&c| c == i)))
            .collect();
        let objects: Vec<GpuObject> =
            scene.objects.iter().zip(placed).map(|(object, p)| GpuObject::new(object, p.model)).collect();
        let shadow_views: Vec<[[f32; 4]; 4]> = shadow_casters
            .iter()
            .flat_map(|&i| cube_face_views(scene.lights[i].position, NEAR_PLANE))
            .map(|m| m.to_cols_array_2d())
            .collect();
        let frame_buffer = device.create_buffer_with_data(&[frame], vk::BufferUsageFlags::UNIFORM_BUFFER, "frame")?;
        // Storage buffers may not be empty: a scene without lights or objects binds one unread element.
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let lights_buffer = device.create_buffer_with_data(&non_empty(&lights), storage, "lights")?;
        let objects_buffer = device.create_buffer_with_data(&non_empty(&objects), storage, "objects")?;
        let views_buffer = device.create_buffer_with_data(&non_empty(&shadow_views), storage, "shadow views")?;
        let meshes = upload_meshes(&device, placed)?;

        // Shadow cubes: one per casting light (a single unused 1-texel cube when none casts), and one depth
        // image reused by every face in turn.
        let shadow_size = if shadow_casters.is_empty() { 1 } else { scene.image.shadow_map_size };
        let cube_layers = 6 * shadow_casters.len().max(1) as u32;
        let shadow_maps = device.create_image(
            ImageDesc {
                width: shadow_size,
                height: shadow_size,
                layers: cube_layers,
                cube: true,
                format: DISTANCE_FORMAT,
                samples: vk::SampleCountFlags::TYPE_1,
                usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                aspect: vk::ImageAspectFlags::COLOR,
            },
            "shadow cubes",
        )?;
        let shadow_depth = device.create_image(
            ImageDesc::plain(
                shadow_size,
                shadow_size,
                DEPTH_FORMAT,
                vk::SampleCountFlags::TYPE_1,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                vk::ImageAspectFlags::DEPTH,
            ),
            "shadow depth",
        )?;
        // One view per face of each cube, in the order the faces are drawn.
        let face_views = (0..6 * shadow_casters.len() as u32)
            .map(|layer| shadow_maps.layer_view(layer, 1))
            .collect::<Result<Vec<_>>>()?;

        let pool = device.create_descriptor_pool(
            1,
            &[
                vk::DescriptorPoolSize { ty: vk::DescriptorType::UNIFORM_BUFFER, descriptor_count: 1 },
                vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: 3 },
                vk::DescriptorPoolSize { ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER, descriptor_count: 1 },
            ],
        )?;
        let set = pool.allocate_set(
            self.layout.set_layouts[0],
            &[
                Descriptor::Buffer(vk::DescriptorType::UNIFORM_BUFFER, &frame_buffer),
                Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &lights_buffer),
                Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &objects_buffer),
                Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &views_buffer),
                Descriptor::SampledImage(
                    shadow_maps.view,
                    &self.shadow_sampler,
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                ),
            ],
        )?;

        // Targets: the multisampled colour and depth, and the single-sample image they resolve to.
        let target = |format, samples, usage, aspect| ImageDesc::plain(width, height, format, samples, usage, aspect);
        let resolved = device.create_image(
            target(
                COLOR_FORMAT,
                vk::SampleCountFlags::TYPE_1,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                vk::ImageAspectFlags::COLOR,
            ),
            "resolved colour",
        )?;
        let multisampled = if samples == vk::SampleCountFlags::TYPE_1 {
            None
        } else {
            Some(device.create_image(
                target(COLOR_FORMAT, samples, vk::ImageUsageFlags::COLOR_ATTACHMENT, vk::ImageAspectFlags::COLOR),
                "multisampled colour",
            )?)
        };
        let depth = device.create_image(
            target(DEPTH_FORMAT, samples, vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT, vk::ImageAspectFlags::DEPTH),
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

        let layout = self.layout.raw;
        let shadow_pipeline = self.shadow.pipeline.raw;
        let forward_pipeline = self.forward.pipeline(samples)?.raw;
        let b = scene.image.background;
        device.submit_and_wait(|cmd| {
            // SAFETY: every handle recorded here lives until submit_and_wait has waited for the work.
            unsafe {
                device.raw.cmd_bind_descriptor_sets(cmd, vk::PipelineBindPoint::GRAPHICS, layout, 0, &[set], &[]);
            }

            // Shadow cubes, one light at a time, then ready to be sampled.
            let cubes_to_read = if shadow_casters.is_empty() {
                image_barrier(&shadow_maps, vk::ImageLayout::UNDEFINED, READ_ONLY, NOTHING, SAMPLED)
            } else {
                barriers(
                    &device,
                    cmd,
                    &[image_barrier(&shadow_maps, vk::ImageLayout::UNDEFINED, COLOR_TARGET, NOTHING, COLOR_WRITE)],
                );
                // SAFETY: as above.
                unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, shadow_pipeline) };
                let faces = shadow_casters.iter().flat_map(|&light| (0..6u32).map(move |face| (light as u32, face)));
                for (face_view, light_face) in face_views.iter().zip(faces) {
                    // The depth image is cleared for each face: the previous face's tests must be over first.
                    barriers(
                        &device,
                        cmd,
                        &[image_barrier(
                            &shadow_depth,
                            vk::ImageLayout::UNDEFINED,
                            DEPTH_TARGET,
                            DEPTH_TESTS,
                            DEPTH_TESTS,
                        )],
                    );
                    let targets = PassTargets {
                        color: face_view.raw,
                        resolve: None,
                        depth: shadow_depth.view,
                        width: shadow_size,
                        height: shadow_size,
                    };
                    shadow::begin(&device, cmd, &targets);
                    draw_objects(&device, cmd, layout, &targets, placed, &meshes, light_face);
                    // SAFETY: as above.
                    unsafe { device.raw.cmd_end_rendering(cmd) };
                }
                image_barrier(&shadow_maps, COLOR_TARGET, READ_ONLY, COLOR_WRITE, SAMPLED)
            };

            // The forward pass.
            let mut to_targets = vec![
                cubes_to_read,
                image_barrier(&resolved, vk::ImageLayout::UNDEFINED, COLOR_TARGET, NOTHING, COLOR_WRITE),
                image_barrier(&depth, vk::ImageLayout::UNDEFINED, DEPTH_TARGET, NOTHING, DEPTH_TESTS),
            ];
            if let Some(image) = &multisampled {
                to_targets.push(image_barrier(image, vk::ImageLayout::UNDEFINED, COLOR_TARGET, NOTHING, COLOR_WRITE));
            }
            barriers(&device, cmd, &to_targets);
            let targets = PassTargets {
                color: multisampled.as_ref().unwrap_or(&resolved).view,
                resolve: multisampled.as_ref().map(|_| resolved.view),
                depth: depth.view,
                width,
                height,
            };
            forward::begin(&device, cmd, &targets, [b.x, b.y, b.z, 1.0]);
            // SAFETY: as above.
            unsafe { device.raw.cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, forward_pipeline) };
            draw_objects(&device, cmd, layout, &targets, placed, &meshes, (0, 0));
            // SAFETY: as above.
            unsafe { device.raw.cmd_end_rendering(cmd) };

            // Read back the resolved image.
            barriers(
                &device,
                cmd,
                &[image_barrier(
                    &resolved,
                    COLOR_TARGET,
                    vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                    COLOR_WRITE,
                    COPY_READ,
                )],
            );
            let region = whole_image_copy(width, height);
            // SAFETY: as above.
            unsafe {
                device.raw.cmd_copy_image_to_buffer(
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

const COLOR_TARGET: vk::ImageLayout = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
const DEPTH_TARGET: vk::ImageLayout = vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL;
const READ_ONLY: vk::ImageLayout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
const NOTHING: Access = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
const COLOR_WRITE: Access =
    (vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT, vk::AccessFlags2::COLOR_ATTACHMENT_WRITE);
const DEPTH_TESTS: Access = (
    vk::PipelineStageFlags2::from_raw(
        vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS.as_raw() | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS.as_raw(),
    ),
    vk::AccessFlags2::from_raw(
        vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ.as_raw()
            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE.as_raw(),
    ),
);
const SAMPLED: Access = (vk::PipelineStageFlags2::FRAGMENT_SHADER, vk::AccessFlags2::SHADER_SAMPLED_READ);
const COPY_READ: Access = (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::TRANSFER_READ);

/// The descriptor set layout and push constants shared by the shadow and forward passes: the frame (0),
/// lights (1), objects (2), the shadow cubes' face matrices (3) and the shadow cubes (4); the push constants
/// name the object drawn and, in the shadow pass, the light and the cube face.
fn scene_layout(device: &Arc<Device>) -> Result<Arc<PipelineLayout>> {
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
        binding(3, vk::DescriptorType::STORAGE_BUFFER),
        binding(4, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
    ];
    let push = [vk::PushConstantRange { stage_flags: stages, offset: 0, size: 12 }];
    device.create_pipeline_layout(&[&bindings], &push, "scene layout")
}

/// `items`, or one default element when there are none: storage buffers may not be empty.
fn non_empty<T: Copy + Default>(items: &[T]) -> std::borrow::Cow<'_, [T]> {
    if items.is_empty() {
        std::borrow::Cow::Owned(vec![T::default()])
    } else {
        std::borrow::Cow::Borrowed(items)
    }
}
