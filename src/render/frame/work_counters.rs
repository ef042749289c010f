//! The frame's work counters (`RenderOptions::count_work`, `relief render --count-work`): per
//! pixel of the scene's targets, how many relief fragments got past the occluder bounds and
//! traced, and the steps and texel fetches their traces took, counted by the surface shader with atomics into a
//! storage buffer beside the bounds (set 3). Pipeline statistics count what the rasteriser
//! started (llvmpipe: per 4x4 stamp, before any test); these count what the shader paid for, so
//! a culled frame shows one trace per pixel where the forward path shows one per surface.
//! Frames that do not count compile the counting out (`SPEC_COUNT_WORK`, `SPEC_COUNT_FETCHES`).

use std::sync::Arc;

use ash::vk;
use serde::{Deserialize, Serialize};

use crate::vk::{memory_barrier, Buffer, Context, MemoryLocation, Readback, Recording, VkResult};

/// One frame's counts, rows top to bottom.
#[derive(Debug, Clone, PartialEq)]
pub struct WorkCounts {
    /// Width of the targets counted (the frame's, times the supersampling).
    pub width: u32,
    /// Height of the targets counted.
    pub height: u32,
    /// Relief fragments traced at each pixel.
    pub traced: Vec<u32>,
    /// Steps those traces took at each pixel, summed.
    pub steps: Vec<u32>,
    /// Texel fetches of the height map, its pyramid and the method's map those traces made at
    /// each pixel, summed (a gather of four texels is one).
    pub fetches: Vec<u32>,
}

/// A frame's counts summed up.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct WorkSummary {
    /// Relief fragments traced in the frame.
    pub traced_fragments: u64,
    /// Pixels at least one relief fragment traced.
    pub traced_pixels: u64,
    /// Traced fragments per traced pixel: 1 where nothing traced is hidden.
    pub fragments_per_traced_pixel: f64,
    /// The most fragments traced at one pixel.
    pub most_fragments_at_a_pixel: u32,
    /// Steps of every trace.
    pub steps: u64,
    /// Steps per traced pixel.
    pub steps_per_traced_pixel: f64,
    /// Texel fetches of every trace.
    pub fetches: u64,
    /// Texel fetches per traced pixel.
    pub fetches_per_traced_pixel: f64,
}

impl WorkCounts {
    /// The counts from the counters' bytes: three native-endian u32 per pixel (traced,
    /// steps, fetches).
    pub fn decode(width: u32, height: u32, bytes: &[u8]) -> WorkCounts {
        let words: Vec<u32> = bytemuck::pod_collect_to_vec(bytes);
        let pixels = (width * height) as usize;
        let per_pixel: Vec<&[u32]> = words.chunks_exact(COUNTS_PER_PIXEL).take(pixels).collect();
        let column = |k: usize| per_pixel.iter().map(|p| p[k]).collect();
        WorkCounts {
            width,
            height,
            traced: column(0),
            steps: column(1),
            fetches: column(2),
        }
    }

    /// The frame's totals.
    pub fn summary(&self) -> WorkSummary {
        let traced_fragments: u64 = self.traced.iter().map(|&n| u64::from(n)).sum();
        let traced_pixels = self.traced.iter().filter(|&&n| n > 0).count() as u64;
        let steps: u64 = self.steps.iter().map(|&n| u64::from(n)).sum();
        let fetches: u64 = self.fetches.iter().map(|&n| u64::from(n)).sum();
        let per_pixel = |n: u64| {
            if traced_pixels == 0 {
                0.0
            } else {
                n as f64 / traced_pixels as f64
            }
        };
        WorkSummary {
            traced_fragments,
            traced_pixels,
            fragments_per_traced_pixel: per_pixel(traced_fragments),
            most_fragments_at_a_pixel: self.traced.iter().copied().max().unwrap_or(0),
            steps,
            steps_per_traced_pixel: per_pixel(steps),
            fetches,
            fetches_per_traced_pixel: per_pixel(fetches),
        }
    }
}

/// Counters per pixel: traced fragments, steps, fetches (`work_index` in occluders.glsl).
const COUNTS_PER_PIXEL: usize = 3;

/// The counters on the device: [`COUNTS_PER_PIXEL`] u32 per pixel of the targets, or one
/// pixel's (a stand-in the set can bind) when the frame does not count.
pub struct WorkCounterBuffer {
    buffer: Buffer,
    size: (u32, u32),
    counting: bool,
}

impl WorkCounterBuffer {
    /// Counters for `width` x `height` targets when `counting`, else the stand-in.
    pub fn new(
        ctx: &Arc<Context>,
        (width, height): (u32, u32),
        counting: bool,
    ) -> VkResult<WorkCounterBuffer> {
        let pixel_bytes = 4 * COUNTS_PER_PIXEL as u64;
        let bytes = if counting {
            pixel_bytes * u64::from(width) * u64::from(height)
        } else {
            pixel_bytes
        };
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER
            | vk::BufferUsageFlags::TRANSFER_SRC
            | vk::BufferUsageFlags::TRANSFER_DST;
        let buffer = Buffer::new(ctx, bytes, usage, MemoryLocation::GpuOnly, "work counters")?;
        Ok(WorkCounterBuffer {
            buffer,
            size: (width, height),
            counting,
        })
    }

    /// The buffer set 3 binds.
    pub fn buffer(&self) -> &Buffer {
        &self.buffer
    }

    /// Whether it counts (else it is the stand-in).
    pub fn counting(&self) -> bool {
        self.counting
    }

    /// A host buffer the counts are copied into.
    pub fn readback(&self, ctx: &Arc<Context>, name: &str) -> VkResult<Readback> {
        Readback::new(ctx, self.buffer.size(), name)
    }

    /// Records the counters' reset to zero, after the last frame's shaders and copy are done
    /// with them and before this frame's shaders count.
    pub fn record_clear(&self, rec: &Recording) -> VkResult<()> {
        memory_barrier(
            rec,
            (
                vk::PipelineStageFlags2::FRAGMENT_SHADER | vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::TRANSFER_READ,
            ),
            (
                vk::PipelineStageFlags2::CLEAR,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
        );
        rec.fill_buffer(&self.buffer, 0, self.buffer.size(), 0)?;
        memory_barrier(
            rec,
            (
                vk::PipelineStageFlags2::CLEAR,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (
                vk::PipelineStageFlags2::FRAGMENT_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
            ),
        );
        Ok(())
    }

    /// Records the copy of this frame's counts into `into`, after the surface pass's shaders.
    pub fn record_copy(&self, rec: &Recording, into: &Readback) -> VkResult<()> {
        let written = (
            vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        into.record_copy_from_buffer(rec, &self.buffer, written)
    }

    /// The counts of `bytes` read back from this buffer.
    pub fn decode(&self, bytes: &[u8]) -> WorkCounts {
        WorkCounts::decode(self.size.0, self.size.1, bytes)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_decode_per_pixel_and_sum_over_traced_pixels() {
        let words: [u32; 12] = [2, 30, 70, 0, 0, 0, 1, 10, 25, 1, 12, 31];
        let counts = WorkCounts::decode(2, 2, bytemuck::cast_slice(&words));
        assert_eq!(counts.traced, [2, 0, 1, 1]);
        assert_eq!(counts.steps, [30, 0, 10, 12]);
        assert_eq!(counts.fetches, [70, 0, 25, 31]);
        let s = counts.summary();
        assert_eq!((s.traced_fragments, s.traced_pixels), (4, 3));
        assert!((s.fragments_per_traced_pixel - 4.0 / 3.0).abs() < 1e-12);
        assert_eq!(s.most_fragments_at_a_pixel, 2);
        assert_eq!(s.steps, 52);
        assert_eq!(s.fetches, 126);
        assert!((s.fetches_per_traced_pixel - 42.0).abs() < 1e-12);
        let empty = WorkCounts::decode(1, 1, &[0; 12]).summary();
        assert_eq!(empty.fragments_per_traced_pixel, 0.0);
    }
}
