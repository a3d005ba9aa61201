//! A window surface and its swapchain (the preview only).

use std::sync::Arc;

use ash::{khr, vk};
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::{Device, Instance};
use crate::error::{Error, Result};

/// A window's Vulkan surface, destroyed in Drop (after every swapchain made on it, which hold it).
pub struct Surface {
    /// The Vulkan handle.
    pub raw: vk::SurfaceKHR,
    /// The `VK_KHR_surface` functions.
    pub loader: khr::surface::Instance,
    /// Kept alive: the surface must be destroyed before its instance.
    _instance: Arc<Instance>,
}

impl Surface {
    /// The instance extensions a surface of this display needs.
    ///
    /// # Errors
    /// `Error::Device` if Vulkan has no surface for this kind of display.
    pub fn required_extensions(display: RawDisplayHandle) -> Result<Vec<&'static std::ffi::CStr>> {
        let names = ash_window::enumerate_required_extensions(display)
            .map_err(|e| Error::Device(format!("no Vulkan surface for this display: {e}")))?;
        // SAFETY: ash-window returns pointers to static, NUL-terminated extension names.
        Ok(names.iter().map(|&name| unsafe { std::ffi::CStr::from_ptr(name) }).collect())
    }

    /// Creates a surface for a window.
    ///
    /// # Errors
    /// `Error::Vulkan` if the surface cannot be made.
    pub fn new(instance: &Arc<Instance>, display: RawDisplayHandle, window: RawWindowHandle) -> Result<Self> {
        // SAFETY: the handles come from a live window, which the caller keeps alive longer than the surface.
        let raw = unsafe { ash_window::create_surface(&instance.entry, &instance.raw, display, window, None)? };
        let loader = khr::surface::Instance::new(&instance.entry, &instance.raw);
        Ok(Self { raw, loader, _instance: instance.clone() })
    }
}

impl Drop for Surface {
    fn drop(&mut self) {
        // SAFETY: swapchains on the surface are gone (each holds an Arc of it); the instance is alive.
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}

/// A swapchain of 8-bit UNORM images that frames are copied into, with its semaphores; destroyed in Drop.
pub struct Swapchain {
    /// The Vulkan handle.
    pub raw: vk::SwapchainKHR,
    /// Its images, in the driver's order: what an acquired index names.
    pub images: Vec<vk::Image>,
    /// `B8G8R8A8_UNORM` or `R8G8B8A8_UNORM`: frames arrive already through the output transform.
    pub format: vk::Format,
    /// The images' size in pixels.
    pub extent: vk::Extent2D,
    /// Whether its images can be copied out (for screenshots).
    pub readable: bool,
    /// Signalled when an acquired image may be written.
    pub acquired: vk::Semaphore,
    /// One per image: signalled when its copy is done, waited on by its presentation.
    pub rendered: Vec<vk::Semaphore>,
    /// The `VK_KHR_swapchain` functions.
    pub loader: khr::swapchain::Device,
    _surface: Arc<Surface>,
    device: Arc<Device>,
}

impl Swapchain {
    /// Creates a swapchain of `width` x `height` (clamped to what the surface allows), replacing `old`.
    ///
    /// # Errors
    /// `Error::Device` if the queue cannot present to the surface or no 8-bit UNORM format is offered;
    /// `Error::Vulkan` otherwise.
    pub fn new(device: &Arc<Device>, surface: &Arc<Surface>, width: u32, height: u32) -> Result<Self> {
        // SAFETY: the physical device and surface are alive.
        let (supported, capabilities, formats) = unsafe {
            (
                surface.loader.get_physical_device_surface_support(
                    device.physical,
                    device.queue_family,
                    surface.raw,
                )?,
                surface.loader.get_physical_device_surface_capabilities(device.physical, surface.raw)?,
                surface.loader.get_physical_device_surface_formats(device.physical, surface.raw)?,
            )
        };
        if !supported {
            return Err(Error::Device(format!("device {} cannot present to this window", device.info.name)));
        }
        // Frames arrive as 8-bit values already through the output transform: a UNORM image shows them as is.
        let format = formats
            .iter()
            .find(|f| matches!(f.format, vk::Format::B8G8R8A8_UNORM | vk::Format::R8G8B8A8_UNORM))
            .ok_or_else(|| Error::Device("the window offers no 8-bit UNORM swapchain format".into()))?;
        let extent = if capabilities.current_extent.width == u32::MAX {
            vk::Extent2D {
                width: width.clamp(capabilities.min_image_extent.width, capabilities.max_image_extent.width),
                height: height.clamp(capabilities.min_image_extent.height, capabilities.max_image_extent.height),
            }
        } else {
            capabilities.current_extent
        };
        let image_count = (capabilities.min_image_count + 1).min(if capabilities.max_image_count == 0 {
            u32::MAX
        } else {
            capabilities.max_image_count
        });
        // Frames are copied in (required), and copied out for screenshots (where the surface allows it).
        let usage = vk::ImageUsageFlags::TRANSFER_DST
            | (capabilities.supported_usage_flags & vk::ImageUsageFlags::TRANSFER_SRC);
        if !capabilities.supported_usage_flags.contains(vk::ImageUsageFlags::TRANSFER_DST) {
            return Err(Error::Device(format!(
                "device {}: this window's swapchain images cannot be copied into (usage {:?})",
                device.info.name, capabilities.supported_usage_flags
            )));
        }
        // Every frame is opaque (alpha 255): any way of compositing alpha shows it the same.
        let composite_alpha = [
            vk::CompositeAlphaFlagsKHR::OPAQUE,
            vk::CompositeAlphaFlagsKHR::INHERIT,
            vk::CompositeAlphaFlagsKHR::PRE_MULTIPLIED,
            vk::CompositeAlphaFlagsKHR::POST_MULTIPLIED,
        ]
        .into_iter()
        .find(|&mode| capabilities.supported_composite_alpha.contains(mode))
        .ok_or_else(|| Error::Device("this window's surface offers no way of compositing".into()))?;
        let info = vk::SwapchainCreateInfoKHR::default()
            .surface(surface.raw)
            .min_image_count(image_count)
            .image_format(format.format)
            .image_color_space(format.color_space)
            .image_extent(extent)
            .image_array_layers(1)
            .image_usage(usage)
            .image_sharing_mode(vk::SharingMode::EXCLUSIVE)
            .pre_transform(capabilities.current_transform)
            .composite_alpha(composite_alpha)
            .present_mode(vk::PresentModeKHR::FIFO)
            .clipped(true);
        let loader = khr::swapchain::Device::new(&device.instance.raw, &device.raw);
        // SAFETY: the surface and device are alive; every failure path below destroys what was made.
        unsafe {
            let raw = loader.create_swapchain(&info, None)?;
            let mut swapchain = Swapchain {
                raw,
                images: Vec::new(),
                format: format.format,
                extent,
                readable: usage.contains(vk::ImageUsageFlags::TRANSFER_SRC),
                acquired: vk::Semaphore::null(),
                rendered: Vec::new(),
                loader,
                _surface: surface.clone(),
                device: device.clone(),
            };
            swapchain.images = swapchain.loader.get_swapchain_images(raw)?;
            swapchain.acquired = device.raw.create_semaphore(&vk::SemaphoreCreateInfo::default(), None)?;
            for _ in 0..swapchain.images.len() {
                let semaphore = device.raw.create_semaphore(&vk::SemaphoreCreateInfo::default(), None)?;
                swapchain.rendered.push(semaphore);
            }
            Ok(swapchain)
        }
    }
}

impl Drop for Swapchain {
    fn drop(&mut self) {
        if self.device.is_given_up() {
            return; // work that never ended may still use it (Device::give_up)
        }
        // SAFETY: the device is idle after this wait, so no semaphore or image is in use.
        unsafe {
            let _ = self.device.raw.device_wait_idle();
            for &semaphore in self.rendered.iter().chain([&self.acquired]) {
                if semaphore != vk::Semaphore::null() {
                    self.device.raw.destroy_semaphore(semaphore, None);
                }
            }
            self.loader.destroy_swapchain(self.raw, None);
        }
    }
}
