//! Images, their views and their memory.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::Device;
use crate::error::Result;

/// A 2D image's size, layers, format, sample count and use.
#[derive(Clone, Copy, Debug)]
pub struct ImageDesc {
    /// Width in texels.
    pub width: u32,
    /// Height in texels.
    pub height: u32,
    /// Array layers: 1 for a plain image, 6 per cube of a cube array.
    pub layers: u32,
    /// Cube-compatible, viewed as a cube array (layers a multiple of 6).
    pub cube: bool,
    /// The texel format.
    pub format: vk::Format,
    /// Samples per texel (`TYPE_1` for an image that is not multisampled).
    pub samples: vk::SampleCountFlags,
    /// What the image is used for.
    pub usage: vk::ImageUsageFlags,
    /// The aspect its views cover: colour or depth.
    pub aspect: vk::ImageAspectFlags,
}

impl ImageDesc {
    /// A single-layer 2D image.
    pub fn plain(
        width: u32,
        height: u32,
        format: vk::Format,
        samples: vk::SampleCountFlags,
        usage: vk::ImageUsageFlags,
        aspect: vk::ImageAspectFlags,
    ) -> Self {
        Self { width, height, layers: 1, cube: false, format, samples, usage, aspect }
    }
}

/// A device-local 2D image with a view of all its layers (2D, 2D array or cube array), freed in Drop.
pub struct Image {
    /// The Vulkan handle.
    pub raw: vk::Image,
    /// The view of all its layers.
    pub view: vk::ImageView,
    /// What it was made as.
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
            .array_layers(desc.layers)
            .flags(if desc.cube { vk::ImageCreateFlags::CUBE_COMPATIBLE } else { vk::ImageCreateFlags::empty() })
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
            let view_type = match (desc.cube, desc.layers) {
                (true, _) => vk::ImageViewType::CUBE_ARRAY,
                (false, 1) => vk::ImageViewType::TYPE_2D,
                (false, _) => vk::ImageViewType::TYPE_2D_ARRAY,
            };
            let view_info = vk::ImageViewCreateInfo::default()
                .image(raw)
                .view_type(view_type)
                .format(desc.format)
                .subresource_range(layer_range(desc.aspect, 0, desc.layers));
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

/// `count` layers from `first` of a single-mip image.
pub fn layer_range(aspect: vk::ImageAspectFlags, first: u32, count: u32) -> vk::ImageSubresourceRange {
    vk::ImageSubresourceRange {
        aspect_mask: aspect,
        base_mip_level: 0,
        level_count: 1,
        base_array_layer: first,
        layer_count: count,
    }
}

/// A (stage, access) pair: where a barrier waits from, or what it makes ready.
pub type Access = (vk::PipelineStageFlags2, vk::AccessFlags2);

/// A layout transition of `range` of a raw image (a swapchain's, or an [`Image`]'s), from `src` to `dst`.
pub fn layout_transition(
    image: vk::Image,
    range: vk::ImageSubresourceRange,
    old: vk::ImageLayout,
    new: vk::ImageLayout,
    src: Access,
    dst: Access,
) -> vk::ImageMemoryBarrier2<'static> {
    vk::ImageMemoryBarrier2::default()
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)
        .old_layout(old)
        .new_layout(new)
        .image(image)
        .subresource_range(range)
}

/// A copy between a tightly packed buffer and the whole first layer of a `width` x `height` colour image.
pub fn whole_image_copy(width: u32, height: u32) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .image_subresource(vk::ImageSubresourceLayers {
            aspect_mask: vk::ImageAspectFlags::COLOR,
            mip_level: 0,
            base_array_layer: 0,
            layer_count: 1,
        })
        .image_extent(vk::Extent3D { width, height, depth: 1 })
}

/// An extra view of some layers of an image (e.g. one cube of a cube array, to render into), destroyed in
/// Drop; its owner keeps the image alive longer.
pub struct ImageView {
    /// The Vulkan handle.
    pub raw: vk::ImageView,
    device: Arc<Device>,
}

impl Image {
    /// A 2D-array view of `count` layers from `first`.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the view.
    pub fn layer_view(&self, first: u32, count: u32) -> Result<ImageView> {
        let info = vk::ImageViewCreateInfo::default()
            .image(self.raw)
            .view_type(vk::ImageViewType::TYPE_2D_ARRAY)
            .format(self.desc.format)
            .subresource_range(layer_range(self.desc.aspect, first, count));
        // SAFETY: the image is alive; the view is destroyed before it by its owner.
        let raw = unsafe { self.device.raw.create_image_view(&info, None)? };
        Ok(ImageView { raw, device: self.device.clone() })
    }

    /// Every layer of the image.
    pub fn full_range(&self) -> vk::ImageSubresourceRange {
        layer_range(self.desc.aspect, 0, self.desc.layers)
    }
}

impl Drop for ImageView {
    fn drop(&mut self) {
        if self.device.is_given_up() {
            return; // work that never ended may still use it (Device::give_up)
        }
        // SAFETY: renders wait for their work before returning, so the GPU no longer uses the view.
        unsafe { self.device.raw.destroy_image_view(self.raw, None) };
    }
}

impl Drop for Image {
    fn drop(&mut self) {
        if self.device.is_given_up() {
            return; // work that never ended may still use it (Device::give_up)
        }
        // SAFETY: the owner guarantees the GPU no longer uses the image (renders wait for their fence).
        unsafe {
            self.device.raw.destroy_image_view(self.view, None);
            self.device.raw.destroy_image(self.raw, None);
        }
        let _ = self.device.allocator().free(std::mem::take(&mut self.allocation));
    }
}
