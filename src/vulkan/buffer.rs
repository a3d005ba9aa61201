//! Buffers and their memory.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::vulkan::{Allocation, AllocationCreateDesc, AllocationScheme};
use gpu_allocator::MemoryLocation;

use super::Device;
use crate::error::{Error, Result};

/// What a buffer is for and where its memory lives.
#[derive(Clone, Copy, Debug)]
pub struct BufferDesc {
    /// Size in bytes.
    pub size: vk::DeviceSize,
    /// What the buffer is bound as (vertex, index, uniform, storage, transfer).
    pub usage: vk::BufferUsageFlags,
    /// Where its memory lives: device-only, or mapped for writing from or reading back to the CPU.
    pub location: MemoryLocation,
}

/// A buffer with its own allocation, freed in Drop.
pub struct Buffer {
    /// The Vulkan handle.
    pub raw: vk::Buffer,
    /// What it was made as.
    pub desc: BufferDesc,
    allocation: Allocation,
    device: Arc<Device>,
}

impl Device {
    /// Creates a buffer and binds memory from the allocator.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation` when the buffer or its memory cannot be had.
    pub fn create_buffer(self: &Arc<Self>, desc: BufferDesc, name: &str) -> Result<Buffer> {
        let info = vk::BufferCreateInfo::default().size(desc.size.max(1)).usage(desc.usage);
        // SAFETY: the device is alive; the buffer is destroyed on every failure path below.
        unsafe {
            let raw = self.raw.create_buffer(&info, None)?;
            let requirements = self.raw.get_buffer_memory_requirements(raw);
            let allocation = self.allocator().allocate(&AllocationCreateDesc {
                name,
                requirements,
                location: desc.location,
                linear: true,
                allocation_scheme: AllocationScheme::GpuAllocatorManaged,
            });
            let allocation = match allocation {
                Ok(a) => a,
                Err(e) => {
                    self.raw.destroy_buffer(raw, None);
                    return Err(e.into());
                }
            };
            if let Err(e) = self.raw.bind_buffer_memory(raw, allocation.memory(), allocation.offset()) {
                self.raw.destroy_buffer(raw, None);
                let _ = self.allocator().free(allocation);
                return Err(e.into());
            }
            self.set_name(raw, name);
            Ok(Buffer { raw, desc, allocation, device: self.clone() })
        }
    }

    /// Creates a host-visible buffer holding `data`.
    ///
    /// # Errors
    /// As [`Device::create_buffer`].
    pub fn create_buffer_with_data<T: Copy>(
        self: &Arc<Self>,
        data: &[T],
        usage: vk::BufferUsageFlags,
        name: &str,
    ) -> Result<Buffer> {
        let size = std::mem::size_of_val(data) as vk::DeviceSize;
        let mut buffer = self.create_buffer(BufferDesc { size, usage, location: MemoryLocation::CpuToGpu }, name)?;
        buffer.write(data)?;
        Ok(buffer)
    }
}

impl Buffer {
    /// Copies `data` to the start of a host-visible buffer.
    ///
    /// # Errors
    /// `Error::Vulkan(ERROR_MEMORY_MAP_FAILED)` if the buffer is not host-visible or too small.
    pub fn write<T: Copy>(&mut self, data: &[T]) -> Result<()> {
        let bytes_len = std::mem::size_of_val(data);
        let mapped = self.allocation.mapped_slice_mut().ok_or(Error::Vulkan(vk::Result::ERROR_MEMORY_MAP_FAILED))?;
        if mapped.len() < bytes_len {
            return Err(Error::Vulkan(vk::Result::ERROR_MEMORY_MAP_FAILED));
        }
        // SAFETY: T is Copy (plain data) and the destination holds at least bytes_len bytes.
        unsafe { std::ptr::copy_nonoverlapping(data.as_ptr().cast::<u8>(), mapped.as_mut_ptr(), bytes_len) };
        Ok(())
    }

    /// The contents of a host-visible buffer, to write in place.
    ///
    /// # Errors
    /// `Error::Vulkan(ERROR_MEMORY_MAP_FAILED)` if the buffer is not host-visible.
    pub fn bytes_mut(&mut self) -> Result<&mut [u8]> {
        let size = self.desc.size as usize;
        let mapped = self.allocation.mapped_slice_mut().ok_or(Error::Vulkan(vk::Result::ERROR_MEMORY_MAP_FAILED))?;
        Ok(&mut mapped[..size])
    }

    /// The contents of a host-visible buffer.
    ///
    /// # Errors
    /// `Error::Vulkan(ERROR_MEMORY_MAP_FAILED)` if the buffer is not host-visible.
    pub fn bytes(&self) -> Result<&[u8]> {
        let mapped = self.allocation.mapped_slice().ok_or(Error::Vulkan(vk::Result::ERROR_MEMORY_MAP_FAILED))?;
        Ok(&mapped[..self.desc.size as usize])
    }
}

impl Buffer {
    /// Makes writes by `stage` (with `access`) to this buffer visible to the host once the submission's fence
    /// has signalled; record it last, before reading a `GpuToCpu` buffer.
    pub fn record_host_read_barrier(
        &self,
        cmd: vk::CommandBuffer,
        stage: vk::PipelineStageFlags2,
        access: vk::AccessFlags2,
    ) {
        let barrier = [vk::BufferMemoryBarrier2::default()
            .src_stage_mask(stage)
            .src_access_mask(access)
            .dst_stage_mask(vk::PipelineStageFlags2::HOST)
            .dst_access_mask(vk::AccessFlags2::HOST_READ)
            .buffer(self.raw)
            .size(vk::WHOLE_SIZE)];
        // SAFETY: the command buffer is recording and the buffer outlives the submission (its owner waits).
        unsafe {
            self.device.raw.cmd_pipeline_barrier2(cmd, &vk::DependencyInfo::default().buffer_memory_barriers(&barrier));
        }
    }
}

impl Drop for Buffer {
    fn drop(&mut self) {
        if self.device.is_given_up() {
            return; // work that never ended may still use it (Device::give_up)
        }
        // SAFETY: the owner guarantees the GPU no longer uses the buffer (renders wait for their fence).
        unsafe { self.device.raw.destroy_buffer(self.raw, None) };
        let _ = self.device.allocator().free(std::mem::take(&mut self.allocation));
    }
}
