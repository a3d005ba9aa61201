//! Samplers.

use std::sync::Arc;

use ash::vk;

use super::Device;
use crate::error::Result;

/// A sampler, destroyed in Drop.
pub struct Sampler {
    /// The Vulkan handle.
    pub raw: vk::Sampler,
    device: Arc<Device>,
}

impl Device {
    /// A sampler that reads the nearest texel, clamped to the edge: shadow maps hold distances, which must
    /// not be blended.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the sampler.
    pub fn create_nearest_sampler(self: &Arc<Self>, name: &str) -> Result<Sampler> {
        self.create_sampler(vk::Filter::NEAREST, vk::SamplerAddressMode::CLAMP_TO_EDGE, name)
    }

    /// A sampler for equirectangular maps: bilinear, wrapping around in u (longitude), clamped in v at the
    /// poles.
    ///
    /// # Errors
    /// `Error::Vulkan` if the driver refuses the sampler.
    pub fn create_environment_sampler(self: &Arc<Self>, name: &str) -> Result<Sampler> {
        self.create_sampler(vk::Filter::LINEAR, vk::SamplerAddressMode::REPEAT, name)
    }

    /// A sampler of level 0 with `filter`, addressing u as `address_u` and v and w clamped to the edge.
    fn create_sampler(
        self: &Arc<Self>,
        filter: vk::Filter,
        address_u: vk::SamplerAddressMode,
        name: &str,
    ) -> Result<Sampler> {
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter)
            .min_filter(filter)
            .mipmap_mode(vk::SamplerMipmapMode::NEAREST)
            .address_mode_u(address_u)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(0.0);
        // SAFETY: the device is alive.
        let raw = unsafe { self.raw.create_sampler(&info, None)? };
        self.set_name(raw, name);
        Ok(Sampler { raw, device: self.clone() })
    }
}

impl Drop for Sampler {
    fn drop(&mut self) {
        if self.device.is_given_up() {
            return; // work that never ended may still use it (Device::give_up)
        }
        // SAFETY: renders wait for their work before returning, so no descriptor using it is in flight.
        unsafe { self.device.raw.destroy_sampler(self.raw, None) };
    }
}
