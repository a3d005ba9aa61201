//! Descriptor pools and the descriptor sets allocated from them.

use std::sync::Arc;

use ash::vk;

use super::{Buffer, Device, Sampler};
use crate::error::Result;

/// A descriptor pool, destroyed (with every set allocated from it) in Drop.
pub struct DescriptorPool {
    /// The Vulkan handle.
    pub raw: vk::DescriptorPool,
    device: Arc<Device>,
}

/// What one binding of a set points at.
pub enum Descriptor<'a> {
    /// A uniform or storage buffer, whole.
    Buffer(vk::DescriptorType, &'a Buffer),
    /// The first bytes of a buffer: a dynamic descriptor's window, which each bind moves by its offset.
    BufferRange(vk::DescriptorType, &'a Buffer, vk::DeviceSize),
    /// An image view read through a sampler, in the given layout.
    SampledImage(vk::ImageView, &'a Sampler, vk::ImageLayout),
}

impl Device {
    /// Creates a pool for `max_sets` sets holding at most `sizes` descriptors.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the pool.
    pub fn create_descriptor_pool(
        self: &Arc<Self>,
        max_sets: u32,
        sizes: &[vk::DescriptorPoolSize],
    ) -> Result<DescriptorPool> {
        let info = vk::DescriptorPoolCreateInfo::default().max_sets(max_sets).pool_sizes(sizes);
        // SAFETY: the device is alive.
        let raw = unsafe { self.raw.create_descriptor_pool(&info, None)? };
        Ok(DescriptorPool { raw, device: self.clone() })
    }
}

impl DescriptorPool {
    /// Allocates one set of `layout` and points binding i at `descriptors[i]`.
    ///
    /// # Errors
    /// `Error::Vulkan` if the pool is exhausted.
    pub fn allocate_set(
        &self,
        layout: vk::DescriptorSetLayout,
        descriptors: &[Descriptor],
    ) -> Result<vk::DescriptorSet> {
        let layouts = [layout];
        let info = vk::DescriptorSetAllocateInfo::default().descriptor_pool(self.raw).set_layouts(&layouts);
        // SAFETY: the pool and layout are alive.
        let set = unsafe { self.device.raw.allocate_descriptor_sets(&info)? }[0];
        self.write_set(set, descriptors);
        Ok(set)
    }

    /// Points binding i of `set`, a set of this pool that no submitted work still uses, at `descriptors[i]`.
    pub fn write_set(&self, set: vk::DescriptorSet, descriptors: &[Descriptor]) {
        let buffer_infos: Vec<[vk::DescriptorBufferInfo; 1]> = descriptors
            .iter()
            .map(|d| match d {
                Descriptor::Buffer(_, buffer) => {
                    [vk::DescriptorBufferInfo { buffer: buffer.raw, offset: 0, range: vk::WHOLE_SIZE }]
                }
                Descriptor::BufferRange(_, buffer, range) => {
                    [vk::DescriptorBufferInfo { buffer: buffer.raw, offset: 0, range: *range }]
                }
                Descriptor::SampledImage(..) => [vk::DescriptorBufferInfo::default()],
            })
            .collect();
        let image_infos: Vec<[vk::DescriptorImageInfo; 1]> = descriptors
            .iter()
            .map(|d| match d {
                Descriptor::SampledImage(view, sampler, layout) => {
                    [vk::DescriptorImageInfo { sampler: sampler.raw, image_view: *view, image_layout: *layout }]
                }
                Descriptor::Buffer(..) | Descriptor::BufferRange(..) => [vk::DescriptorImageInfo::default()],
            })
            .collect();
        let writes: Vec<_> = descriptors
            .iter()
            .enumerate()
            .map(|(binding, d)| {
                let write = vk::WriteDescriptorSet::default().dst_set(set).dst_binding(binding as u32);
                match d {
                    Descriptor::Buffer(kind, _) | Descriptor::BufferRange(kind, ..) => {
                        write.descriptor_type(*kind).buffer_info(&buffer_infos[binding])
                    }
                    Descriptor::SampledImage(..) => write
                        .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                        .image_info(&image_infos[binding]),
                }
            })
            .collect();
        // SAFETY: the set and everything it points at are alive, and no pending work uses the set.
        unsafe { self.device.raw.update_descriptor_sets(&writes, &[]) };
    }
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        if self.device.is_given_up() {
            return; // work that never ended may still use it (Device::give_up)
        }
        // SAFETY: renders wait for their work before returning, so no set of this pool is in use.
        unsafe { self.device.raw.destroy_descriptor_pool(self.raw, None) };
    }
}
