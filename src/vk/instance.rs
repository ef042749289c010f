//! The Vulkan instance: loader, optional Khronos validation, and a debug messenger that counts what
//! the validation layer reports, so tests can demand zero errors at teardown.

use std::ffi::{c_char, c_void, CStr};
use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::Mutex;

use ash::{ext, vk};

use super::error::{Named, VkError, VkResult};
use super::surface::WindowSurface;

const VALIDATION_LAYER: &CStr = c"VK_LAYER_KHRONOS_validation";
/// How many validation messages are kept verbatim for reports; the rest are only counted.
const KEPT_MESSAGES: usize = 16;

/// Whether to enable the validation layer, from `RELIEF_VALIDATION` or the build profile.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Validation {
    /// On if the layer is installed (debug builds and tests).
    IfInstalled,
    /// Required: fail if the layer is missing.
    Required,
    /// Off.
    Off,
}

impl Validation {
    /// `RELIEF_VALIDATION=0|1` wins; otherwise debug builds validate when the layer is installed.
    pub fn from_env() -> Self {
        match std::env::var("RELIEF_VALIDATION").as_deref() {
            Ok("0") => Validation::Off,
            Ok("1") => Validation::Required,
            _ if cfg!(debug_assertions) => Validation::IfInstalled,
            _ => Validation::Off,
        }
    }
}

/// Counts of validation messages by severity, plus the first few error texts.
#[derive(Debug, Default)]
pub struct MessageCounts {
    errors: AtomicU32,
    warnings: AtomicU32,
    kept: Mutex<Vec<String>>,
}

impl MessageCounts {
    /// Number of validation errors reported so far.
    pub fn errors(&self) -> u32 {
        self.errors.load(Ordering::Relaxed)
    }

    /// Number of validation warnings reported so far.
    pub fn warnings(&self) -> u32 {
        self.warnings.load(Ordering::Relaxed)
    }

    /// The first error and warning messages, verbatim.
    pub fn kept_messages(&self) -> Vec<String> {
        self.kept.lock().map(|k| k.clone()).unwrap_or_default()
    }

    /// An error naming the validation errors reported so far, with the first messages, if there
    /// were any: a program that ran under the layer fails on them, since each is a bug.
    pub fn ensure_none(&self) -> VkResult<()> {
        match self.errors() {
            0 => Ok(()),
            n => Err(VkError::Invalid(format!(
                "the validation layer reported {n} error(s): {:?}",
                self.kept_messages()
            ))),
        }
    }

    fn record(&self, severity: vk::DebugUtilsMessageSeverityFlagsEXT, text: &str) {
        let counter = if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::ERROR) {
            log::error!("vulkan: {text}");
            &self.errors
        } else if severity.contains(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING) {
            log::warn!("vulkan: {text}");
            &self.warnings
        } else {
            log::debug!("vulkan: {text}");
            return;
        };
        counter.fetch_add(1, Ordering::Relaxed);
        if let Ok(mut kept) = self.kept.lock() {
            if kept.len() < KEPT_MESSAGES {
                kept.push(text.to_owned());
            }
        }
    }
}

/// The instance and what hangs off it; destroyed by [`super::Context`] in its written-out order.
pub(crate) struct InstanceParts {
    /// Keeps the loader library loaded for as long as the instance lives.
    pub entry: ash::Entry,
    pub instance: ash::Instance,
    pub debug_utils: Option<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)>,
    pub validation_enabled: bool,
    /// The window surface, for a context that presents.
    pub surface: Option<WindowSurface>,
}

/// Loads Vulkan and creates the instance with `extensions` (a window system's) besides relief's
/// own. `counts` must outlive the messenger: the context owns both.
pub(crate) fn create_instance(
    validation: Validation,
    counts: &MessageCounts,
    extensions: &[*const c_char],
) -> VkResult<InstanceParts> {
    // SAFETY: loading the system loader library runs its initialisers; nothing else is shared yet.
    let entry = unsafe { ash::Entry::load() }.map_err(|e| VkError::Loader(e.to_string()))?;
    let validation_enabled = match validation {
        Validation::Off => false,
        Validation::IfInstalled => layer_installed(&entry)?,
        Validation::Required if layer_installed(&entry)? => true,
        Validation::Required => {
            return Err(VkError::Unsupported(
                "the Khronos validation layer (RELIEF_VALIDATION=1); install it with: \
                 sudo apt-get install vulkan-validationlayers"
                    .into(),
            ))
        }
    };
    let debug_utils_present = extension_present(&entry, ext::debug_utils::NAME)?;

    let app = vk::ApplicationInfo::default()
        .application_name(c"relief")
        .engine_name(c"relief")
        .api_version(vk::API_VERSION_1_3);
    let layers = if validation_enabled {
        vec![VALIDATION_LAYER.as_ptr()]
    } else {
        vec![]
    };
    let mut extensions = extensions.to_vec();
    if debug_utils_present {
        extensions.push(ext::debug_utils::NAME.as_ptr());
    }
    let info = vk::InstanceCreateInfo::default()
        .application_info(&app)
        .enabled_layer_names(&layers)
        .enabled_extension_names(&extensions);
    // SAFETY: the create info and the arrays it points to live until the call returns.
    let instance = match unsafe { entry.create_instance(&info, None) } {
        // The loader's answer when it finds no driver at all: that is "no device", not a bug.
        Err(vk::Result::ERROR_INCOMPATIBLE_DRIVER) => return Err(VkError::NoDevice),
        other => other.named("vkCreateInstance")?,
    };

    let debug_utils = if debug_utils_present {
        match create_messenger(&entry, &instance, counts) {
            Ok(pair) => Some(pair),
            Err(e) => {
                // SAFETY: nothing was created from the instance yet.
                unsafe { instance.destroy_instance(None) };
                return Err(e);
            }
        }
    } else {
        None
    };
    Ok(InstanceParts {
        entry,
        instance,
        debug_utils,
        validation_enabled,
        surface: None,
    })
}

fn layer_installed(entry: &ash::Entry) -> VkResult<bool> {
    // SAFETY: plain enumeration on a loaded entry.
    let layers = unsafe { entry.enumerate_instance_layer_properties() }
        .named("vkEnumerateInstanceLayerProperties")?;
    Ok(layers
        .iter()
        .any(|l| l.layer_name_as_c_str().is_ok_and(|n| n == VALIDATION_LAYER)))
}

fn extension_present(entry: &ash::Entry, name: &CStr) -> VkResult<bool> {
    // SAFETY: plain enumeration on a loaded entry.
    let exts = unsafe { entry.enumerate_instance_extension_properties(None) }
        .named("vkEnumerateInstanceExtensionProperties")?;
    Ok(exts
        .iter()
        .any(|e| e.extension_name_as_c_str().is_ok_and(|n| n == name)))
}

fn create_messenger(
    entry: &ash::Entry,
    instance: &ash::Instance,
    counts: &MessageCounts,
) -> VkResult<(ext::debug_utils::Instance, vk::DebugUtilsMessengerEXT)> {
    let loader = ext::debug_utils::Instance::new(entry, instance);
    let info = vk::DebugUtilsMessengerCreateInfoEXT::default()
        .message_severity(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR
                | vk::DebugUtilsMessageSeverityFlagsEXT::WARNING
                | vk::DebugUtilsMessageSeverityFlagsEXT::INFO,
        )
        .message_type(
            vk::DebugUtilsMessageTypeFlagsEXT::GENERAL
                | vk::DebugUtilsMessageTypeFlagsEXT::VALIDATION
                | vk::DebugUtilsMessageTypeFlagsEXT::PERFORMANCE,
        )
        .pfn_user_callback(Some(on_message))
        .user_data(counts as *const MessageCounts as *mut c_void);
    // SAFETY: `counts` is owned (boxed) by the context and outlives the messenger, which the
    // context destroys before dropping it.
    let messenger = unsafe { loader.create_debug_utils_messenger(&info, None) }
        .named("vkCreateDebugUtilsMessengerEXT")?;
    Ok((loader, messenger))
}

unsafe extern "system" fn on_message(
    severity: vk::DebugUtilsMessageSeverityFlagsEXT,
    _types: vk::DebugUtilsMessageTypeFlagsEXT,
    data: *const vk::DebugUtilsMessengerCallbackDataEXT<'_>,
    user: *mut c_void,
) -> vk::Bool32 {
    if data.is_null() || user.is_null() {
        return vk::FALSE;
    }
    // SAFETY: the layer passes a valid callback-data struct for the duration of the call, and
    // `user` is the `MessageCounts` registered in `create_messenger`, alive while the messenger is.
    let (data, counts) = unsafe { (&*data, &*(user as *const MessageCounts)) };
    // SAFETY: p_message is a NUL-terminated string when non-null, valid during the callback.
    let text = unsafe { data.message_as_c_str() }
        .map(|m| m.to_string_lossy().into_owned())
        .unwrap_or_default();
    counts.record(severity, &text);
    vk::FALSE
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ensure_none_fails_on_an_error_and_names_it_but_not_on_a_warning() {
        let counts = MessageCounts::default();
        counts.record(vk::DebugUtilsMessageSeverityFlagsEXT::WARNING, "a warning");
        assert!(counts.ensure_none().is_ok(), "warnings are not errors");
        counts.record(
            vk::DebugUtilsMessageSeverityFlagsEXT::ERROR,
            "VUID-x: broken",
        );
        let message = counts.ensure_none().expect_err("one error").to_string();
        assert!(
            message.contains("1 error") && message.contains("VUID-x: broken"),
            "{message}"
        );
    }
}
