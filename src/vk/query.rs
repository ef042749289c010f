//! GPU timestamps: a query pool that checks the device supports them, masks the values to the
//! valid bits and converts ticks to milliseconds with `timestampPeriod`.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

use ash::vk;

use super::context::Context;
use super::counters::Created;
use super::deferred::Doomed;
use super::error::{Named, VkError, VkResult};
use super::recording::Recording;

/// A pool of `capacity` timestamp queries, reset from the host before each use.
pub struct TimestampPool {
    ctx: Arc<Context>,
    raw: vk::QueryPool,
    capacity: u32,
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
        // SAFETY: valid device and create info.
        let raw =
            unsafe { ctx.device().create_query_pool(&create, None) }.named("vkCreateQueryPool")?;
        ctx.set_name(raw, name);
        ctx.count(Created::QueryPool);
        // SAFETY: hostQueryReset is enabled at device creation; the pool is unused.
        unsafe { ctx.device().reset_query_pool(raw, 0, capacity) };
        Ok(TimestampPool {
            ctx: ctx.clone(),
            raw,
            capacity,
            written: (0..capacity).map(|_| AtomicBool::new(false)).collect(),
            mask,
            period_ns: f64::from(info.timestamp_period_ns),
        })
    }

    /// How many timestamps the pool holds.
    pub fn capacity(&self) -> u32 {
        self.capacity
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
        // SAFETY: hostQueryReset is enabled; the caller's contract keeps the device away.
        unsafe {
            self.ctx
                .device()
                .reset_query_pool(self.raw, 0, self.capacity)
        };
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
        if index >= self.capacity {
            return Err(VkError::Invalid(format!(
                "timestamp {index} of {}",
                self.capacity
            )));
        }
        if self.written[index as usize].swap(true, Ordering::Relaxed) {
            return Err(VkError::Invalid(format!(
                "timestamp {index} written twice without a reset"
            )));
        }
        // SAFETY: `rec` is recording; the query was reset and not written since (checked above).
        unsafe {
            self.ctx
                .device()
                .cmd_write_timestamp2(rec.raw(), stage, self.raw, index)
        };
        Ok(())
    }

    /// Reads the first `count` raw timestamps (masked to the valid bits). If they are not ready,
    /// waits (at most the GPU timeout) for every submission made so far; timestamps still
    /// missing then were never submitted, which is an error rather than a wait forever.
    pub fn read_ticks(&self, count: u32) -> VkResult<Vec<u64>> {
        if count > self.capacity {
            return Err(VkError::Invalid(format!(
                "{count} timestamps read from a pool of {}",
                self.capacity
            )));
        }
        let mut ticks = vec![0u64; count as usize];
        if count == 0 {
            return Ok(ticks);
        }
        if !self.try_read(&mut ticks)? {
            self.ctx.wait_submitted("timestamp queries")?;
            if !self.try_read(&mut ticks)? {
                return Err(VkError::Invalid(format!(
                    "{count} timestamps read before the work writing them was submitted"
                )));
            }
        }
        Ok(ticks.into_iter().map(|t| t & self.mask).collect())
    }

    /// Reads `ticks.len()` results without waiting; `false` when some are not available yet.
    fn try_read(&self, ticks: &mut [u64]) -> VkResult<bool> {
        // SAFETY: `ticks` has room for its length of 64-bit results, and that length is at most
        // the pool's capacity (checked by the caller).
        let got = unsafe {
            self.ctx.device().get_query_pool_results(
                self.raw,
                0,
                ticks,
                vk::QueryResultFlags::TYPE_64,
            )
        };
        match got {
            Ok(()) => Ok(true),
            Err(vk::Result::NOT_READY) => Ok(false),
            Err(e) => Err(e).named("vkGetQueryPoolResults"),
        }
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

impl Drop for TimestampPool {
    fn drop(&mut self) {
        self.ctx.defer(Doomed::QueryPool(self.raw));
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
