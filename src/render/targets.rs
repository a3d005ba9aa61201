//! Kept per image size: what the forward pass draws into and what its image is read back through.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::forward::{COLOR_FORMAT, DEPTH_FORMAT};
use super::passes::PassTargets;
use crate::error::Result;
use crate::vulkan::{Buffer, BufferDesc, Device, Image, ImageDesc};

/// The multisampled colour and depth targets, the single-sample image they resolve to and the host buffer
/// it is copied to; kept while the size and sample count hold.
pub struct Targets {
    pub resolved: Image,
    /// `None` with one sample: the pass draws into `resolved` itself.
    pub multisampled: Option<Image>,
    pub depth: Image,
    pub readback: Buffer,
    samples: vk::SampleCountFlags,
}

/// Bytes per pixel of the colour format (four 32-bit floats).
pub const BYTES_PER_PIXEL: u64 = 16;

impl Targets {
    /// `kept` if it has this size and sample count, new targets otherwise.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn for_size(
        device: &Arc<Device>,
        kept: Option<Self>,
        width: u32,
        height: u32,
        samples: vk::SampleCountFlags,
    ) -> Result<Self> {
        if let Some(kept) = kept.filter(|t| t.fits(width, height, samples)) {
            return Ok(kept);
        }
        // Let the old targets go before making the new ones: a resized preview window must not hold both.
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
                size: u64::from(width) * u64::from(height) * BYTES_PER_PIXEL,
                usage: vk::BufferUsageFlags::TRANSFER_DST,
                location: MemoryLocation::GpuToCpu,
            },
            "readback",
        )?;
        Ok(Self { resolved, multisampled, depth, readback, samples })
    }

    fn fits(&self, width: u32, height: u32, samples: vk::SampleCountFlags) -> bool {
        self.resolved.desc.width == width && self.resolved.desc.height == height && self.samples == samples
    }

    /// The forward pass's attachments.
    pub fn pass_targets(&self) -> PassTargets {
        PassTargets {
            color: self.multisampled.as_ref().unwrap_or(&self.resolved).view,
            resolve: self.multisampled.as_ref().map(|_| self.resolved.view),
            depth: self.depth.view,
            width: self.resolved.desc.width,
            height: self.resolved.desc.height,
        }
    }
}
