//! Rewritten every image: the scene's data for the shaders, in buffers and a descriptor set that are kept.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::analytic::{AnalyticValues, REPORT_BYTES};
use super::environment::EnvironmentTextures;
use super::gpu_types::{GpuAlbedoEntry, GpuFrame, GpuObject, GpuPointLight};
use crate::error::Result;
use crate::vulkan::{Buffer, BufferDesc, Descriptor, DescriptorPool, Device, PipelineLayout, Sampler};

/// The frame, lights, objects, shadow face matrices and albedo tables (storage buffers) in host-visible
/// buffers, each
/// made again only when a scene needs more room than it has, and the one descriptor set the passes bind.
pub struct SceneData {
    frame: Buffer,
    lights: Buffer,
    objects: Buffer,
    shadow_views: Buffer,
    environment_albedo: Buffer,
    pool: DescriptorPool,
    pub set: vk::DescriptorSet,
}

/// What one image's shaders read.
pub struct SceneValues<'a> {
    pub frame: GpuFrame,
    pub lights: &'a [GpuPointLight],
    pub objects: &'a [GpuObject],
    pub shadow_views: &'a [[[f32; 4]; 4]],
    /// The fast mode's albedo tables, ALBEDO_TABLE_SIZE entries an object (one unused entry otherwise).
    pub environment_albedo: &'a [GpuAlbedoEntry],
}

/// What the shaders read besides the values: the shadow cubes, the environment's map, tables and layers, the
/// measured tables, and the analytic materials' values and reports.
#[derive(Clone, Copy)]
pub struct SceneResources<'a> {
    pub shadow_cubes: (vk::ImageView, &'a Sampler),
    pub environment: (&'a EnvironmentTextures, &'a Sampler),
    pub measured: &'a Buffer,
    pub analytic: &'a AnalyticValues,
}

impl SceneData {
    /// Buffers holding `values` and a set pointing at them and at `images`.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn new(
        device: &Arc<Device>,
        layout: &PipelineLayout,
        values: &SceneValues,
        images: SceneResources,
    ) -> Result<Self> {
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let pool = device.create_descriptor_pool(
            1,
            &[
                vk::DescriptorPoolSize { ty: vk::DescriptorType::UNIFORM_BUFFER, descriptor_count: 1 },
                vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER, descriptor_count: 7 },
                vk::DescriptorPoolSize { ty: vk::DescriptorType::STORAGE_BUFFER_DYNAMIC, descriptor_count: 1 },
                vk::DescriptorPoolSize { ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER, descriptor_count: 3 },
            ],
        )?;
        let mut data = Self {
            frame: host_buffer(device, size_of_slice(&[values.frame]), vk::BufferUsageFlags::UNIFORM_BUFFER, "frame")?,
            lights: host_buffer(device, size_of_slice(values.lights), storage, "lights")?,
            objects: host_buffer(device, size_of_slice(values.objects), storage, "objects")?,
            shadow_views: host_buffer(device, size_of_slice(values.shadow_views), storage, "shadow views")?,
            environment_albedo: host_buffer(
                device,
                size_of_slice(values.environment_albedo),
                storage,
                "environment albedo",
            )?,
            set: vk::DescriptorSet::null(),
            pool,
        };
        data.set = data.pool.allocate_set(layout.set_layouts[0], &data.descriptors(images))?;
        data.write(device, values, images)?;
        Ok(data)
    }

    /// Writes `values`, making a buffer anew where it is too small, and points the set at the buffers and
    /// `images`. No submitted work may still read the set or the buffers (renders wait for theirs).
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn write(&mut self, device: &Arc<Device>, values: &SceneValues, images: SceneResources) -> Result<()> {
        write_growing(device, &mut self.frame, &[values.frame], "frame")?;
        write_growing(device, &mut self.lights, values.lights, "lights")?;
        write_growing(device, &mut self.objects, values.objects, "objects")?;
        write_growing(device, &mut self.shadow_views, values.shadow_views, "shadow views")?;
        write_growing(device, &mut self.environment_albedo, values.environment_albedo, "environment albedo")?;
        self.pool.write_set(self.set, &self.descriptors(images));
        Ok(())
    }

    fn descriptors<'a>(&'a self, images: SceneResources<'a>) -> [Descriptor<'a>; 12] {
        let (cubes, sampler) = images.shadow_cubes;
        let (environment, map_sampler) = images.environment;
        let read_only = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        [
            Descriptor::Buffer(vk::DescriptorType::UNIFORM_BUFFER, &self.frame),
            Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &self.lights),
            Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &self.objects),
            Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &self.shadow_views),
            Descriptor::SampledImage(cubes, sampler, read_only),
            Descriptor::SampledImage(environment.map.view, map_sampler, read_only),
            Descriptor::SampledImage(environment.prefiltered.view, map_sampler, read_only),
            Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &environment.sampling),
            Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, &self.environment_albedo),
            Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, images.measured),
            Descriptor::Buffer(vk::DescriptorType::STORAGE_BUFFER, images.analytic.values()),
            Descriptor::BufferRange(
                vk::DescriptorType::STORAGE_BUFFER_DYNAMIC,
                images.analytic.reports(),
                REPORT_BYTES,
            ),
        ]
    }
}

/// Bytes of `items`, at least one element's: storage buffers may not be empty, and a scene without lights
/// or objects binds one element it does not read.
fn size_of_slice<T>(items: &[T]) -> vk::DeviceSize {
    (std::mem::size_of_val(items).max(std::mem::size_of::<T>())) as vk::DeviceSize
}

fn host_buffer(device: &Arc<Device>, size: vk::DeviceSize, usage: vk::BufferUsageFlags, name: &str) -> Result<Buffer> {
    device.create_buffer(BufferDesc { size, usage, location: MemoryLocation::CpuToGpu }, name)
}

/// Writes `items` to `buffer`, replacing it with a larger one (twice the size needed, so that a growing
/// scene does not replace it at every image) when they do not fit.
fn write_growing<T: Copy>(device: &Arc<Device>, buffer: &mut Buffer, items: &[T], name: &str) -> Result<()> {
    let needed = size_of_slice(items);
    if buffer.desc.size < needed {
        *buffer = host_buffer(device, 2 * needed, buffer.desc.usage, name)?;
    }
    buffer.write(items)
}
