//! Descriptor pools and the buffer descriptor sets allocated from them.

use std::sync::Arc;

use ash::vk;

use super::{Buffer, Device};
use crate::error::Result;

/// A descriptor pool, destroyed (with every set allocated from it) in Drop.
pub struct DescriptorPool {
    pub raw: vk::DescriptorPool,
    device: Arc<Device>,
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
    /// Allocates one set of `layout` and points binding i at `buffers[i]` (its type taken from the pair).
    ///
    /// # Errors
    /// `Error::Vulkan` if the pool is exhausted.
    pub fn allocate_buffer_set(
        &self,
        layout: vk::DescriptorSetLayout,
        buffers: &[(vk::DescriptorType, &Buffer)],
    ) -> Result<vk::DescriptorSet> {
        let layouts = [layout];
        let info = vk::DescriptorSetAllocateInfo::default().descriptor_pool(self.raw).set_layouts(&layouts);
        // SAFETY: the pool and layout are alive.
        let set = unsafe { self.device.raw.allocate_descriptor_sets(&info)? }[0];
        let infos: Vec<[vk::DescriptorBufferInfo; 1]> = buffers
            .iter()
            .map(|(_, buffer)| [vk::DescriptorBufferInfo { buffer: buffer.raw, offset: 0, range: vk::WHOLE_SIZE }])
            .collect();
        let writes: Vec<_> = buffers
            .iter()
            .zip(&infos)
            .enumerate()
            .map(|(binding, ((kind, _), info))| {
                vk::WriteDescriptorSet::default()
                    .dst_set(set)
                    .dst_binding(binding as u32)
                    .descriptor_type(*kind)
                    .buffer_info(info)
            })
            .collect();
        // SAFETY: the set and the buffers are alive.
        unsafe { self.device.raw.update_descriptor_sets(&writes, &[]) };
        Ok(set)
    }
}

impl Drop for DescriptorPool {
    fn drop(&mut self) {
        // SAFETY: renders wait for their work before returning, so no set of this pool is in use.
        unsafe { self.device.raw.destroy_descriptor_pool(self.raw, None) };
    }
}
