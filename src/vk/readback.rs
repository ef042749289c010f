//! Reading GPU results on the host. Device writes become visible to host reads only through a
//! barrier to `HOST`/`HOST_READ` before the fence signals; a fence alone is not enough on non-coherent
//! or cached memory. [`Readback`] records that barrier with every copy it records, and hands out
//! its bytes only once the submission that carries its latest copy has finished on the GPU (the
//! context's timeline has passed it): never memory a copy may still be writing, nor bytes no copy
//! was recorded for.
//!
//! Producers write device-local memory; the copy into this host-visible buffer is recorded after
//! them (and after any closing timestamp), so timed work never pays for writes over the bus.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::buffer::Buffer;
use super::commands::memory_barrier;
use super::context::Context;
use super::error::{VkError, VkResult};
use super::image::WholeImage;
use super::recording::{Recording, UNSUBMITTED};
use super::transfer::texel_size;

/// A host-visible (`GpuToCpu`) buffer that GPU results are copied into and read from.
pub struct Readback {
    buffer: Buffer,
    /// The timeline value of the submission that carries the latest copy into it: 0 before any
    /// copy was recorded, `UNSUBMITTED` while the recording that holds it is open or was
    /// abandoned.
    filled_by: Arc<AtomicU64>,
}

impl Readback {
    /// A readback buffer of `size` bytes, named `name`.
    pub fn new(ctx: &Arc<Context>, size: u64, name: &str) -> VkResult<Readback> {
        let buffer = Buffer::new(
            ctx,
            size,
            vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuToCpu,
            name,
        )?;
        Ok(Readback {
            buffer,
            filled_by: Arc::new(AtomicU64::new(0)),
        })
    }

    /// Records: a barrier after `after` (the stage and access that wrote `src`), the
    /// copy of this buffer's size from the start of `src`, and the host-read barrier.
    pub fn record_copy_from_buffer(
        &self,
        rec: &Recording,
        src: &Buffer,
        after: (vk::PipelineStageFlags2, vk::AccessFlags2),
    ) -> VkResult<()> {
        let size = self.buffer.size();
        if src.size() < size {
            return Err(VkError::Invalid(format!(
                "readback of {size} bytes from {} bytes",
                src.size()
            )));
        }
        memory_barrier(rec, after, copy_read());
        let region = [vk::BufferCopy::default().size(size)];
        // SAFETY: `rec` is recording; the region lies within both buffers.
        unsafe {
            rec.device()
                .cmd_copy_buffer(rec.raw(), src.raw(), self.buffer.raw(), &region)
        };
        self.record_host_barrier(rec);
        Ok(())
    }

    /// Records the copy of `region` of `image` (an [`Image`](super::Image) or a
    /// [`SwapchainImage`](super::SwapchainImage), in `TRANSFER_SRC_OPTIMAL`, made available to
    /// transfers by the caller's layout transition) and the host-read barrier. The region must
    /// lie within the image's level and, as tightly packed rows, within this buffer; otherwise
    /// nothing is recorded and the error says why.
    pub fn record_copy_from_image(
        &self,
        rec: &Recording,
        image: &impl WholeImage,
        region: vk::BufferImageCopy,
    ) -> VkResult<()> {
        self.check_image_region(image, &region)?;
        let layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        let dst = self.buffer.raw();
        // SAFETY: `rec` is recording; the region lies within the image and the buffer (checked
        // above); the image is alive (borrowed, then kept by deferred destruction or the
        // swapchain's idle wait).
        unsafe {
            rec.device().cmd_copy_image_to_buffer(
                rec.raw(),
                image.whole_raw(),
                layout,
                dst,
                &[region],
            )
        };
        self.record_host_barrier(rec);
        Ok(())
    }

    fn check_image_region(
        &self,
        image: &impl WholeImage,
        region: &vk::BufferImageCopy,
    ) -> VkResult<()> {
        let sub = region.image_subresource;
        let level = sub.mip_level;
        let whole = image.whole_extent();
        let (lw, lh) = (
            (whole.width >> level).max(1),
            (whole.height >> level).max(1),
        );
        let (o, e) = (region.image_offset, region.image_extent);
        let inside = |offset: i32, size: u32, limit: u32| {
            u32::try_from(offset)
                .ok()
                .and_then(|o| o.checked_add(size))
                .is_some_and(|end| end <= limit)
        };
        let fits = level < image.whole_levels()
            && sub.layer_count >= 1
            && sub.base_array_layer.saturating_add(sub.layer_count) <= image.whole_layers()
            && inside(o.x, e.width, lw)
            && inside(o.y, e.height, lh)
            && o.z == 0
            && e.depth == 1;
        let texel = texel_size(image.whole_format())? as u64;
        let row = u64::from(region.buffer_row_length.max(e.width));
        let rows = u64::from(region.buffer_image_height.max(e.height));
        let bytes = row * rows.saturating_sub(1) * texel
            + u64::from(e.width) * texel
            + (rows * row * texel) * u64::from(sub.layer_count.saturating_sub(1));
        let in_buffer = region
            .buffer_offset
            .checked_add(bytes)
            .is_some_and(|end| end <= self.buffer.size());
        if fits && in_buffer {
            return Ok(());
        }
        Err(VkError::Invalid(format!(
            "copy of {}x{} at {},{} of mip {level} ({lw}x{lh}) into readback {:?} of {} bytes at {}",
            e.width,
            e.height,
            o.x,
            o.y,
            self.buffer.name(),
            self.buffer.size(),
            region.buffer_offset
        )))
    }

    fn record_host_barrier(&self, rec: &Recording) {
        host_read_barrier(rec);
        rec.note_fill(&self.filled_by);
    }

    /// The copied bytes, once the submission that carries the latest copy into this buffer has
    /// finished on the GPU: it waits for that submission (at most the GPU timeout) when it is
    /// still running, so it never returns bytes a copy may still be writing; an error before any
    /// copy was recorded, or while the recording that holds the copy is not submitted.
    pub fn bytes(&self) -> VkResult<&[u8]> {
        let filled_by = self.filled_by.load(Ordering::Acquire);
        if let Some(why) = unreadable(filled_by) {
            return Err(VkError::Invalid(format!(
                "readback {:?} read {why}",
                self.buffer.name()
            )));
        }
        let what = format!(
            "the submission that fills readback {:?}",
            self.buffer.name()
        );
        self.buffer.context().wait_submission(filled_by, &what)?;
        self.buffer.mapped()
    }

    /// The buffer the copies land in.
    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }
}

/// Why a readback whose copy went out in submission `filled_by` can never be read as it is;
/// `None` when waiting for that submission is enough.
fn unreadable(filled_by: u64) -> Option<&'static str> {
    match filled_by {
        0 => Some("before a copy into it was recorded"),
        UNSUBMITTED => Some("before the recording that copies into it was submitted"),
        _ => None,
    }
}

fn copy_read() -> (vk::PipelineStageFlags2, vk::AccessFlags2) {
    (
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ,
    )
}

/// Records the barrier that makes transfer writes visible to host reads after the submission's
/// fence: `COPY`/`TRANSFER_WRITE` to `HOST`/`HOST_READ`.
pub fn host_read_barrier(rec: &Recording) {
    memory_barrier(
        rec,
        (
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_WRITE,
        ),
        (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
    );
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn only_a_submitted_copy_can_be_waited_for() {
        assert!(unreadable(0).is_some_and(|w| w.contains("before a copy")));
        assert!(unreadable(UNSUBMITTED).is_some_and(|w| w.contains("submitted")));
        assert_eq!(unreadable(7), None);
    }
}
