//! Pipeline-statistics queries: how many vertex, fragment and compute invocations and clipped
//! primitives the commands between a begin and an end made the device run. The counts are the
//! device's own: llvmpipe, for one, counts fragment invocations per 4x4 stamp before the depth
//! test, so they measure rasterised area rather than what survived culling.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

use ash::vk;
use serde::Serialize;

use super::context::Context;
use super::error::{VkError, VkResult};
use super::query_core::QueryCore;
use super::recording::Recording;

/// What each query counts, in the order Vulkan writes the results (by flag bit).
const COUNTED: [vk::QueryPipelineStatisticFlags; 4] = [
    vk::QueryPipelineStatisticFlags::VERTEX_SHADER_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::CLIPPING_PRIMITIVES,
    vk::QueryPipelineStatisticFlags::FRAGMENT_SHADER_INVOCATIONS,
    vk::QueryPipelineStatisticFlags::COMPUTE_SHADER_INVOCATIONS,
];

/// One query's counts.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, Serialize)]
pub struct PipelineCounts {
    /// Vertex shader invocations.
    pub vertex_invocations: u64,
    /// Primitives the clipper passed on to rasterisation.
    pub clipped_primitives: u64,
    /// Fragment shader invocations, as the device counts them.
    pub fragment_invocations: u64,
    /// Compute shader invocations.
    pub compute_invocations: u64,
}

impl PipelineCounts {
    /// The sum of two counts field by field.
    pub fn plus(self, other: PipelineCounts) -> PipelineCounts {
        PipelineCounts {
            vertex_invocations: self.vertex_invocations + other.vertex_invocations,
            clipped_primitives: self.clipped_primitives + other.clipped_primitives,
            fragment_invocations: self.fragment_invocations + other.fragment_invocations,
            compute_invocations: self.compute_invocations + other.compute_invocations,
        }
    }
}

/// A pool of `capacity` pipeline-statistics queries, reset from the host before each use.
pub struct StatisticsPool {
    core: QueryCore,
    /// Which queries were begun since the last reset (one use per reset).
    begun: Vec<AtomicBool>,
    /// Which begun queries were ended.
    ended: Vec<AtomicBool>,
}

impl StatisticsPool {
    /// Creates the pool, or says why the device cannot count (`pipelineStatisticsQuery`).
    pub fn new(ctx: &Arc<Context>, capacity: u32, name: &str) -> VkResult<StatisticsPool> {
        if !ctx.info().pipeline_statistics {
            return Err(VkError::Unsupported(
                "pipeline statistics queries (pipelineStatisticsQuery)".into(),
            ));
        }
        let flags = COUNTED
            .iter()
            .fold(vk::QueryPipelineStatisticFlags::empty(), |a, &f| a | f);
        let create = vk::QueryPoolCreateInfo::default()
            .query_type(vk::QueryType::PIPELINE_STATISTICS)
            .pipeline_statistics(flags)
            .query_count(capacity);
        let flags = || (0..capacity).map(|_| AtomicBool::new(false)).collect();
        Ok(StatisticsPool {
            core: QueryCore::new(ctx, create, name)?,
            begun: flags(),
            ended: flags(),
        })
    }

    /// How many queries the pool holds.
    pub fn capacity(&self) -> u32 {
        self.core.capacity
    }

    /// Resets every query from the host.
    ///
    /// # Safety
    /// No pending submission and no open recording may use the pool, as for
    /// [`TimestampPool::reset`](super::TimestampPool::reset).
    pub unsafe fn reset(&self) {
        // SAFETY: the caller's contract.
        unsafe { self.core.reset() };
        for flag in self.begun.iter().chain(&self.ended) {
            flag.store(false, Ordering::Relaxed);
        }
    }

    /// Starts counting into query `index`. Vulkan lets a query begin and end on either side of
    /// a rendering only if both are outside it, or both inside the same one: the caller keeps
    /// to that (the validation layer checks it).
    pub fn begin(&self, rec: &Recording, index: u32) -> VkResult<()> {
        self.check(index)?;
        if self.begun[index as usize].swap(true, Ordering::Relaxed) {
            return Err(VkError::Invalid(format!(
                "statistics query {index} begun twice without a reset"
            )));
        }
        // SAFETY: `rec` is recording; the query was reset and not used since (checked above).
        unsafe {
            self.core.ctx.device().cmd_begin_query(
                rec.raw(),
                self.core.raw,
                index,
                vk::QueryControlFlags::empty(),
            )
        };
        Ok(())
    }

    /// Stops counting into query `index`, begun in the same recording.
    pub fn end(&self, rec: &Recording, index: u32) -> VkResult<()> {
        self.check(index)?;
        let i = index as usize;
        if !self.begun[i].load(Ordering::Relaxed) || self.ended[i].swap(true, Ordering::Relaxed) {
            return Err(VkError::Invalid(format!(
                "statistics query {index} ended without being begun"
            )));
        }
        // SAFETY: `rec` is recording and began the query (checked above).
        unsafe {
            self.core
                .ctx
                .device()
                .cmd_end_query(rec.raw(), self.core.raw, index)
        };
        Ok(())
    }

    fn check(&self, index: u32) -> VkResult<()> {
        if index >= self.core.capacity {
            return Err(VkError::Invalid(format!(
                "statistics query {index} of {}",
                self.core.capacity
            )));
        }
        Ok(())
    }

    /// The counts of the first `count` queries, each begun and ended since the last reset.
    /// Waits (at most the GPU timeout) for every submission made so far when they are not
    /// ready yet.
    pub fn read(&self, count: u32) -> VkResult<Vec<PipelineCounts>> {
        let mut ended = self.ended.iter().take(count as usize);
        if let Some(i) = ended.position(|e| !e.load(Ordering::Relaxed)) {
            return Err(VkError::Invalid(format!(
                "statistics query {i} read before it was recorded"
            )));
        }
        let mut values = vec![[0u64; COUNTED.len()]; count as usize];
        self.core.read(&mut values, "statistics queries")?;
        Ok(values
            .iter()
            .map(|v| PipelineCounts {
                vertex_invocations: v[0],
                clipped_primitives: v[1],
                fragment_invocations: v[2],
                compute_invocations: v[3],
            })
            .collect())
    }
}
