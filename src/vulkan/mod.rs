//! Thin owners of Vulkan objects: one module per concept, each object destroyed in its Drop.
//!
//! Ownership: every object holds an `Arc<Device>`, the device holds an `Arc<Instance>`, so teardown
//! runs objects, then the device (wait idle, allocator, device), then the instance (messenger, instance).

mod buffer;
mod descriptor;
mod device;
mod image;
mod instance;
mod pipeline;
mod sampler;
mod shader;
#[cfg(feature = "preview")]
mod swapchain;
#[cfg(test)]
mod validation_tests;

/// Held around the Vulkan loader's process-wide work: making and destroying instances and devices,
/// enumerating physical devices, and naming objects. The loader of Debian 13 (1.4.309) unloads unused
/// drivers (dlclose) while it enumerates, and a name given on another thread at that moment walked its
/// tables and crashed (SIGSEGV in vkSetDebugUtilsObjectNameEXT, about one run in ten of the reference
/// tests, which open renderers on several threads). These calls are few, so the lock costs nothing else.
pub(crate) fn loader_lock() -> std::sync::MutexGuard<'static, ()> {
    static LOCK: std::sync::Mutex<()> = std::sync::Mutex::new(());
    LOCK.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

pub use buffer::{Buffer, BufferDesc};
pub use descriptor::{Descriptor, DescriptorPool};
pub use device::{list_devices, preferred_device, version_string, Device, DeviceInfo, DEFAULT_TIMEOUT};
pub use image::{layer_range, layout_transition, whole_image_copy, Access, Image, ImageDesc, ImageView};
pub use instance::{Instance, ValidationLog, INSTALL_HINT, SYNC_VALIDATION_SEES_DYNAMIC_RENDERING};
pub use pipeline::{GraphicsPipelineDesc, Pipeline, PipelineLayout};
pub use sampler::Sampler;
pub use shader::{ShaderCompiler, ShaderModule, ShaderSources};
#[cfg(feature = "preview")]
pub use swapchain::{Surface, Swapchain};
