//! Timestamp scopes around passes, and where the device counts them, the pipeline statistics of
//! each scope. Each frame slot has its own timer: a scope writes a timestamp before and after the
//! pass's commands (and begins and ends a statistics query around them), and the values are read
//! when the slot comes round again, after its fence, so reading never stalls the frame being
//! recorded.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use serde::Serialize;

use super::pass::Pass;
use crate::vk::{
    ClockPair, Context, PipelineCounts, Recording, StatisticsPool, TimestampPool, VkError, VkResult,
};

/// GPU time of one pass in one frame (the sum of its scopes), and what it made the device run.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PassTiming {
    /// The pass timed.
    pub pass: Pass,
    /// Milliseconds between its timestamps, summed over its scopes.
    pub gpu_ms: f64,
    /// Its scopes' pipeline statistics summed, where the device counts them and every scope of
    /// the pass was counted.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub counts: Option<PipelineCounts>,
}

/// One scope as the GPU ran it.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TimedScope {
    /// Which scope.
    pub scope: Scope,
    /// Milliseconds between its timestamps.
    pub gpu_ms: f64,
    /// Its two timestamps, in the device's ticks.
    pub ticks: [u64; 2],
    /// Its pipeline statistics, where counted.
    pub counts: Option<PipelineCounts>,
}

/// One timed scope: a pass, and for passes recorded per height map, which one.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Scope {
    /// The pass the scope belongs to; a frame's [`PassTiming`] sums its scopes.
    pub pass: Pass,
    /// For the pyramid and AO passes, which height map or AO map (in the frame's order);
    /// `None` for passes recorded once.
    pub part: Option<usize>,
}

/// A timestamp pool, a statistics pool where the device has one, and the scopes recorded into
/// them since the last reset (each with its statistics query, if counted).
pub struct PassTimer {
    pool: TimestampPool,
    statistics: Option<StatisticsPool>,
    scopes: Vec<(Scope, Option<u32>)>,
    counted: u32,
}

impl PassTimer {
    /// A timer for up to `max_scopes` scopes per frame; it counts them too where the device has
    /// pipeline statistics queries.
    pub fn new(ctx: &Arc<Context>, max_scopes: u32, name: &str) -> VkResult<PassTimer> {
        let statistics = match StatisticsPool::new(ctx, max_scopes, &format!("{name} counts")) {
            Ok(pool) => Some(pool),
            Err(VkError::Unsupported(_)) => None,
            Err(e) => return Err(e),
        };
        Ok(PassTimer {
            pool: TimestampPool::new(ctx, 2 * max_scopes, name)?,
            statistics,
            scopes: Vec::new(),
            counted: 0,
        })
    }

    /// When the device's clock read `ticks`, on the host's clock (see
    /// [`TimestampPool::host_time`]).
    pub fn host_time(&self, pair: &ClockPair, ticks: u64) -> Instant {
        self.pool.host_time(pair, ticks)
    }

    /// Milliseconds per device tick.
    pub fn ms_per_tick(&self) -> f64 {
        self.pool.period_ns() * 1e-6
    }

    /// Forgets the last frame's scopes.
    ///
    /// # Safety
    /// As [`TimestampPool::reset`]: no pending submission or open recording may write the pool.
    pub unsafe fn reset(&mut self) {
        // SAFETY: the caller's contract.
        unsafe { self.pool.reset() };
        if let Some(statistics) = &self.statistics {
            // SAFETY: as above; the two pools are used by the same recordings.
            unsafe { statistics.reset() };
        }
        self.scopes.clear();
        self.counted = 0;
    }

    /// Records `record` between two timestamps, as one scope of `pass`, counted where the
    /// device counts. `record` must begin and end any rendering it begins (a statistics query may
    /// not span a rendering's begin or end); [`PassTimer::scope_uncounted`] times one that does.
    pub fn scope<R>(
        &mut self,
        rec: &Recording,
        scope: Scope,
        record: impl FnOnce(&Recording) -> VkResult<R>,
    ) -> VkResult<R> {
        let query = match &self.statistics {
            Some(statistics) => {
                let index = self.counted;
                statistics.begin(rec, index)?;
                self.counted += 1;
                Some(index)
            }
            None => None,
        };
        let value = self.timed(rec, scope, query, record)?;
        if let (Some(statistics), Some(index)) = (&self.statistics, query) {
            statistics.end(rec, index)?;
        }
        Ok(value)
    }

    /// As [`PassTimer::scope`], timed only: for a scope that begins a rendering another scope
    /// ends, or ends one another began.
    pub fn scope_uncounted<R>(
        &mut self,
        rec: &Recording,
        scope: Scope,
        record: impl FnOnce(&Recording) -> VkResult<R>,
    ) -> VkResult<R> {
        self.timed(rec, scope, None, record)
    }

    fn timed<R>(
        &mut self,
        rec: &Recording,
        scope: Scope,
        query: Option<u32>,
        record: impl FnOnce(&Recording) -> VkResult<R>,
    ) -> VkResult<R> {
        let index = 2 * self.scopes.len() as u32;
        if index + 2 > self.pool.capacity() {
            return Err(VkError::Invalid(format!(
                "more than {} timed scopes in one frame",
                self.pool.capacity() / 2
            )));
        }
        let all = vk::PipelineStageFlags2::ALL_COMMANDS;
        self.pool.write(rec, all, index)?;
        let value = record(rec)?;
        self.pool.write(rec, all, index + 1)?;
        self.scopes.push((scope, query));
        Ok(value)
    }

    /// Every scope recorded since the last reset, in recording order, with its time and counts.
    /// Call once the frame's fence has signalled (the results are then available at once).
    pub fn read(&self) -> VkResult<Vec<TimedScope>> {
        if self.scopes.is_empty() {
            return Ok(Vec::new());
        }
        let ticks = self.pool.read_ticks(2 * self.scopes.len() as u32)?;
        let counts = match &self.statistics {
            Some(statistics) => statistics.read(self.counted)?,
            None => Vec::new(),
        };
        Ok(self
            .scopes
            .iter()
            .zip(ticks.chunks_exact(2))
            .map(|(&(scope, query), t)| TimedScope {
                scope,
                gpu_ms: self.pool.ticks_to_ms(t[0], t[1]),
                ticks: [t[0], t[1]],
                counts: query.and_then(|q| counts.get(q as usize).copied()),
            })
            .collect())
    }
}

/// Sums scopes per pass, in the order passes first appear; a pass's counts are summed only if
/// every one of its scopes was counted.
pub fn per_pass(scopes: &[TimedScope]) -> Vec<PassTiming> {
    let mut out: Vec<PassTiming> = Vec::new();
    for s in scopes {
        match out.iter_mut().find(|t| t.pass == s.scope.pass) {
            Some(t) => {
                t.gpu_ms += s.gpu_ms;
                t.counts = t.counts.zip(s.counts).map(|(a, b)| a.plus(b));
            }
            None => out.push(PassTiming {
                pass: s.scope.pass,
                gpu_ms: s.gpu_ms,
                counts: s.counts,
            }),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    fn counts(fragments: u64) -> Option<PipelineCounts> {
        Some(PipelineCounts {
            fragment_invocations: fragments,
            ..PipelineCounts::default()
        })
    }

    fn timed(pass: Pass, part: Option<usize>, gpu_ms: f64, counted: Option<u64>) -> TimedScope {
        TimedScope {
            scope: Scope { pass, part },
            gpu_ms,
            ticks: [0, 0],
            counts: counted.and_then(counts),
        }
    }

    #[test]
    fn scopes_of_one_pass_add_up_in_first_seen_order() {
        let list = [
            timed(Pass::Pyramid, Some(0), 1.0, Some(3)),
            timed(Pass::Pyramid, Some(1), 2.5, Some(4)),
            timed(Pass::Surface, None, 10.0, Some(9)),
        ];
        let sums = per_pass(&list);
        assert_eq!(sums.len(), 2);
        assert_eq!((sums[0].pass, sums[0].gpu_ms), (Pass::Pyramid, 3.5));
        assert_eq!(sums[0].counts, counts(7));
        assert_eq!((sums[1].pass, sums[1].gpu_ms), (Pass::Surface, 10.0));
        assert_eq!(sums[1].counts, counts(9));
    }

    #[test]
    fn a_pass_with_an_uncounted_scope_has_no_counts() {
        let list = [
            timed(Pass::Surface, None, 1.0, Some(3)),
            timed(Pass::Surface, None, 2.0, None),
        ];
        assert_eq!(per_pass(&list)[0].counts, None);
    }
}
