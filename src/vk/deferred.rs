//! Deferred destruction, retired by a timeline semaphore. Safe code may drop a buffer, image,
//! pipeline or pool while a submitted frame still reads it; the handles then wait here, tagged
//! with the last submission that may use them, until the GPU has passed that submission.
//!
//! Every queue submission in `vk` goes through [`Context::submit_tracked`], which also signals
//! the next value of the context's timeline semaphore. An object dropped while a recording is
//! still open (not yet submitted) may be referenced by that recording, whose value is not known
//! yet: it waits untagged until no recording is open, then takes the last submitted value.

use std::collections::VecDeque;
use std::sync::{Mutex, MutexGuard};

use ash::{khr, vk};
use gpu_allocator::vulkan::Allocation;

use super::context::Context;
use super::counters::Created;
use super::error::{Named, VkError, VkResult};
use super::faults::SubmitFault;

/// Handles whose owner has gone, waiting for the GPU to finish with them.
pub(crate) enum Doomed {
    Buffer(vk::Buffer, Option<Allocation>),
    Image(vk::Image, Option<Allocation>),
    ImageView(vk::ImageView),
    Sampler(vk::Sampler),
    /// With its bind point: graphics and compute pipelines are counted apart.
    Pipeline(vk::Pipeline, vk::PipelineLayout, vk::PipelineBindPoint),
    DescriptorPool(vk::DescriptorPool),
    DescriptorLayout(vk::DescriptorSetLayout),
    QueryPool(vk::QueryPool),
    Semaphore(vk::Semaphore),
    /// With the loader of its extension's functions.
    Swapchain(khr::swapchain::Device, vk::SwapchainKHR),
    /// With the loader of its extension's functions; its buffer is queued after it.
    AccelerationStructure(
        khr::acceleration_structure::Device,
        vk::AccelerationStructureKHR,
    ),
}

/// The timeline semaphore and what waits on it.
pub(crate) struct Retirement {
    timeline: vk::Semaphore,
    state: Mutex<State>,
}

#[derive(Default)]
struct State {
    /// The timeline value the latest submission signals.
    submitted: u64,
    /// Recordings begun and not yet submitted or abandoned.
    open: usize,
    /// Dropped while a recording was open: tagged when the last one closes.
    limbo: Vec<Doomed>,
    /// Tagged objects, in drop order; tags never decrease along the queue.
    queue: VecDeque<(u64, Doomed)>,
}

impl Retirement {
    /// Creates the timeline semaphore at value 0.
    pub(crate) fn new(device: &ash::Device) -> VkResult<Retirement> {
        let mut kind = vk::SemaphoreTypeCreateInfo::default()
            .semaphore_type(vk::SemaphoreType::TIMELINE)
            .initial_value(0);
        let info = vk::SemaphoreCreateInfo::default().push_next(&mut kind);
        // SAFETY: valid device; timelineSemaphore is enabled at device creation.
        let timeline =
            unsafe { device.create_semaphore(&info, None) }.named("vkCreateSemaphore")?;
        Ok(Retirement {
            timeline,
            state: Mutex::new(State::default()),
        })
    }

    /// The timeline semaphore, for naming.
    pub(crate) fn timeline(&self) -> vk::Semaphore {
        self.timeline
    }

    fn state(&self) -> MutexGuard<'_, State> {
        // A panic while the lock was held leaves the lists consistent (each push or pop is
        // whole), so a poisoned lock is still usable.
        self.state.lock().unwrap_or_else(|p| p.into_inner())
    }

    /// Destroys everything still waiting, then the semaphore.
    ///
    /// # Safety
    /// The device is idle and nothing else uses the context any more (its `Drop`).
    pub(crate) unsafe fn drain(&self, ctx: &Context) {
        let mut state = self.state();
        let limbo = std::mem::take(&mut state.limbo);
        for (_, doomed) in state.queue.drain(..) {
            destroy(ctx, doomed);
        }
        for doomed in limbo {
            destroy(ctx, doomed);
        }
        // SAFETY: the device is idle (the caller's contract), so no submission signals it.
        unsafe { ctx.device().destroy_semaphore(self.timeline, None) };
    }
}

/// A recording in progress: while one is open, dropped objects stay in limbo.
pub(crate) struct OpenRecording<'c> {
    ctx: &'c Context,
}

impl Drop for OpenRecording<'_> {
    fn drop(&mut self) {
        let mut state = self.ctx.retirement().state();
        state.open -= 1;
        if state.open == 0 {
            let tag = state.submitted;
            let limbo = std::mem::take(&mut state.limbo);
            state.queue.extend(limbo.into_iter().map(|d| (tag, d)));
        }
        drop(state);
        self.ctx.retire();
    }
}

impl Context {
    /// Marks a recording as begun; keep the value until the recording is submitted (after
    /// [`Context::submit_tracked`]) or abandoned.
    pub(crate) fn open_recording(&self) -> OpenRecording<'_> {
        self.retirement().state().open += 1;
        OpenRecording { ctx: self }
    }

    /// Submits `cmd` on the queue, waiting for `waits` and signalling `signals` and `fence`, and
    /// signals the next timeline value, so what the work uses is destroyed only after it;
    /// returns that value.
    pub(crate) fn submit_tracked(
        &self,
        cmd: vk::CommandBuffer,
        waits: &[(vk::Semaphore, vk::PipelineStageFlags)],
        signals: &[vk::Semaphore],
        fence: vk::Fence,
    ) -> VkResult<u64> {
        let queue = self
            .queue()
            .lock()
            .map_err(|_| VkError::Invalid("queue lock poisoned".into()))?;
        let value = self.retirement().state().submitted + 1;
        let cmds = [cmd];
        let wait_raw: Vec<_> = waits.iter().map(|w| w.0).collect();
        let stages: Vec<_> = waits.iter().map(|w| w.1).collect();
        let mut signal_raw = signals.to_vec();
        signal_raw.push(self.retirement().timeline);
        // Binary semaphores ignore their entries; the timeline's is the last.
        let mut values = vec![0; signals.len()];
        values.push(value);
        let wait_values = vec![0; waits.len()];
        let mut timeline = vk::TimelineSemaphoreSubmitInfo::default()
            .wait_semaphore_values(&wait_values)
            .signal_semaphore_values(&values);
        let submit = vk::SubmitInfo::default()
            .command_buffers(&cmds)
            .wait_semaphores(&wait_raw)
            .wait_dst_stage_mask(&stages)
            .signal_semaphores(&signal_raw)
            .push_next(&mut timeline);
        match self.faults().submission() {
            Some(SubmitFault::LoseDevice) => {
                return Err(VkError::from_call(
                    "vkQueueSubmit",
                    vk::Result::ERROR_DEVICE_LOST,
                ))
            }
            // Counted as submitted but never made: its fence and timeline value never signal.
            Some(SubmitFault::Hang) => {}
            None => {
                // SAFETY: the buffer is fully recorded; the queue is externally synchronised by
                // the lock, which also keeps timeline values increasing in submission order.
                unsafe { self.device().queue_submit(*queue, &[submit], fence) }
                    .named("vkQueueSubmit")?;
            }
        }
        self.retirement().state().submitted = value;
        drop(queue);
        self.retire();
        Ok(value)
    }

    /// Hands `doomed` over for destruction once the GPU has passed every submission that may use
    /// it. After a hang it is left to the process exit: the hung work may never finish.
    pub(crate) fn defer(&self, doomed: Doomed) {
        if self.is_hung() {
            return;
        }
        let mut state = self.retirement().state();
        if state.open > 0 {
            state.limbo.push(doomed);
        } else {
            let tag = state.submitted;
            state.queue.push_back((tag, doomed));
        }
        drop(state);
        self.retire();
    }

    /// Destroys every waiting object the GPU has finished with.
    pub(crate) fn retire(&self) {
        let timeline = self.retirement().timeline;
        // SAFETY: the semaphore belongs to this device and lives until the context drops.
        let Ok(done) = (unsafe { self.device().get_semaphore_counter_value(timeline) }) else {
            return;
        };
        let mut state = self.retirement().state();
        while state.queue.front().is_some_and(|(tag, _)| *tag <= done) {
            if let Some((_, doomed)) = state.queue.pop_front() {
                destroy(self, doomed);
            }
        }
    }

    /// Waits (at most the GPU timeout) until every submission made so far has finished.
    pub(crate) fn wait_submitted(&self, what: &str) -> VkResult<()> {
        let value = self.retirement().state().submitted;
        self.wait_submission(value, what)
    }

    /// Waits (at most the GPU timeout) until submission `value` (a timeline value
    /// [`Context::submit_tracked`] returned) has finished.
    pub(crate) fn wait_submission(&self, value: u64, what: &str) -> VkResult<()> {
        let semaphores = [self.retirement().timeline];
        let values = [value];
        let info = vk::SemaphoreWaitInfo::default()
            .semaphores(&semaphores)
            .values(&values);
        let timeout = self.gpu_timeout();
        let nanos = u64::try_from(timeout.as_nanos()).unwrap_or(u64::MAX);
        // SAFETY: the semaphore belongs to this device; waiting needs no external sync.
        match unsafe { self.device().wait_semaphores(&info, nanos) } {
            Err(vk::Result::TIMEOUT) => {
                self.mark_hung();
                Err(VkError::Hang {
                    what: what.to_owned(),
                    seconds: timeout.as_secs_f64(),
                })
            }
            other => other.named("vkWaitSemaphores"),
        }?;
        self.retire();
        Ok(())
    }
}

fn destroy(ctx: &Context, doomed: Doomed) {
    let device = ctx.device();
    let counted = counted_as(&doomed);
    let allocation = match doomed {
        // SAFETY (all arms): the GPU has passed every submission that may use the handle (its tag
        // or a drained, idle device), its owner is gone, and it is destroyed here once.
        Doomed::Buffer(raw, allocation) => {
            // SAFETY: see above.
            unsafe { device.destroy_buffer(raw, None) };
            allocation
        }
        Doomed::Image(raw, allocation) => {
            // SAFETY: see above; the image's views were queued, and so destroyed, before it.
            unsafe { device.destroy_image(raw, None) };
            allocation
        }
        Doomed::ImageView(raw) => {
            // SAFETY: see above.
            unsafe { device.destroy_image_view(raw, None) };
            None
        }
        Doomed::Sampler(raw) => {
            // SAFETY: see above.
            unsafe { device.destroy_sampler(raw, None) };
            None
        }
        Doomed::Pipeline(raw, layout, _) => {
            // SAFETY: see above; the layout goes with its pipeline.
            unsafe {
                device.destroy_pipeline(raw, None);
                device.destroy_pipeline_layout(layout, None);
            }
            None
        }
        Doomed::DescriptorPool(raw) => {
            // SAFETY: see above; every set of the pool went before it.
            unsafe { device.destroy_descriptor_pool(raw, None) };
            None
        }
        Doomed::DescriptorLayout(raw) => {
            // SAFETY: see above.
            unsafe { device.destroy_descriptor_set_layout(raw, None) };
            None
        }
        Doomed::QueryPool(raw) => {
            // SAFETY: see above.
            unsafe { device.destroy_query_pool(raw, None) };
            None
        }
        Doomed::Swapchain(loader, raw) => {
            // SAFETY: see above; its owner waited for an idle device before handing it over, so
            // no presentation uses it; its images go with it.
            unsafe { loader.destroy_swapchain(raw, None) };
            None
        }
        Doomed::AccelerationStructure(loader, raw) => {
            // SAFETY: see above; the buffer holding it goes after it.
            unsafe { loader.destroy_acceleration_structure(raw, None) };
            None
        }
        Doomed::Semaphore(raw) => {
            // SAFETY: see above; a presentation's wait on it is the swapchain's to finish (it
            // waits for an idle device before its semaphores go).
            unsafe { device.destroy_semaphore(raw, None) };
            None
        }
    };
    if let Some(what) = counted {
        ctx.count_destroyed(what);
    }
    if let (Some(a), Ok(mut alloc)) = (allocation, ctx.allocator().lock()) {
        let _ = alloc.free(a);
    }
}

/// How `doomed` was counted when it was created, if it was: buffers and images only once their
/// memory was bound, and views, pools, layouts, swapchains and semaphores not at all.
fn counted_as(doomed: &Doomed) -> Option<Created> {
    match doomed {
        Doomed::Buffer(_, Some(a)) => Some(Created::Buffer { bytes: a.size() }),
        Doomed::Image(_, Some(a)) => Some(Created::Image { bytes: a.size() }),
        Doomed::Sampler(_) => Some(Created::Sampler),
        Doomed::QueryPool(_) => Some(Created::QueryPool),
        Doomed::Pipeline(_, _, vk::PipelineBindPoint::COMPUTE) => Some(Created::ComputePipeline),
        Doomed::Pipeline(..) => Some(Created::GraphicsPipeline),
        _ => None,
    }
}
