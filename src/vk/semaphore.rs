//! A binary semaphore: orders one submission or presentation after another on the device.
//! Dropping it while a submission uses it is safe: it is destroyed after that submission.

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use super::deferred::Doomed;
use super::error::{Named, VkResult};

/// An owned binary semaphore.
pub struct Semaphore {
    ctx: Arc<Context>,
    raw: vk::Semaphore,
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
        })
    }

    /// The raw handle, for submissions and presentation.
    pub(crate) fn raw(&self) -> vk::Semaphore {
        self.raw
    }
}

impl Drop for Semaphore {
    fn drop(&mut self) {
        // Submissions that wait on or signal it may still be pending: destroyed after them.
        self.ctx.defer(Doomed::Semaphore(self.raw));
    }
}
