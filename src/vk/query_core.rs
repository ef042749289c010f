//! What every query pool relief makes shares: the pool's creation, named and counted, reset from
//! the host before first use; a host reset; reading results, waiting for the submissions made so
//! far when they are not ready; and its deferred destruction. The timestamp and
//! pipeline-statistics pools build on it with their own rules for writing queries.

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use super::counters::Created;
use super::deferred::Doomed;
use super::error::{Named, VkError, VkResult};

/// One Vulkan query pool of `capacity` queries.
pub(super) struct QueryCore {
    pub ctx: Arc<Context>,
    pub raw: vk::QueryPool,
    pub capacity: u32,
}

impl QueryCore {
    /// Creates the pool `create` describes (its count is `capacity`), names it and resets it.
    pub fn new(
        ctx: &Arc<Context>,
        create: vk::QueryPoolCreateInfo,
        name: &str,
    ) -> VkResult<QueryCore> {
        let capacity = create.query_count;
        // SAFETY: valid device and create info (the caller checked the features it needs).
        let raw =
            unsafe { ctx.device().create_query_pool(&create, None) }.named("vkCreateQueryPool")?;
        ctx.set_name(raw, name);
        ctx.count(Created::QueryPool);
        // SAFETY: hostQueryReset is enabled at device creation; the pool is unused.
        unsafe { ctx.device().reset_query_pool(raw, 0, capacity) };
        Ok(QueryCore {
            ctx: ctx.clone(),
            raw,
            capacity,
        })
    }

    /// Resets every query from the host.
    ///
    /// # Safety
    /// No pending submission and no open recording may use the pool.
    pub unsafe fn reset(&self) {
        // SAFETY: hostQueryReset is enabled; the caller's contract keeps the device away.
        unsafe {
            self.ctx
                .device()
                .reset_query_pool(self.raw, 0, self.capacity)
        };
    }

    /// Reads the results of the first `values.len()` queries, one element per query (its
    /// results as 64-bit values). If they are not ready, waits (at most the GPU timeout) for every
    /// submission made so far; results still missing then were never submitted, which is an
    /// error naming `what` rather than a wait forever.
    pub fn read<T>(&self, values: &mut [T], what: &str) -> VkResult<()> {
        let count = values.len();
        if count > self.capacity as usize {
            return Err(VkError::Invalid(format!(
                "{count} {what} read from a pool of {}",
                self.capacity
            )));
        }
        if count == 0 || self.try_read(values)? {
            return Ok(());
        }
        self.ctx.wait_submitted(what)?;
        if self.try_read(values)? {
            return Ok(());
        }
        Err(VkError::Invalid(format!(
            "{count} {what} read before the work writing them was submitted"
        )))
    }

    /// Reads without waiting; `false` when some results are not available yet.
    fn try_read<T>(&self, values: &mut [T]) -> VkResult<bool> {
        // SAFETY: one element per query, sized by the caller to that query's 64-bit results;
        // the count is at most the pool's capacity (checked in `read`).
        let got = unsafe {
            self.ctx.device().get_query_pool_results(
                self.raw,
                0,
                values,
                vk::QueryResultFlags::TYPE_64,
            )
        };
        match got {
            Ok(()) => Ok(true),
            Err(vk::Result::NOT_READY) => Ok(false),
            Err(e) => Err(e).named("vkGetQueryPoolResults"),
        }
    }
}

impl Drop for QueryCore {
    fn drop(&mut self) {
        self.ctx.defer(Doomed::QueryPool(self.raw));
    }
}
