//! Reading GPU results on the host. Device writes become visible to host reads only through a
//! barrier to `HOST`/`HOST_READ` before the fence signals; a fence alone is not enough on non-coherent
//! or cached memory. [`Readback`] records that barrier with every copy it records, and refuses to
//! hand out bytes no copy was recorded for, so a caller cannot forget either.
//!
//! Producers write device-local memory; the copy into this host-visible buffer is recorded after
//! them (and after any closing timestamp), so timed work never pays for writes over the bus.

use std::cell::Cell;
use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::buffer::Buffer;
use super::commands::memory_barrier;
use super::context::Context;
use super::error::{VkError, VkResult};
use super::image::Image;
use super::recording::Recording;

/// A host-visible (`GpuToCpu`) buffer that GPU results are copied into and read from.
pub struct Readback {
    buffer: Buffer,
    recorded: Cell<bool>,
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
            recorded: Cell::new(false),
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

    /// Records the copy of `region` of `image` (in `TRANSFER_SRC_OPTIMAL`, made
    /// available to transfers by the caller's layout transition) and the host-read barrier.
    pub fn record_copy_from_image(
        &self,
        rec: &Recording,
        image: &Image,
        region: vk::BufferImageCopy,
    ) {
        self.record_copy_from_raw_image(rec, image.raw(), region);
    }

    /// As [`Readback::record_copy_from_image`], for an image relief does not own (a swapchain's).
    pub fn record_copy_from_raw_image(
        &self,
        rec: &Recording,
        raw: vk::Image,
        region: vk::BufferImageCopy,
    ) {
        let layout = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
        let dst = self.buffer.raw();
        // SAFETY: `rec` is recording; the caller's region lies within the image and the buffer.
        unsafe {
            rec.device()
                .cmd_copy_image_to_buffer(rec.raw(), raw, layout, dst, &[region])
        };
        self.record_host_barrier(rec);
    }

    fn record_host_barrier(&self, rec: &Recording) {
        host_read_barrier(rec);
        self.recorded.set(true);
    }

    /// The copied bytes: valid once the submission that recorded the copy has completed.
    pub fn bytes(&self) -> VkResult<&[u8]> {
        if !self.recorded.get() {
            return Err(VkError::Invalid(format!(
                "readback {:?} read before a copy into it was recorded",
                self.buffer.name()
            )));
        }
        self.buffer.mapped()
    }

    /// The buffer the copies land in.
    pub fn buffer(&self) -> &Buffer {
        &self.buffer
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
