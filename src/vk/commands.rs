//! One-shot command submission and the barriers relief records: record, submit, wait on a fence
//! (with the GPU timeout). One-shots may run on several threads; the command pool lock serialises them.

use ash::vk;

use super::context::Context;
use super::counters::Created;
use super::error::{Named, VkError, VkResult};
use super::image::WholeImage;
use super::recording::Recording;

impl Context {
    /// Records commands with `record`, submits them on the queue and waits (at most the GPU
    /// timeout, see [`Context::wait_fence`]) until they finish.
    ///
    /// Safe to call from several threads at once; `record` must not call `one_shot` itself (it
    /// runs while the command pool is locked).
    pub fn one_shot<R>(&self, record: impl FnOnce(&Recording) -> VkResult<R>) -> VkResult<R> {
        // The pool is held for the whole use, not just the allocation: a command pool and every
        // buffer allocated from it must be externally synchronised while a buffer is allocated,
        // recorded, submitted or freed. Holding one lock is simpler than a pool per thread (no
        // thread registry, no pools outliving their threads) and costs little, since each
        // one-shot waits for its own work anyway and there is one queue.
        let pool = self
            .command_pool()
            .lock()
            .map_err(|_| VkError::Invalid("command pool lock poisoned".into()))?;
        let device = self.device();
        let alloc = vk::CommandBufferAllocateInfo::default()
            .command_pool(*pool)
            .level(vk::CommandBufferLevel::PRIMARY)
            .command_buffer_count(1);
        // SAFETY: valid pool on this device, locked for this thread.
        let cmd = unsafe { device.allocate_command_buffers(&alloc) }
            .named("vkAllocateCommandBuffers")?[0];
        self.count(Created::CommandBuffer);
        let result = self.record_and_submit(cmd, record);
        if !matches!(result, Err(VkError::Hang { .. })) {
            // SAFETY: the submission has completed or never happened; the pool is locked.
            unsafe { device.free_command_buffers(*pool, &[cmd]) };
            self.count_destroyed(Created::CommandBuffer);
        }
        result
    }

    fn record_and_submit<R>(
        &self,
        cmd: vk::CommandBuffer,
        record: impl FnOnce(&Recording) -> VkResult<R>,
    ) -> VkResult<R> {
        let device = self.device();
        let begin = vk::CommandBufferBeginInfo::default()
            .flags(vk::CommandBufferUsageFlags::ONE_TIME_SUBMIT);
        // SAFETY: freshly allocated command buffer.
        unsafe { device.begin_command_buffer(cmd, &begin) }.named("vkBeginCommandBuffer")?;
        let open = self.open_recording();
        let rec = Recording::new(device, cmd);
        let value = record(&rec)?;
        // SAFETY: recording was begun above.
        unsafe { device.end_command_buffer(cmd) }.named("vkEndCommandBuffer")?;
        // SAFETY: valid device.
        let fence = unsafe { device.create_fence(&vk::FenceCreateInfo::default(), None) }
            .named("vkCreateFence")?;
        self.count(Created::Fence);
        let submitted = self.submit_tracked(cmd, &[], &[], fence);
        if let Ok(timeline) = submitted {
            rec.submitted(timeline);
        }
        drop(open);
        // SAFETY: the fence was created above and is destroyed only below.
        let waited =
            submitted.and_then(|_| unsafe { self.wait_fence(fence, "a one-shot submission") });
        self.retire();
        if !matches!(waited, Err(VkError::Hang { .. })) {
            // SAFETY: the fence is signalled or was never submitted.
            unsafe { device.destroy_fence(fence, None) };
            self.count_destroyed(Created::Fence);
        }
        waited.map(|_| value)
    }
}

/// One image layout transition over a range of mip levels (colour aspect unless `aspect` says).
/// The image is one of this layer's ([`Image`](super::Image) or
/// [`SwapchainImage`](super::SwapchainImage)), never a raw handle:
///
/// ```compile_fail,E0277
/// use relief::vk::{raw, ImageTransition};
/// fn forge() -> ImageTransition<'static> {
///     let none = (raw::PipelineStageFlags2::NONE, raw::AccessFlags2::NONE);
///     let layouts = (raw::ImageLayout::UNDEFINED, raw::ImageLayout::GENERAL);
///     ImageTransition::color(&raw::Image::null(), layouts, none, none)
/// }
/// ```
///
/// while this layer's images are accepted:
///
/// ```no_run
/// use relief::vk::{raw, Image, ImageTransition};
/// fn real(image: &Image) -> ImageTransition<'_> {
///     let none = (raw::PipelineStageFlags2::NONE, raw::AccessFlags2::NONE);
///     let layouts = (raw::ImageLayout::UNDEFINED, raw::ImageLayout::GENERAL);
///     ImageTransition::color(image, layouts, none, none)
/// }
/// ```
#[derive(Clone, Copy)]
pub struct ImageTransition<'a> {
    /// The image whose layout changes.
    pub image: &'a dyn WholeImage,
    /// The aspect the barrier covers.
    pub aspect: vk::ImageAspectFlags,
    /// The first mip level.
    pub base_mip: u32,
    /// How many mip levels, from `base_mip`.
    pub mip_count: u32,
    /// The layout before.
    pub old: vk::ImageLayout,
    /// The layout after.
    pub new: vk::ImageLayout,
    /// The stages and accesses that must finish first.
    pub src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    /// The stages and accesses that wait.
    pub dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
}

impl<'a> ImageTransition<'a> {
    /// The transition of a single-mip colour image.
    pub fn color(
        image: &'a dyn WholeImage,
        (old, new): (vk::ImageLayout, vk::ImageLayout),
        src: (vk::PipelineStageFlags2, vk::AccessFlags2),
        dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
    ) -> ImageTransition<'a> {
        ImageTransition {
            image,
            aspect: vk::ImageAspectFlags::COLOR,
            base_mip: 0,
            mip_count: 1,
            old,
            new,
            src,
            dst,
        }
    }
}

/// The copy region of a whole single-mip colour image of `width` x `height` to or from the start
/// of a tightly packed buffer.
pub fn whole_color_region(width: u32, height: u32) -> vk::BufferImageCopy {
    vk::BufferImageCopy::default()
        .image_subresource(
            vk::ImageSubresourceLayers::default()
                .aspect_mask(vk::ImageAspectFlags::COLOR)
                .layer_count(1),
        )
        .image_extent(vk::Extent3D {
            width,
            height,
            depth: 1,
        })
}

/// Records a set of image transitions as one synchronization2 barrier.
pub fn transition_images(rec: &Recording, list: &[ImageTransition]) {
    let barriers: Vec<_> = list
        .iter()
        .map(|t| {
            vk::ImageMemoryBarrier2::default()
                .image(t.image.whole_raw())
                .old_layout(t.old)
                .new_layout(t.new)
                .src_stage_mask(t.src.0)
                .src_access_mask(t.src.1)
                .dst_stage_mask(t.dst.0)
                .dst_access_mask(t.dst.1)
                .src_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .dst_queue_family_index(vk::QUEUE_FAMILY_IGNORED)
                .subresource_range(
                    vk::ImageSubresourceRange::default()
                        .aspect_mask(t.aspect)
                        .base_mip_level(t.base_mip)
                        .level_count(t.mip_count)
                        // Every layer of array images; plain images have one.
                        .layer_count(vk::REMAINING_ARRAY_LAYERS),
                )
        })
        .collect();
    let dep = vk::DependencyInfo::default().image_memory_barriers(&barriers);
    // SAFETY: `rec` is recording; the barriers reference images of this layer, borrowed, so alive
    // (and kept to the end of the submission by deferred destruction or the swapchain).
    unsafe { rec.device().cmd_pipeline_barrier2(rec.raw(), &dep) };
}

/// Records a global memory barrier (e.g. between timed repeats or compute passes).
pub fn memory_barrier(
    rec: &Recording,
    src: (vk::PipelineStageFlags2, vk::AccessFlags2),
    dst: (vk::PipelineStageFlags2, vk::AccessFlags2),
) {
    let barrier = [vk::MemoryBarrier2::default()
        .src_stage_mask(src.0)
        .src_access_mask(src.1)
        .dst_stage_mask(dst.0)
        .dst_access_mask(dst.1)];
    let dep = vk::DependencyInfo::default().memory_barriers(&barrier);
    // SAFETY: `rec` is recording.
    unsafe { rec.device().cmd_pipeline_barrier2(rec.raw(), &dep) };
}
