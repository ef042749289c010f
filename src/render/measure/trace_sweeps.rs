//! The trace pass's timed sweeps: recording `warmup + frames` sweeps of the bound kernel in one
//! submission, with timestamps and pipeline statistics around the timed ones.

use std::sync::Arc;

use ash::vk;

use super::trace_pass::TRACE_GROUP_SIDE as GROUP;
use crate::render::compute_pass::ComputePass;
use crate::render::shader_interface::TraceParams;
use crate::vk::{
    memory_barrier, Context, DescriptorSet, Recording, StatisticsPool, TimestampPool, VkError,
    VkResult,
};

/// The timestamps around each timed sweep, and its statistics where the device counts them.
pub(super) struct SweepTimers {
    timestamps: TimestampPool,
    statistics: Option<StatisticsPool>,
}

impl SweepTimers {
    /// Timers for `frames` timed sweeps.
    pub(super) fn new(ctx: &Arc<Context>, frames: u32) -> VkResult<SweepTimers> {
        let timestamps = TimestampPool::new(ctx, 2 * frames, "trace timestamps")?;
        let statistics = match StatisticsPool::new(ctx, frames, "trace counts") {
            Ok(pool) => Some(pool),
            Err(VkError::Unsupported(_)) => None,
            Err(e) => return Err(e),
        };
        Ok(SweepTimers {
            timestamps,
            statistics,
        })
    }

    /// Records the start of timed sweep `k`.
    fn begin(&self, rec: &Recording, k: u32) -> VkResult<()> {
        self.timestamps
            .write(rec, vk::PipelineStageFlags2::ALL_COMMANDS, 2 * k)?;
        if let Some(stats) = &self.statistics {
            stats.begin(rec, k)?;
        }
        Ok(())
    }

    /// Records the end of timed sweep `k`.
    fn end(&self, rec: &Recording, k: u32) -> VkResult<()> {
        if let Some(stats) = &self.statistics {
            stats.end(rec, k)?;
        }
        self.timestamps
            .write(rec, vk::PipelineStageFlags2::ALL_COMMANDS, 2 * k + 1)
    }

    /// The GPU time of each of `frames` timed sweeps, in ms.
    pub(super) fn frame_ms(&self, frames: u32) -> VkResult<Vec<f64>> {
        let ticks = self.timestamps.read_ticks(2 * frames)?;
        Ok(ticks
            .chunks_exact(2)
            .map(|t| self.timestamps.ticks_to_ms(t[0], t[1]))
            .collect())
    }

    /// The compute invocations of each of `frames` timed sweeps (none where not counted).
    pub(super) fn compute_invocations(&self, frames: u32) -> VkResult<Vec<u64>> {
        Ok(match &self.statistics {
            Some(stats) => stats
                .read(frames)?
                .iter()
                .map(|c| c.compute_invocations)
                .collect(),
            None => Vec::new(),
        })
    }
}

/// The sweeps one submission records: the bound kernel, its parameters and timers, and the
/// warm-up sweeps, timed sweeps and dispatches per sweep (`counts`).
pub(super) struct TimedSweeps<'a> {
    pub pass: &'a ComputePass,
    pub set: &'a DescriptorSet,
    pub params: TraceParams,
    pub timers: &'a SweepTimers,
    pub counts: (u32, u32, u32),
}

impl TimedSweeps<'_> {
    /// Records every sweep, the warm-up ones first, each ordered after the last.
    pub(super) fn record(&self, rec: &Recording) -> VkResult<()> {
        let (warmup, frames, dispatches) = self.counts;
        let [cols, rows, ..] = self.params.grid;
        let full = (
            all_stages(),
            vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE,
        );
        let pipeline = self.pass.pipeline();
        pipeline.bind(rec, Some(self.set));
        pipeline.push(rec, bytemuck::bytes_of(&self.params))?;
        for frame in 0..warmup + frames {
            let timed = frame.checked_sub(warmup);
            if let Some(k) = timed {
                self.timers.begin(rec, k)?;
            }
            for d in 0..dispatches {
                if d > 0 {
                    // The repeats write the same buffers: order them as the frames are.
                    memory_barrier(rec, full, full);
                }
                rec.dispatch([cols.div_ceil(GROUP), rows.div_ceil(GROUP), 1]);
            }
            if let Some(k) = timed {
                self.timers.end(rec, k)?;
            }
            memory_barrier(rec, full, full);
        }
        Ok(())
    }
}

/// Every stage: the sweeps are ordered after each other whole.
fn all_stages() -> vk::PipelineStageFlags2 {
    vk::PipelineStageFlags2::ALL_COMMANDS
}
