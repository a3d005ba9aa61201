//! Kept per image size: what the forward pass draws into and the buffer its image is read back into.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::forward::COLOR_FORMAT;
use super::passes::PassTargets;
use super::passes::DEPTH_FORMAT;
use crate::error::Result;
use crate::vulkan::{Buffer, BufferDesc, Device, Image, ImageDesc};

/// The colour and depth targets (multisampled or not) and the host buffer the resolve pass writes the
/// image into; kept while the size and sample count hold.
pub struct Targets {
    /// Read by the resolve pass's compute shader, sample by sample.
    pub color: Image,
    pub depth: Image,
    pub readback: Buffer,
    samples: vk::SampleCountFlags,
}

/// Bytes per pixel of the colour format (four 32-bit floats), and of the radiance read back.
pub const BYTES_PER_PIXEL: u64 = 16;

impl Targets {
    /// `kept` if it has this size and sample count, new targets otherwise; their depth can be sampled (by the
    /// resolve, when it writes the background) where `sampled_depth` says so for this sample count, which
    /// depends on the device alone.
    ///
    /// # Errors
    /// `Error::Vulkan` or `Error::Allocation`.
    pub fn for_size(
        device: &Arc<Device>,
        kept: Option<Self>,
        (width, height): (u32, u32),
        samples: vk::SampleCountFlags,
        sampled_depth: bool,
    ) -> Result<Self> {
        if let Some(kept) = kept.filter(|t| t.fits(width, height, samples)) {
            return Ok(kept);
        }
        // Let the old targets go before making the new ones: a resized preview window must not hold both.
        let target = |format, samples, usage, aspect| ImageDesc::plain(width, height, format, samples, usage, aspect);
        let color = device.create_image(
            target(
                COLOR_FORMAT,
                samples,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                vk::ImageAspectFlags::COLOR,
            ),
            "colour",
        )?;
        let mut depth_usage = vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT;
        if sampled_depth {
            depth_usage |= vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST;
        }
        let depth =
            device.create_image(target(DEPTH_FORMAT, samples, depth_usage, vk::ImageAspectFlags::DEPTH), "depth")?;
        let readback = device.create_buffer(
            BufferDesc {
                size: u64::from(width) * u64::from(height) * BYTES_PER_PIXEL,
                usage: vk::BufferUsageFlags::STORAGE_BUFFER,
                location: MemoryLocation::GpuToCpu,
            },
            "readback",
        )?;
        Ok(Self { color, depth, readback, samples })
    }

    fn fits(&self, width: u32, height: u32, samples: vk::SampleCountFlags) -> bool {
        self.size() == (width, height) && self.samples == samples
    }

    /// Width and height in pixels.
    pub fn size(&self) -> (u32, u32) {
        (self.color.desc.width, self.color.desc.height)
    }

    /// Samples a pixel.
    pub fn samples(&self) -> u32 {
        self.samples.as_raw()
    }

    /// The forward pass's attachments.
    pub fn pass_targets(&self) -> PassTargets {
        let (width, height) = self.size();
        PassTargets { color: self.color.view, depth: self.depth.view, width, height }
    }
}
