//! Physical device choice, the logical device, its graphics queue and the memory allocator.

use std::ffi::CStr;
use std::mem::ManuallyDrop;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};
use std::sync::{Arc, Mutex, MutexGuard};
use std::time::Duration;

use ash::{khr, vk};
use gpu_allocator::vulkan::{Allocator, AllocatorCreateDesc};
use gpu_allocator::AllocationSizes;

use super::Instance;
use crate::error::{Error, Result};

/// What `vk-render devices` shows of each physical device.
#[derive(Clone, Debug)]
pub struct DeviceInfo {
    /// Its place in the loader's order: what `--device` takes as a number.
    pub index: usize,
    /// The driver's name for the device, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    pub name: String,
    /// Discrete, integrated, virtual GPU, CPU or other: see [`DeviceInfo::kind_name`].
    pub kind: vk::PhysicalDeviceType,
    /// Vulkan version the driver offers.
    pub api_version: u32,
    /// The driver's own version text (`driverInfo`), e.g. Mesa's version; empty if it gives none.
    pub driver: String,
    /// Which driver it is (lavapipe is `MESA_LLVMPIPE`).
    pub driver_id: vk::DriverId,
}

impl DeviceInfo {
    /// "discrete GPU", "CPU" and so on.
    pub fn kind_name(&self) -> &'static str {
        match self.kind {
            vk::PhysicalDeviceType::DISCRETE_GPU => "discrete GPU",
            vk::PhysicalDeviceType::INTEGRATED_GPU => "integrated GPU",
            vk::PhysicalDeviceType::VIRTUAL_GPU => "virtual GPU",
            vk::PhysicalDeviceType::CPU => "CPU",
            _ => "other",
        }
    }

    /// Whether this is Mesa's lavapipe (llvmpipe), whichever its version.
    pub fn is_lavapipe(&self) -> bool {
        self.driver_id == vk::DriverId::MESA_LLVMPIPE
    }

    /// Preference when no device is named: GPUs first, then lavapipe (CPU).
    fn rank(&self) -> u32 {
        match self.kind {
            vk::PhysicalDeviceType::DISCRETE_GPU => 0,
            vk::PhysicalDeviceType::INTEGRATED_GPU => 1,
            vk::PhysicalDeviceType::VIRTUAL_GPU => 2,
            vk::PhysicalDeviceType::CPU => 3,
            _ => 4,
        }
    }

    /// "1.3.230".
    pub fn api_version_string(&self) -> String {
        version_string(self.api_version)
    }
}

/// A Vulkan version number as "1.3.230".
pub fn version_string(v: u32) -> String {
    format!("{}.{}.{}", vk::api_version_major(v), vk::api_version_minor(v), vk::api_version_patch(v))
}

/// Lists the physical devices in the loader's order.
///
/// # Errors
/// `Error::Vulkan` if the enumeration fails.
pub fn list_devices(instance: &Instance) -> Result<Vec<(vk::PhysicalDevice, DeviceInfo)>> {
    let loader = super::loader_lock();
    // SAFETY: the instance is alive.
    let physical = unsafe { instance.raw.enumerate_physical_devices()? };
    drop(loader);
    Ok(physical
        .into_iter()
        .enumerate()
        .map(|(index, raw)| {
            let mut driver = vk::PhysicalDeviceDriverProperties::default();
            let mut properties2 = vk::PhysicalDeviceProperties2::default().push_next(&mut driver);
            // SAFETY: raw comes from this instance.
            unsafe { instance.raw.get_physical_device_properties2(raw, &mut properties2) };
            let p = properties2.properties;
            let name = p.device_name_as_c_str().map_or_else(|_| "?".into(), |n| n.to_string_lossy().into_owned());
            let driver_id = driver.driver_id;
            let driver =
                driver.driver_info_as_c_str().map_or_else(|_| String::new(), |n| n.to_string_lossy().into_owned());
            (raw, DeviceInfo { index, name, kind: p.device_type, api_version: p.api_version, driver, driver_id })
        })
        .collect())
}

/// The logical device with one graphics queue, its allocator and a command pool.
///
/// Every resource holds an `Arc<Device>`, so the device outlives them; it holds the instance the same way.
pub struct Device {
    /// The ash device: its function table and handle.
    pub raw: ash::Device,
    /// The physical device it was opened on.
    pub physical: vk::PhysicalDevice,
    /// What `vk-render devices` shows of it.
    pub info: DeviceInfo,
    /// The physical device's limits (image sizes, sample counts, ...), checked before a render asks for more.
    pub limits: vk::PhysicalDeviceLimits,
    /// The one queue every submission goes to: graphics and compute (and presenting, for the preview).
    pub queue: vk::Queue,
    /// The queue's family index.
    pub queue_family: u32,
    allocator: ManuallyDrop<Mutex<Allocator>>,
    command_pool: vk::CommandPool,
    /// The instance it was made from, kept alive as long as the device.
    pub instance: Arc<Instance>,
    /// VK_EXT_depth_range_unrestricted is enabled: depth may be cleared outside [0, 1], which the forward
    /// pass uses to mark the samples no object covers (render/resolve.rs).
    pub depth_range_unrestricted: bool,
    /// The shaderFloat64 feature is enabled: shaders may compute in double (`shaders/brdf_density64.comp`).
    pub float64: bool,
    /// How long a wait for submitted work may last, in nanoseconds ([`Device::set_timeout`]).
    timeout_ns: AtomicU64,
    /// Whether work was given up after it outlasted the timeout, or the device was lost: see
    /// [`Device::give_up`].
    given_up: AtomicBool,
    /// Whether the driver reported the device lost (the reason it was given up).
    lost: AtomicBool,
}

/// How long vk-render waits for the device to finish a piece of work before giving the device up (`--timeout`):
/// far longer than any of its images takes, and short enough that a shader that never ends is reported.
pub const DEFAULT_TIMEOUT: Duration = Duration::from_secs(30);

impl Device {
    /// Opens the device named by `selector` (an index from `vk-render devices`, or part of a name,
    /// case-insensitive), or else the best one that can do the work: a discrete or integrated GPU first, then
    /// lavapipe; with the device `extensions` asked for (the swapchain's, for the preview). With `present_to`
    /// (a window's surface), only a device with a queue family that can also present to it will do.
    ///
    /// # Errors
    /// `Error::NoVulkan` when there is no device at all, `Error::Device` when the selector matches none or
    /// no device offers what vk-render needs (each one's reason named).
    pub fn new(
        instance: Arc<Instance>,
        selector: Option<&str>,
        extensions: &[&'static CStr],
        present_to: Option<(&khr::surface::Instance, vk::SurfaceKHR)>,
    ) -> Result<Arc<Device>> {
        let devices = list_devices(&instance)?;
        let (physical, info, queue_family) = match selector {
            Some(selector) => {
                let (physical, info) = select(&devices, selector)?;
                let family = usable_queue_family(&instance, physical, &info, present_to)
                    .map_err(|why| Error::Device(format!("device {} ({}) {why}", info.index, info.name)))?;
                (physical, info, family)
            }
            None if devices.is_empty() => {
                return Err(Error::NoVulkan(format!("no Vulkan device was found. {}", super::instance::INSTALL_HINT)))
            }
            None => {
                let ((physical, info), family) = preferred_device(&instance, &devices, present_to)
                    .map_err(|reasons| Error::Device(format!("no Vulkan device will do: {}", reasons.join("; "))))?;
                (*physical, info.clone(), family)
            }
        };
        let priorities = [1.0];
        let queue_info =
            [vk::DeviceQueueCreateInfo::default().queue_family_index(queue_family).queue_priorities(&priorities)];
        let mut features13 =
            vk::PhysicalDeviceVulkan13Features::default().dynamic_rendering(true).synchronization2(true);
        // Fragment stores: an analytic model's report of invalid values (shaders/common/analytic.glsl).
        // Doubles where offered: a .brdf file's integrals in double precision (shaders/brdf_density64.comp).
        // SAFETY: physical comes from this instance.
        let float64 = unsafe { instance.raw.get_physical_device_features(physical) }.shader_float64 == vk::TRUE;
        let features = vk::PhysicalDeviceFeatures::default()
            .image_cube_array(true)
            .fragment_stores_and_atomics(true)
            .shader_float64(float64);
        // SAFETY: physical comes from this instance.
        let offered = unsafe { instance.raw.enumerate_device_extension_properties(physical)? };
        let unrestricted = ash::ext::depth_range_unrestricted::NAME;
        let depth_range_unrestricted = offered.iter().any(|e| e.extension_name_as_c_str() == Ok(unrestricted));
        let extension_names: Vec<*const std::ffi::c_char> =
            extensions.iter().chain(depth_range_unrestricted.then_some(&unrestricted)).map(|e| e.as_ptr()).collect();
        let create_info = vk::DeviceCreateInfo::default()
            .queue_create_infos(&queue_info)
            .enabled_extension_names(&extension_names)
            .enabled_features(&features)
            .push_next(&mut features13);
        // SAFETY: create_info and what it points to outlive the call.
        let raw = {
            let _loader = super::loader_lock();
            unsafe { instance.raw.create_device(physical, &create_info, None)? }
        };
        // SAFETY: the family was created with one queue.
        let queue = unsafe { raw.get_device_queue(queue_family, 0) };
        // SAFETY: physical comes from this instance.
        let limits = unsafe { instance.raw.get_physical_device_properties(physical) }.limits;

        let allocator = Allocator::new(&AllocatorCreateDesc {
            instance: instance.raw.clone(),
            device: raw.clone(),
            physical_device: physical,
            debug_settings: Default::default(),
            buffer_device_address: false,
            allocation_sizes: AllocationSizes::default(),
        });
        let allocator = match allocator {
            Ok(a) => a,
            Err(e) => {
                // SAFETY: nothing was created from the device yet.
                unsafe { raw.destroy_device(None) };
                return Err(e.into());
            }
        };
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(queue_family)
            .flags(vk::CommandPoolCreateFlags::TRANSIENT | vk::CommandPoolCreateFlags::RESET_COMMAND_BUFFER);
        // SAFETY: the device is alive. On failure the allocator drops before the device is destroyed.
        let command_pool = match unsafe { raw.create_command_pool(&pool_info, None) } {
            Ok(pool) => pool,
            Err(e) => {
                drop(allocator);
                unsafe { raw.destroy_device(None) };
                return Err(e.into());
            }
        };
        log::info!("using Vulkan device {} ({}, {}) {}", info.index, info.name, info.kind_name(), info.driver);
        Ok(Arc::new(Device {
            raw,
            physical,
            info,
            limits,
            queue,
            queue_family,
            allocator: ManuallyDrop::new(Mutex::new(allocator)),
            command_pool,
            instance,
            depth_range_unrestricted,
            float64,
            timeout_ns: AtomicU64::new(DEFAULT_TIMEOUT.as_nanos() as u64),
            given_up: AtomicBool::new(false),
            lost: AtomicBool::new(false),
        }))
    }

    /// Sets how long a wait for submitted work may last ([`DEFAULT_TIMEOUT`] until set).
    pub fn set_timeout(&self, timeout: Duration) {
        self.timeout_ns.store(timeout.as_nanos().min(u128::from(u64::MAX)) as u64, Ordering::SeqCst);
    }

    /// How long a wait for submitted work may last.
    pub fn timeout(&self) -> Duration {
        Duration::from_nanos(self.timeout_ns.load(Ordering::SeqCst))
    }

    /// Whether the device was given up (work outlasted the timeout and may still run).
    pub fn is_given_up(&self) -> bool {
        self.given_up.load(Ordering::SeqCst)
    }

    /// Gives the device up: work that may never finish (a user's shader that loops for ever) may still use
    /// every object, so none is destroyed from now on (each owner's Drop leaves it, and the device and
    /// instance are never destroyed): the memory stays taken until the process ends, which it should soon.
    fn give_up(&self) {
        self.given_up.store(true, Ordering::SeqCst);
        self.instance.give_up();
    }

    /// The memory allocator.
    pub fn allocator(&self) -> MutexGuard<'_, Allocator> {
        self.allocator.lock().unwrap_or_else(|poisoned| poisoned.into_inner())
    }

    /// Records one command buffer with `record`, submits it and waits for it to finish, at most
    /// [`Device::timeout`].
    ///
    /// # Errors
    /// What `record` returns, `Error::Vulkan` from recording, submission or the wait, `Error::Timeout` when
    /// the work outlasts the timeout (the device is then given up: every later submission fails so too).
    pub fn submit_and_wait(&self, record: impl FnOnce(vk::CommandBuffer) -> Result<()>) -> Result<()> {
        self.submit_and_wait_with(&[], &[], record)
    }

    /// As [`Device::submit_and_wait`], the submission first waiting for `wait` (semaphore, stage) and then
    /// signalling `signal` (a swapchain's acquire and present semaphores).
    ///
    /// # Errors
    /// As [`Device::submit_and_wait`].
    pub fn submit_and_wait_with(
        &self,
        wait: &[(vk::Semaphore, vk::PipelineStageFlags2)],
        signal: &[vk::Semaphore],
        record: impl FnOnce(vk::CommandBuffer) -> Result<()>,
    ) -> Result<()> {
        let alloc_info = vk::CommandBufferAllocateInfo::default()
            .command_pool(self.command_pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        let waits: Vec<_> = wait
            .iter()
            .map(|&(semaphore, stage)| vk::SemaphoreSubmitInfo::default().semaphore(semaphore).stage_mask(stage))
            .collect();
        let signals: Vec<_> = signal
            .iter()
            .map(|&semaphore| {
                vk::SemaphoreSubmitInfo::default()
                    .semaphore(semaphore)
                    .stage_mask(vk::PipelineStageFlags2::ALL_COMMANDS)
            })
            .collect();
        let timeout = self.timeout();
        if self.lost.load(Ordering::SeqCst) {
            return Err(Error::Vulkan(vk::Result::ERROR_DEVICE_LOST));
        }
        if self.is_given_up() {
            return Err(Error::Timeout { seconds: timeout.as_secs_f64(), models: Vec::new() });
        }
        // SAFETY: the pool belongs to this device; each step's handles are freed below on every path but a
        // timeout, where the work may still use them.
        unsafe {
            let cmd = self.raw.allocate_command_buffers(&alloc_info)?[0];
            let fence = match self.raw.create_fence(&vk::FenceCreateInfo::default(), None) {
                Ok(f) => f,
                Err(e) => {
                    self.raw.free_command_buffers(self.command_pool, &[cmd]);
                    return Err(e.into());
                }
            };
            let result = (|| {
                let begin = vk::CommandBufferBeginInfo::default().flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
                self.raw.begin_command_buffer(cmd, &begin)?;
                record(cmd)?;
                self.raw.end_command_buffer(cmd)?;
                let cmd_info = [vk::CommandBufferSubmitInfo::default().command_buffer(cmd)];
                let submit = [vk::SubmitInfo2::default()
                    .wait_semaphore_infos(&waits)
                    .command_buffer_infos(&cmd_info)
                    .signal_semaphore_infos(&signals)];
                self.raw.queue_submit2(self.queue, &submit, fence)?;
                let nanos = u64::try_from(timeout.as_nanos()).unwrap_or(u64::MAX);
                self.raw.wait_for_fences(&[fence], true, nanos)?;
                Ok(())
            })();
            if matches!(result, Err(Error::Vulkan(vk::Result::TIMEOUT))) {
                self.give_up();
                return Err(Error::Timeout { seconds: timeout.as_secs_f64(), models: Vec::new() });
            }
            // A failed submission may leave work queued: finish it before freeing what it uses. A lost device
            // finishes nothing, and its fences and command buffers stay in use for good (on an NVIDIA GPU, a
            // shader that never ends in another process can take this one's work with it): given up, as
            // after a timeout, so that nothing it may still use is destroyed.
            let lost = matches!(result, Err(Error::Vulkan(vk::Result::ERROR_DEVICE_LOST)))
                || (result.is_err() && self.raw.device_wait_idle() == Err(vk::Result::ERROR_DEVICE_LOST));
            if lost {
                self.lost.store(true, Ordering::SeqCst);
                self.give_up();
                return Err(Error::Vulkan(vk::Result::ERROR_DEVICE_LOST));
            }
            self.raw.destroy_fence(fence, None);
            self.raw.free_command_buffers(self.command_pool, &[cmd]);
            result
        }
    }

    /// Checks that `format` has the `needed` features with optimal tiling, for `what` (named in the error).
    ///
    /// # Errors
    /// `Error::Device` naming the device, the format and its use.
    pub fn require_format(&self, format: vk::Format, needed: vk::FormatFeatureFlags, what: &str) -> Result<()> {
        // SAFETY: a plain query on a live physical device.
        let properties = unsafe { self.instance.raw.get_physical_device_format_properties(self.physical, format) };
        if properties.optimal_tiling_features.contains(needed) {
            Ok(())
        } else {
            Err(Error::Device(format!(
                "device {} ({}) cannot use {format:?} for {what} (it needs {needed:?})",
                self.info.index, self.info.name
            )))
        }
    }

    /// Gives a handle a name that validation messages and debuggers show.
    pub fn set_name<H: vk::Handle>(&self, handle: H, name: &str) {
        if !self.instance.validating() {
            return;
        }
        let Ok(name) = std::ffi::CString::new(name) else { return };
        let loader = ash::ext::debug_utils::Device::new(&self.instance.raw, &self.raw);
        let info = vk::DebugUtilsObjectNameInfoEXT::default().object_handle(handle).object_name(&name);
        let _loader = super::loader_lock();
        // SAFETY: the handle belongs to this device; naming is advisory, so a failure is ignored.
        let _ = unsafe { loader.set_debug_utils_object_name(&info) };
    }
}

/// The queue family that vk-render submits all its work to on this device: graphics and compute (which
/// imply transfer), and presentation to `present_to` when given; or why the device will not do (below Vulkan
/// 1.3, or without a feature the passes use: dynamic rendering, synchronization2, cube arrays for the
/// shadow cubes, stores from fragment shaders for the analytic models' reports).
fn usable_queue_family(
    instance: &Instance,
    physical: vk::PhysicalDevice,
    info: &DeviceInfo,
    present_to: Option<(&khr::surface::Instance, vk::SurfaceKHR)>,
) -> std::result::Result<u32, String> {
    if info.api_version < vk::API_VERSION_1_3 {
        return Err(format!("offers Vulkan {}, and vk-render needs 1.3", info.api_version_string()));
    }
    let mut features13 = vk::PhysicalDeviceVulkan13Features::default();
    let mut features = vk::PhysicalDeviceFeatures2::default().push_next(&mut features13);
    // SAFETY: physical comes from this instance.
    unsafe { instance.raw.get_physical_device_features2(physical, &mut features) };
    let (cube_array, fragment_stores) =
        (features.features.image_cube_array, features.features.fragment_stores_and_atomics);
    let missing: Vec<&str> = [
        (features13.dynamic_rendering, "dynamicRendering"),
        (features13.synchronization2, "synchronization2"),
        (cube_array, "imageCubeArray"),
        (fragment_stores, "fragmentStoresAndAtomics"),
    ]
    .into_iter()
    .filter(|(supported, _)| *supported == vk::FALSE)
    .map(|(_, name)| name)
    .collect();
    if !missing.is_empty() {
        return Err(format!("lacks the feature(s) {}", missing.join(", ")));
    }
    // SAFETY: physical comes from this instance.
    let families = unsafe { instance.raw.get_physical_device_queue_family_properties(physical) };
    let work = vk::QueueFlags::GRAPHICS | vk::QueueFlags::COMPUTE;
    let can_present = |family: u32| match present_to {
        // SAFETY: the surface was made from this instance and is alive; a failed query counts as no.
        Some((loader, surface)) => {
            unsafe { loader.get_physical_device_surface_support(physical, family, surface) }.unwrap_or(false)
        }
        None => true,
    };
    let family =
        (0..families.len() as u32).find(|&f| families[f as usize].queue_flags.contains(work) && can_present(f));
    family.ok_or_else(|| match present_to {
        Some(_) => "has no queue that can both render and present to this window".to_string(),
        None => "has no queue for graphics and compute".to_string(),
    })
}

/// The device used when none is named, and its queue family: the first that can do the work (see
/// [`Device::new`]) of the discrete GPUs, then the integrated, the virtual, and lavapipe (CPU), in the loader's
/// order among equals; or why each will not do.
pub fn preferred_device<'a>(
    instance: &Instance,
    devices: &'a [(vk::PhysicalDevice, DeviceInfo)],
    present_to: Option<(&khr::surface::Instance, vk::SurfaceKHR)>,
) -> std::result::Result<(&'a (vk::PhysicalDevice, DeviceInfo), u32), Vec<String>> {
    let mut ranked: Vec<_> = devices.iter().collect();
    ranked.sort_by_key(|(_, info)| info.rank());
    let mut reasons = Vec::new();
    for device in ranked {
        match usable_queue_family(instance, device.0, &device.1, present_to) {
            Ok(family) => return Ok((device, family)),
            Err(why) => reasons.push(format!("device {} ({}) {why}", device.1.index, device.1.name)),
        }
    }
    Err(reasons)
}

/// Finds a device by index or by part of its name.
fn select(devices: &[(vk::PhysicalDevice, DeviceInfo)], selector: &str) -> Result<(vk::PhysicalDevice, DeviceInfo)> {
    let wanted = selector.to_lowercase();
    let found = match selector.parse::<usize>() {
        Ok(index) => devices.iter().find(|(_, info)| info.index == index),
        Err(_) => devices.iter().find(|(_, info)| info.name.to_lowercase().contains(&wanted)),
    };
    found.cloned().ok_or_else(|| {
        let names: Vec<_> = devices.iter().map(|(_, info)| format!("{}: {}", info.index, info.name)).collect();
        Error::Device(format!("--device {selector:?} matches no Vulkan device (devices: {})", names.join("; ")))
    })
}

impl Drop for Device {
    fn drop(&mut self) {
        if self.is_given_up() {
            return;
        }
        // SAFETY: all resources made from this device hold an Arc of it, so none is left. The allocator
        // frees its memory blocks on drop, which must happen before the device is destroyed.
        unsafe {
            let _ = self.raw.device_wait_idle();
            self.raw.destroy_command_pool(self.command_pool, None);
            ManuallyDrop::drop(&mut self.allocator);
            let _loader = super::loader_lock();
            self.raw.destroy_device(None);
        }
    }
}
