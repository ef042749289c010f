//! A binary semaphore: orders one submission or presentation after another on the device.
//! Dropping it while a submission uses it is safe: it is destroyed after that submission. An
//! engine's own semaphore can be borrowed, so relief's submissions wait on or signal it.

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use super::deferred::Doomed;
use super::error::{Named, VkResult};

/// A binary semaphore: relief's own, or an engine's borrowed one ([`Semaphore::borrowed`]).
pub struct Semaphore {
    ctx: Arc<Context>,
    raw: vk::Semaphore,
    owned: bool,
}

impl Semaphore {
    /// Creates an unsignalled semaphore named `name`.
    pub fn new(ctx: &Arc<Context>, name: &str) -> VkResult<Semaphore> {
        // SAFETY: valid device and create info.
        let raw = unsafe {
            ctx.device()
                .create_semaphore(&vk::SemaphoreCreateInfo::default(), None)
        }
        .named("vkCreateSemaphore")?;
        ctx.set_name(raw, name);
        Ok(Semaphore {
            ctx: ctx.clone(),
            raw,
            owned: true,
        })
    }

    /// The engine's binary semaphore `raw`, for relief's submissions to wait on or signal
    /// ([`crate::vk::SubmitSync`]); relief never destroys it.
    ///
    /// # Safety
    /// `raw` is a binary semaphore of `ctx`'s device, and it stays alive until every submission
    /// made with the returned value has finished (the engine destroys it after that). Waits and
    /// signals must pair up as Vulkan requires: each wait follows a signal submitted earlier.
    pub unsafe fn borrowed(ctx: &Arc<Context>, raw: vk::Semaphore) -> Semaphore {
        Semaphore {
            ctx: ctx.clone(),
            raw,
            owned: false,
        }
    }

    /// The raw handle, for submissions and presentation.
    pub(crate) fn raw(&self) -> vk::Semaphore {
        self.raw
    }
}

impl Drop for Semaphore {
    fn drop(&mut self) {
        if !self.owned {
            return;
        }
        // Submissions that wait on or signal it may still be pending: destroyed after them.
        self.ctx.defer(Doomed::Semaphore(self.raw));
    }
}
