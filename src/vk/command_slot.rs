//! A command buffer that is recorded and submitted over and over: one frame in flight. Each slot
//! has its own command pool, so recording never shares a pool (and its lock) with another thread,
//! and its own fence, so the owner can wait for exactly the work it submitted and reuse the slot
//! without stalling on newer frames.

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use super::counters::Created;
use super::error::{Named, VkResult};
use super::recording::Recording;
use super::semaphore::Semaphore;

/// What a submission waits for before its commands reach `stage`, and what it signals when they
/// finish: a swapchain image's acquisition and its presentation.
#[derive(Clone, Copy, Default)]
pub struct SubmitSync<'a> {
    /// A semaphore to wait for, and the stage that waits.
    pub wait: Option<(&'a Semaphore, vk::PipelineStageFlags)>,
    /// A semaphore to signal once the commands finish.
    pub signal: Option<&'a Semaphore>,
}

/// A reusable command buffer with its pool and fence.
pub struct CommandSlot {
    ctx: Arc<Context>,
    pool: vk::CommandPool,
    cmd: vk::CommandBuffer,
    fence: vk::Fence,
    in_flight: bool,
    name: String,
}

impl CommandSlot {
    /// Creates the pool, the buffer and the fence.
    pub fn new(ctx: &Arc<Context>, name: &str) -> VkResult<CommandSlot> {
        let device = ctx.device();
        let pool_info = vk::CommandPoolCreateInfo::default()
            .queue_family_index(ctx.queue_family())
            .flags(vk::CommandPoolCreateFlags::TRANSIENT);
        // SAFETY: valid device and create info.
        let pool =
            unsafe { device.create_command_pool(&pool_info, None) }.named("vkCreateCommandPool")?;
        let mut slot = CommandSlot {
            ctx: ctx.clone(),
            pool,
            cmd: vk::CommandBuffer::null(),
            fence: vk::Fence::null(),
            in_flight: false,
            name: name.to_owned(),
        };
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: the pool belongs to this device and is used by this slot only.
        slot.cmd = unsafe { device.allocate_command_buffers(&alloc) }
            .named("vkAllocateCommandBuffers")?[0];
        ctx.count(Created::CommandBuffer);
        // SAFETY: valid device.
        slot.fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .named("vkCreateFence")?;
        ctx.count(Created::Fence);
        ctx.set_name(slot.pool, &format!("{name} pool"));
        ctx.set_name(slot.cmd, name);
        ctx.set_name(slot.fence, &format!("{name} fence"));
        Ok(slot)
    }

    /// Whether work submitted from this slot may still be running.
    pub fn in_flight(&self) -> bool {
        self.in_flight
    }

    /// Waits until the last submission from this slot has finished (at once if there is none).
    pub fn wait(&mut self) -> VkResult<()> {
        if !self.in_flight {
            return Ok(());
        }
        // SAFETY: the slot's own fence, alive until the slot drops.
        unsafe { self.ctx.wait_fence(self.fence, &self.name) }?;
        // SAFETY: the fence is signalled and no submission waits on it.
        unsafe { self.ctx.device().reset_fences(&[self.fence]) }.named("vkResetFences")?;
        self.in_flight = false;
        self.ctx.retire();
        Ok(())
    }

    /// Waits for the slot's previous work, records new commands with `record` and submits them.
    /// The recording lives only inside `record`.
    pub fn submit<R>(&mut self, record: impl FnOnce(&Recording) -> VkResult<R>) -> VkResult<R> {
        self.submit_synced(SubmitSync::default(), record)
    }

    /// As [`CommandSlot::submit`], ordered after and before other work by `sync`'s semaphores.
    pub fn submit_synced<R>(
        &mut self,
        sync: SubmitSync<'_>,
        record: impl FnOnce(&Recording) -> VkResult<R>,
    ) -> VkResult<R> {
        self.wait()?;
        let device = self.ctx.device();
        // SAFETY: the slot's previous submission has completed, so its pool's buffer is idle.
        unsafe { device.reset_command_pool(self.pool, vk::CommandPoolResetFlags::empty()) }
            .named("vkResetCommandPool")?;
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: the buffer was reset above.
        unsafe { device.begin_command_buffer(self.cmd, &begin) }.named("vkBeginCommandBuffer")?;
        let open = self.ctx.open_recording();
        let rec = Recording::new(device, self.cmd);
        let recorded = record(&rec);
        // SAFETY: recording was begun above; ending it also closes a recording cut short by an
        // error, so the pool reset next time finds no buffer in the recording state.
        let ended = unsafe { device.end_command_buffer(self.cmd) }.named("vkEndCommandBuffer");
        let value = recorded?;
        ended?;
        let waits: Vec<_> = sync
            .wait
            .iter()
            .map(|&(s, stage)| (s.raw(), stage))
            .collect();
        let signals: Vec<_> = sync.signal.iter().map(|s| s.raw()).collect();
        let timeline = self
            .ctx
            .submit_tracked(self.cmd, &waits, &signals, self.fence)?;
        rec.submitted(timeline);
        drop(open);
        self.in_flight = true;
        Ok(value)
    }
}

impl Drop for CommandSlot {
    fn drop(&mut self) {
        // A failed wait (device lost) still lets the objects go: the device is past using them.
        let _ = self.wait();
        if self.ctx.is_hung() && self.in_flight {
            // The hung submission may still use the buffer and signal the fence: leave both to
            // the process exit.
            return;
        }
        // SAFETY: no submission from this slot is pending; the fence and pool are ours alone.
        unsafe {
            self.ctx.device().destroy_fence(self.fence, None);
            self.ctx.device().destroy_command_pool(self.pool, None);
        }
        // A slot whose creation failed part-way counted only what it made.
        if self.cmd != vk::CommandBuffer::null() {
            self.ctx.count_destroyed(Created::CommandBuffer);
        }
        if self.fence != vk::Fence::null() {
            self.ctx.count_destroyed(Created::Fence);
        }
    }
}
