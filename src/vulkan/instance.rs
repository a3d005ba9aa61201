//! The Vulkan instance, and the validation layer's debug messenger when asked for.

use std::ffi::{c_void, CStr};
use std::sync::Mutex;

use ash::{ext, vk};

use crate::error::{Error, Result};

/// What to tell a user whose machine has no Vulkan loader or no Vulkan device.
pub const INSTALL_HINT: &str = "vk-render needs a Vulkan loader and a Vulkan device. On Debian or Ubuntu, install \
     Mesa's CPU device lavapipe and the loader: sudo apt-get install mesa-vulkan-drivers libvulkan1 \
     (or run `make setup`); on a machine with a GPU, install its vendor's Vulkan driver";

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// The Vulkan loader and instance; owns the debug messenger, which it destroys first.
pub struct Instance {
    /// The loaded Vulkan loader's entry points.
    pub entry: ash::Entry,
    /// The ash instance: its function table and handle.
    pub raw: ash::Instance,
    debug: Option<DebugMessenger>,
    /// Set when a device of this instance was given up with work that never finished (see
    /// `Device::give_up`): the instance is then never destroyed, the device still existing.
    given_up: std::sync::atomic::AtomicBool,
}

/// The first Khronos validation layer whose synchronization validation sees hazards inside dynamic rendering
/// (1.3.268, KhronosGroup/Vulkan-ValidationLayers#6860): older layers (Debian 12 has 1.3.239) are blind
/// between vkCmdBeginRendering and the barriers after vkCmdEndRendering.
pub const SYNC_VALIDATION_SEES_DYNAMIC_RENDERING: u32 = vk::make_api_version(0, 1, 3, 268);

/// The validation layer's messages, collected so that tests and `--validate` can fail on any of them.
#[derive(Default)]
pub struct ValidationLog {
    messages: Mutex<Vec<String>>,
}

impl ValidationLog {
    /// Takes the messages reported so far.
    pub fn take(&self) -> Vec<String> {
        std::mem::take(&mut *self.messages.lock().unwrap_or_else(|poisoned| poisoned.into_inner()))
    }

    fn push(&self, message: String) {
        self.messages.lock().unwrap_or_else(|poisoned| poisoned.into_inner()).push(message);
    }
}

struct DebugMessenger {
    loader: ext::debug_utils::Instance,
    raw: vk::DebugUtilsMessengerEXT,
    /// The validation layer's version (its spec version: 1.3.239 on Debian 12).
    layer_version: u32,
    /// Boxed so that its address, given to the layer as user data, stays fixed; freed after `raw`.
    log: Box<ValidationLog>,
}

impl Instance {
    /// Loads Vulkan and creates an instance, with the Khronos validation layer when `validate` is set and
    /// the instance `extensions` asked for (a window surface's, for the preview).
    ///
    /// # Errors
    /// `Error::NoVulkan` with installation advice when there is no loader, no driver, or (with `validate`)
    /// no validation layer.
    pub fn new(validate: bool, extensions: &[&'static CStr]) -> Result<Instance> {
        // SAFETY: loading libvulkan.so.1 runs its initialisers; the Vulkan loader is made for that.
        let entry = unsafe { ash::Entry::load() }
            .map_err(|e| Error::NoVulkan(format!("no Vulkan loader could be opened ({e}). {INSTALL_HINT}")))?;
        let mut layer_version = 0;
        if validate {
            // SAFETY: a plain query with no handles.
            let layers = unsafe { entry.enumerate_instance_layer_properties()? };
            let found = layers.iter().find(|l| l.layer_name_as_c_str().is_ok_and(|name| name == VALIDATION_LAYER));
            let Some(layer) = found else {
                return Err(Error::NoVulkan(
                    "validation was asked for, but the Khronos validation layer is not installed: \
                     sudo apt-get install vulkan-validationlayers (or run `make setup`)"
                        .into(),
                ));
            };
            layer_version = layer.spec_version;
        }

        let app_info = vk::ApplicationInfo::default()
            .application_name(c"vk-render")
            .engine_name(c"vk-render")
            .api_version(vk::API_VERSION_1_3);
        let layers = if validate { vec![VALIDATION_LAYER.as_ptr()] } else { vec![] };
        let mut names: Vec<*const std::ffi::c_char> = extensions.iter().map(|e| e.as_ptr()).collect();
        if validate {
            names.push(ext::debug_utils::NAME.as_ptr());
        }
        let log = Box::new(ValidationLog::default());
        let mut messenger_info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::WARNING | vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                    | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                    | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(debug_callback))
            .user_data(std::ptr::from_ref::<ValidationLog>(&log).cast_mut().cast());
        // Synchronization validation also checks barriers and layouts, the errors that lavapipe forgives.
        let enabled_features = [vk::ValidationFeatureEnableEXT::SYNCHRONIZATION_VALIDATION];
        let mut validation_features =
            vk::ValidationFeaturesEXT::default().enabled_validation_features(&enabled_features);
        let mut create_info = vk::InstanceCreateInfo::default()
            .application_info(&app_info)
            .enabled_layer_names(&layers)
            .enabled_extension_names(&names);
        if validate {
            // Chained here too so that messages from instance creation and destruction are caught.
            create_info = create_info.push_next(&mut messenger_info).push_next(&mut validation_features);
        }
        let loader_lock = super::loader_lock();
        // SAFETY: every pointer in create_info outlives the call.
        let raw = unsafe { entry.create_instance(&create_info, None) }.map_err(|e| match e {
            vk::Result::ERROR_INCOMPATIBLE_DRIVER | vk::Result::ERROR_INITIALIZATION_FAILED => {
                Error::NoVulkan(format!("no Vulkan driver was found ({e}). {INSTALL_HINT}"))
            }
            other => Error::Vulkan(other),
        })?;

        let debug = if validate {
            let loader = ext::debug_utils::Instance::new(&entry, &raw);
            // SAFETY: the instance is alive and has the debug-utils extension enabled.
            match unsafe { loader.create_debug_utils_messenger(&messenger_info, None) } {
                Ok(messenger) => Some(DebugMessenger { loader, raw: messenger, layer_version, log }),
                Err(e) => {
                    // SAFETY: nothing was created from the instance yet.
                    unsafe { raw.destroy_instance(None) };
                    return Err(e.into());
                }
            }
        } else {
            None
        };
        drop(loader_lock);
        Ok(Instance { entry, raw, debug, given_up: std::sync::atomic::AtomicBool::new(false) })
    }

    /// Keeps the instance alive for the rest of the process: a device of it was given up.
    pub(super) fn give_up(&self) {
        self.given_up.store(true, std::sync::atomic::Ordering::SeqCst);
    }

    /// Whether the validation layer is on.
    pub fn validating(&self) -> bool {
        self.debug.is_some()
    }

    /// The validation layer's version, when it is on.
    pub fn validation_layer_version(&self) -> Option<u32> {
        self.debug.as_ref().map(|d| d.layer_version)
    }

    /// Takes the validation messages reported since the last call (none without validation).
    pub fn take_validation_messages(&self) -> Vec<String> {
        self.debug.as_ref().map(|d| d.log.take()).unwrap_or_default()
    }
}

impl Drop for Instance {
    fn drop(&mut self) {
        if self.given_up.load(std::sync::atomic::Ordering::SeqCst) {
            return;
        }
        // SAFETY: every device and object made from this instance is gone: they hold an Arc of it.
        unsafe {
            let _loader = super::loader_lock();
            if let Some(debug) = &self.debug {
                debug.loader.destroy_debug_utils_messenger(debug.raw, None);
            }
            self.raw.destroy_instance(None);
        }
    }
}

/// Logs each message and keeps validation and performance warnings and errors for `take_validation_messages`.
unsafe extern "system" fn debug_callback(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    kind: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user_data: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes valid callback data for the duration of the call.
    let data = unsafe { data.as_ref() };
    let text_of = |text: Option<&CStr>| text.map(|t| t.to_string_lossy().into_owned());
    // SAFETY: the strings of valid callback data are null or null-terminated.
    let message = text_of(data.and_then(|d| unsafe { d.message_as_c_str() })).unwrap_or("(no message)".into());
    // The message's identifier (a VUID, or SYNC-HAZARD-...): newer layers leave it out of the message text.
    // SAFETY: as above.
    let id = text_of(data.and_then(|d| unsafe { d.message_id_name_as_c_str() })).unwrap_or_default();
    let text = format!("[{kind:?} {severity:?}] [{id}] {message}");
    if kind.intersects(vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE) {
        log::error!("validation: {text}");
        // SAFETY: user_data is the boxed ValidationLog, alive until after the messenger is destroyed.
        if let Some(log) = unsafe { user_data.cast::<ValidationLog>().as_ref() } {
            log.push(text);
        }
    } else {
        log::warn!("vulkan: {text}");
    }
    vk::FALSE
}
