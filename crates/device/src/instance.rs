//! Vulkan instance creation, validation layers and the debug messenger that turns validation
//! errors into data the caller can check.

use std::ffi::{c_void, CStr};
use std::sync::{Arc, Mutex};

use ash::{ext, vk};

use crate::error::{DeviceError, Result, VkContext};

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";

/// Validation messages of severity "error", collected by the debug messenger.
#[derive(Default)]
pub(crate) struct ValidationLog {
    pub errors: Mutex<Vec<String>>,
}

pub(crate) struct InstanceParts {
    /// Keeps the loader library loaded while the instance lives.
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub debug_utils: Option<ext::debug_utils::Instance>,
    pub messenger: vk::DebugUtilsMessengerEXT,
    pub validation: bool,
    /// Kept alive for the messenger's user-data pointer.
    pub log: Arc<ValidationLog>,
}

/// Whether validation is wanted: `LEAKLESS_VALIDATION=1` turns it on, `=0` off; otherwise the
/// caller's default (tests default to on).
pub(crate) fn validation_wanted(default: bool) -> bool {
    match std::env::var("LEAKLESS_VALIDATION").as_deref() {
        Ok("1") | Ok("true") | Ok("on") => true,
        Ok("0") | Ok("false") | Ok("off") => false,
        _ => default,
    }
}

/// Creates the instance, with `extra_extensions` (the window system's surface extensions
/// when the device will present).
pub(crate) fn create(want_validation: bool, extra_extensions: &[*const std::ffi::c_char]) -> Result<InstanceParts> {
    // SAFETY: loading the Vulkan loader library; its symbols are only used through ash.
    let entry = unsafe { ash::Entry::load() }.map_err(|e| DeviceError::Loader(e.to_string()))?;
    // SAFETY: plain queries on a loaded entry.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }.vk("vkEnumerateInstanceLayerProperties")?;
    let has_layer = layers.iter().any(|l| l.layer_name_as_c_str() == Ok(VALIDATION_LAYER));
    let exts =
        unsafe { entry.enumerate_instance_extension_properties(None) }.vk("vkEnumerateInstanceExtensionProperties")?;
    let has_debug_utils = exts.iter().any(|e| e.extension_name_as_c_str() == Ok(ext::debug_utils::NAME));

    let validation = want_validation && has_layer && has_debug_utils;
    if want_validation && !validation {
        log::warn!("warning: Vulkan validation requested but VK_LAYER_KHRONOS_validation is not installed (apt install vulkan-validationlayers)");
    }

    let app = vk::ApplicationInfo::default()
        .application_name(c"leakless")
        .engine_name(c"leakless")
        .api_version(vk::API_VERSION_1_3);
    let layer_names = if validation { vec![VALIDATION_LAYER.as_ptr()] } else { vec![] };
    let mut ext_names = if has_debug_utils { vec![ext::debug_utils::NAME.as_ptr()] } else { vec![] };
    ext_names.extend_from_slice(extra_extensions);
    let info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layer_names)
        .enabled_extension_names(&ext_names);
    // SAFETY: all pointers in `info` outlive the call.
    let instance = unsafe { entry.create_instance(&info, None) }.vk("vkCreateInstance")?;

    let log = Arc::new(ValidationLog::default());
    let debug_utils = has_debug_utils.then(|| ext::debug_utils::Instance::new(&entry, &instance));
    let mut messenger = vk::DebugUtilsMessengerEXT::null();
    if let (true, Some(du)) = (validation, &debug_utils) {
        let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
            .message_severity(
                vk::DebugUtilsMessageSeverityFlagsEXT::ERROR | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING,
            )
            .message_type(
                vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
            )
            .pfn_user_callback(Some(on_message))
            .user_data(Arc::as_ptr(&log) as *mut c_void);
        // SAFETY: the user-data pointer stays valid while `log` lives in InstanceParts, which
        // destroys the messenger before dropping it.
        messenger = unsafe { du.create_debug_utils_messenger(&info, None) }.vk("vkCreateDebugUtilsMessengerEXT")?;
    }
    Ok(InstanceParts { entry, instance, debug_utils, messenger, validation, log })
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    // SAFETY: the layer passes a valid callback-data pointer for the duration of the call,
    // and `user` is the ValidationLog kept alive by InstanceParts.
    let (message, log) = unsafe {
        let msg = (*data).message_as_c_str().map(|m| m.to_string_lossy().into_owned()).unwrap_or_default();
        (msg, &*(user as *const ValidationLog))
    };
    if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
        log::error!("validation error: {message}");
        if let Ok(mut errors) = log.errors.lock() {
            errors.push(message);
        }
    } else {
        log::warn!("validation warning: {message}");
    }
    vk::FALSE
}

impl InstanceParts {
    /// # Safety
    /// Every object created from the instance must already be destroyed.
    pub unsafe fn destroy(&mut self) {
        // SAFETY: per the function contract.
        unsafe {
            if let Some(du) = &self.debug_utils {
                if self.messenger != vk::DebugUtilsMessengerEXT::null() {
                    du.destroy_debug_utils_messenger(self.messenger, None);
                }
            }
            self.instance.destroy_instance(None);
        }
    }
}
