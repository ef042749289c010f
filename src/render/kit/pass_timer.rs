//! Timestamp scopes around passes. Each frame slot has its own timer: a scope writes a timestamp
//! before and after the pass's commands, and the values are read when the slot comes round
//! again, after its fence, so reading never stalls the frame being recorded.

use std::sync::Arc;

use ash::vk;
use serde::Serialize;

use super::pass::Pass;
use crate::vk::{Context, Recording, TimestampPool, VkError, VkResult};

/// GPU time of one pass in one frame (the sum of its scopes).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct PassTiming {
    /// The pass timed.
    pub pass: Pass,
    /// Milliseconds between its timestamps, summed over its scopes.
    pub gpu_ms: f64,
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

/// A timestamp pool and the scopes recorded into it since the last reset.
pub struct PassTimer {
    pool: TimestampPool,
    scopes: Vec<Scope>,
}

impl PassTimer {
    /// A timer for up to `max_scopes` scopes per frame.
    pub fn new(ctx: &Arc<Context>, max_scopes: u32, name: &str) -> VkResult<PassTimer> {
        Ok(PassTimer {
            pool: TimestampPool::new(ctx, 2 * max_scopes, name)?,
            scopes: Vec::new(),
        })
    }

    /// Forgets the last frame's scopes.
    ///
    /// # Safety
    /// As [`TimestampPool::reset`]: no pending submission or open recording may write the pool.
    pub unsafe fn reset(&mut self) {
        // SAFETY: the caller's contract.
        unsafe { self.pool.reset() };
        self.scopes.clear();
    }

    /// Records `record` between two timestamps, as one scope of `pass`.
    pub fn scope<R>(
        &mut self,
        rec: &Recording,
        scope: Scope,
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
        self.scopes.push(scope);
        Ok(value)
    }

    /// The milliseconds of every scope recorded since the last reset, in recording order. Call
    /// once the frame's fence has signalled (the results are then available at once).
    pub fn read(&self) -> VkResult<Vec<(Scope, f64)>> {
        if self.scopes.is_empty() {
            return Ok(Vec::new());
        }
        let ticks = self.pool.read_ticks(2 * self.scopes.len() as u32)?;
        Ok(self
            .scopes
            .iter()
            .zip(ticks.chunks_exact(2))
            .map(|(&scope, t)| (scope, self.pool.ticks_to_ms(t[0], t[1])))
            .collect())
    }
}

/// Sums scopes per pass, in the order passes first appear.
pub fn per_pass(scopes: &[(Scope, f64)]) -> Vec<PassTiming> {
    let mut out: Vec<PassTiming> = Vec::new();
    for &(scope, ms) in scopes {
        match out.iter_mut().find(|t| t.pass == scope.pass) {
            Some(t) => t.gpu_ms += ms,
            None => out.push(PassTiming {
                pass: scope.pass,
                gpu_ms: ms,
            }),
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scopes_of_one_pass_add_up_in_first_seen_order() {
        let scope = |pass, part| Scope { pass, part };
        let list = [
            (scope(Pass::Pyramid, Some(0)), 1.0),
            (scope(Pass::Pyramid, Some(1)), 2.5),
            (scope(Pass::Surface, None), 10.0),
        ];
        let sums = per_pass(&list);
        assert_eq!(sums.len(), 2);
        assert_eq!((sums[0].pass, sums[0].gpu_ms), (Pass::Pyramid, 3.5));
        assert_eq!((sums[1].pass, sums[1].gpu_ms), (Pass::Surface, 10.0));
    }
}
