//! A window's presentation surface: the instance extensions a display needs, the `VkSurfaceKHR`
//! made from a window's raw handles, and whether a queue family can present to it. The context
//! owns the surface and destroys it before the instance.

use std::ffi::c_char;

use ash::{khr, vk};
use raw_window_handle::{RawDisplayHandle, RawWindowHandle};

use super::error::{Named, VkError, VkResult};

/// The raw handles of a window to present to. They are plain pointers: whoever passes them to
/// [`super::Context::new_presenting`] keeps the window alive until the context is dropped.
#[derive(Debug, Clone, Copy)]
pub struct WindowHandles {
    /// The display (X11, Wayland) or none.
    pub display: RawDisplayHandle,
    /// The window.
    pub window: RawWindowHandle,
}

/// The surface with its extension functions.
pub(crate) struct WindowSurface {
    pub loader: khr::surface::Instance,
    pub raw: vk::SurfaceKHR,
}

/// The instance extensions presenting on `display` needs.
pub(crate) fn surface_extensions(display: RawDisplayHandle) -> VkResult<&'static [*const c_char]> {
    ash_window::enumerate_required_extensions(display).map_err(|e| {
        VkError::Unsupported(format!(
            "presenting to this kind of window ({display:?}): {e}"
        ))
    })
}

impl WindowSurface {
    /// Creates the surface of `handles`' window.
    ///
    /// # Safety
    /// The window must outlive the surface, and `instance` must have been created with
    /// [`surface_extensions`] of its display.
    pub unsafe fn new(
        entry: &ash::Entry,
        instance: &ash::Instance,
        handles: &WindowHandles,
    ) -> VkResult<WindowSurface> {
        // SAFETY: the caller's contract.
        let raw = unsafe {
            ash_window::create_surface(entry, instance, handles.display, handles.window, None)
        }
        .named("vkCreate*SurfaceKHR")?;
        Ok(WindowSurface {
            loader: khr::surface::Instance::new(entry, instance),
            raw,
        })
    }

    /// Whether `family` of `physical` can present to this surface.
    pub fn supports(&self, physical: vk::PhysicalDevice, family: u32) -> bool {
        // SAFETY: plain query on a valid physical device and surface.
        unsafe {
            self.loader
                .get_physical_device_surface_support(physical, family, self.raw)
        }
        .unwrap_or(false)
    }

    /// Destroys the surface.
    ///
    /// # Safety
    /// No swapchain of this surface is left, and it is called once.
    pub unsafe fn destroy(&self) {
        // SAFETY: the caller's contract.
        unsafe { self.loader.destroy_surface(self.raw, None) };
    }
}
