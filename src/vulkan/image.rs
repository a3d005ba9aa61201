//! Images, their views and their memory.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::Device;
use crate::error::Result;

/// A 2D image's size, format, sample count and use.
#[derive(Clone, Copy, Debug)]
pub struct ImageDesc {
    pub width: u32,
    pub height: u32,
    pub format: vk::Format,
    pub samples: vk::SampleCountFlags,
    pub usage: vk::ImageUsageFlags,
    pub aspect: vk::ImageAspectFlags,
}

/// A device-local 2D image with one view, freed in Drop.
pub struct Image {
    pub raw: vk::Image,
    pub view: vk::ImageView,
    pub desc: ImageDesc,
    allocation: Allocation,
    device: Arc<Device>,
}

impl Device {
    /// Creates a device-local 2D image and a view of it.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation` when the image or its memory cannot be had.
    pub fn create_image(self: &Arc<Self>, desc: ImageDesc, name: &str) -> Result<Image> {
        let info = vk::ImageCreateInfo::default()
            .image_type(vk::ImageType::TYPE_2D)
            .format(desc.format)
            .extent(vk::Extent3D { width: desc.width, height: desc.height, depth: 1 })
            .mip_levels(1)
            .array_layers(1)
            .samples(desc.samples)
            .tiling(vk::ImageTiling::OPTIMAL)
            .usage(desc.usage)
            .initial_layout(vk::ImageLayout::UNDEFINED);
        // SAFETY: the device is alive; every failure path destroys what was made before it.
        unsafe {
            let raw = self.raw.create_image(&info, None)?;
            let requirements = self.raw.get_image_memory_requirements(raw);
            let allocation = self.allocator().allocate(&AllocationCreateDesc {
                name,
                requirements,
                location: MemoryLocation::GpuOnly,
                linear: false,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            });
            let allocation = match allocation {
                Ok(a) => a,
                Err(e) => {
                    self.raw.destroy_image(raw, None);
                    return Err(e.into());
                }
            };
            let view_info = vk::ImageViewCreateInfo::default()
                .image(raw)
                .view_type(vk::ImageViewType::TYPE_2D)
                .format(desc.format)
                .subresource_range(subresource_range(desc.aspect));
            let view = self
                .raw
                .bind_image_memory(raw, allocation.memory(), allocation.offset())
                .and_then(|()| self.raw.create_image_view(&view_info, None));
            let view = match view {
                Ok(v) => v,
                Err(e) => {
                    self.raw.destroy_image(raw, None);
                    let _ = self.allocator().free(allocation);
                    return Err(e.into());
                }
            };
            self.set_name(raw, name);
            Ok(Image { raw, view, desc, allocation, device: self.clone() })
        }
    }
}

/// The whole of a single-mip, single-layer image.
pub fn subresource_range(aspect: vk::ImageAspectFlags) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: 0,
        layer_count: 1,
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        // SAFETY: the owner guarantees the GPU no longer uses the image (renders wait for their fence).
        unsafe {
            self.device.raw.destroy_image_view(self.view, None);
            self.device.raw.destroy_image(self.raw, None);
        }
        let _ = self.device.allocator().free(std::mem::take(&mut self.allocation));
    }
}
