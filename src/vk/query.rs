//! GPU timestamps: a query pool that checks the device supports them, masks the values to the
//! valid bits and converts ticks to milliseconds with `timestampPeriod`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;

use super::context::Context;
use super::error::{VkError, VkResult};
use super::query_core::QueryCore;
use super::recording::Recording;

/// A pool of `capacity` timestamp queries, reset from the host before each use.
pub struct TimestampPool {
    core: QueryCore,
    /// Which queries a recording has written since the last reset: Vulkan allows one write per
    /// reset, so a second is refused.
    written: Vec<AtomicBool>,
    mask: u64,
    period_ns: f64,
}

impl TimestampPool {
    /// Creates the pool, or says why the device cannot time passes.
    pub fn new(ctx: &Arc<Context>, capacity: u32, name: &str) -> VkResult<TimestampPool> {
        let info = ctx.info();
        let bits = info.timestamp_valid_bits;
        if bits == 0 || info.timestamp_period_ns <= 0.0 {
            return Err(VkError::Unsupported(format!(
                "timestamps on its queue (timestampValidBits = {bits}, timestampPeriod = {})",
                info.timestamp_period_ns
            )));
        }
        let mask = if bits >= 64 {
            u64::MAX
        } else {
            (1u64 << bits) - 1
        };
        let create = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::TIMESTAMP)
            .query_count(capacity);
        Ok(TimestampPool {
            core: QueryCore::new(ctx, create, name)?,
            written: (0..capacity).map(|_| AtomicBool::new(false)).collect(),
            mask,
            period_ns: f64::from(info.timestamp_period_ns),
        })
    }

    /// How many timestamps the pool holds.
    pub fn capacity(&self) -> u32 {
        self.core.capacity
    }

    /// Nanoseconds per tick.
    pub fn period_ns(&self) -> f64 {
        self.period_ns
    }

    /// Resets every query from the host.
    ///
    /// # Safety
    /// No pending submission and no open recording may write the pool: Vulkan forbids a host
    /// reset of queries the device may still use. Waiting for the submissions that wrote it
    /// ([`CommandSlot::wait`](super::CommandSlot::wait), or a one-shot having returned) meets this.
    /// Safe code cannot call it:
    ///
    /// ```compile_fail,E0133
    /// fn reset(pool: &relief::vk::TimestampPool) {
    ///     pool.reset();
    /// }
    /// ```
    pub unsafe fn reset(&self) {
        // SAFETY: the caller's contract.
        unsafe { self.core.reset() };
        for w in &self.written {
            w.store(false, Ordering::Relaxed);
        }
    }

    /// Records a timestamp into `index` once all earlier work has passed `stage`. An index past
    /// the pool, or one already written since the last [`TimestampPool::reset`], is an error.
    pub fn write(
        &self,
        rec: &Recording,
        stage: vk::PipelineStageFlags2,
        index: u32,
    ) -> VkResult<()> {
        if index >= self.core.capacity {
            return Err(VkError::Invalid(format!(
                "timestamp {index} of {}",
                self.core.capacity
            )));
        }
        if self.written[index as usize].swap(true, Ordering::Relaxed) {
            return Err(VkError::Invalid(format!(
                "timestamp {index} written twice without a reset"
            )));
        }
        // SAFETY: `rec` is recording; the query was reset and not written since (checked above).
        unsafe {
            self.core
                .ctx
                .device()
                .cmd_write_timestamp2(rec.raw(), stage, self.core.raw, index)
        };
        Ok(())
    }

    /// Reads the first `count` raw timestamps (masked to the valid bits). If they are not ready,
    /// waits (at most the GPU timeout) for every submission made so far; timestamps still
    /// missing then were never submitted, which is an error rather than a wait forever.
    pub fn read_ticks(&self, count: u32) -> VkResult<Vec<u64>> {
        let mut ticks = vec![0u64; count as usize];
        self.core.read(&mut ticks, "timestamps")?;
        Ok(ticks.into_iter().map(|t| t & self.mask).collect())
    }

    /// When the device's clock read `ticks`, on the host's clock, from a calibration taken near
    /// it ([`Context::calibrate`]); ticks before the calibration come out before its instant.
    pub fn host_time(&self, pair: &ClockPair, ticks: u64) -> Instant {
        let ahead = ticks.wrapping_sub(pair.gpu_ticks) & self.mask;
        let behind = pair.gpu_ticks.wrapping_sub(ticks) & self.mask;
        let ns = |t: u64| Duration::from_nanos((t as f64 * self.period_ns).round() as u64);
        if ahead <= behind {
            pair.host + ns(ahead)
        } else {
            pair.host.checked_sub(ns(behind)).unwrap_or(pair.host)
        }
    }

    /// Milliseconds between two raw ticks (handles a wrap of the valid bits).
    pub fn ticks_to_ms(&self, start: u64, end: u64) -> f64 {
        let delta = end.wrapping_sub(start) & self.mask;
        delta as f64 * self.period_ns * 1e-6
    }
}

/// The device's timestamp counter and the host's clock read at one moment.
#[derive(Debug, Clone, Copy)]
pub struct ClockPair {
    /// The device's counter, in timestamp ticks (masked to the valid bits).
    pub gpu_ticks: u64,
    /// The host's clock at the same moment.
    pub host: Instant,
    /// How far apart the two readings may be: half the time the host took to read the
    /// device's counter.
    pub uncertainty: Duration,
}
