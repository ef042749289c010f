//! How many Vulkan objects and memory allocations a context has created, and how many of them are
//! still alive: the evidence that a scene builds only what its plan lists (a test compares counts
//! before and after a frame) and that a long sequence holds no more objects at its end than after
//! its first frame.

use std::sync::atomic::{AtomicU64, Ordering};

/// Counts of objects created so far (never decremented).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct ObjectCounts {
    /// Graphics pipelines.
    pub graphics_pipelines: u64,
    /// Compute pipelines.
    pub compute_pipelines: u64,
    /// Images (each with its own allocation).
    pub images: u64,
    /// Buffers (each with its own allocation).
    pub buffers: u64,
    /// Samplers.
    pub samplers: u64,
    /// Descriptor sets.
    pub descriptor_sets: u64,
    /// Timestamp query pools.
    pub query_pools: u64,
    /// Command buffers (one-shot and frame slots).
    pub command_buffers: u64,
    /// Fences.
    pub fences: u64,
    /// CPU time spent in `vkCreate*Pipelines`, in microseconds.
    pub pipeline_create_us: u64,
    /// Device memory allocations (one per image and buffer, through gpu-allocator).
    pub allocations: u64,
    /// Bytes of those allocations.
    pub allocated_bytes: u64,
}

impl std::ops::Sub for ObjectCounts {
    type Output = ObjectCounts;

    fn sub(self, before: ObjectCounts) -> ObjectCounts {
        ObjectCounts {
            graphics_pipelines: self.graphics_pipelines - before.graphics_pipelines,
            compute_pipelines: self.compute_pipelines - before.compute_pipelines,
            images: self.images - before.images,
            buffers: self.buffers - before.buffers,
            samplers: self.samplers - before.samplers,
            descriptor_sets: self.descriptor_sets - before.descriptor_sets,
            query_pools: self.query_pools - before.query_pools,
            command_buffers: self.command_buffers - before.command_buffers,
            fences: self.fences - before.fences,
            pipeline_create_us: self.pipeline_create_us - before.pipeline_create_us,
            allocations: self.allocations - before.allocations,
            allocated_bytes: self.allocated_bytes - before.allocated_bytes,
        }
    }
}

/// Objects alive now: created and not yet destroyed. An object dropped while the GPU may still
/// use it stays alive until the deferred destruction retires it; a descriptor set stops being
/// alive when its last owner drops it (its pool's memory goes with the pool).
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct LiveObjects {
    /// Graphics and compute pipelines.
    pub pipelines: u64,
    /// Images.
    pub images: u64,
    /// Buffers.
    pub buffers: u64,
    /// Samplers.
    pub samplers: u64,
    /// Descriptor sets.
    pub descriptor_sets: u64,
    /// Timestamp query pools.
    pub query_pools: u64,
    /// Command buffers.
    pub command_buffers: u64,
    /// Fences.
    pub fences: u64,
    /// Device memory allocations.
    pub allocations: u64,
    /// Bytes of those allocations.
    pub allocated_bytes: u64,
}

impl LiveObjects {
    /// Each count as (name, value), in a fixed order: what a soak samples and fits.
    pub fn fields(&self) -> [(&'static str, u64); 10] {
        [
            ("pipelines", self.pipelines),
            ("images", self.images),
            ("buffers", self.buffers),
            ("samplers", self.samplers),
            ("descriptor_sets", self.descriptor_sets),
            ("query_pools", self.query_pools),
            ("command_buffers", self.command_buffers),
            ("fences", self.fences),
            ("allocations", self.allocations),
            ("allocated_bytes", self.allocated_bytes),
        ]
    }
}

/// What a context counts, by kind.
#[derive(Debug, Clone, Copy)]
pub(crate) enum Created {
    GraphicsPipeline,
    ComputePipeline,
    Image { bytes: u64 },
    Buffer { bytes: u64 },
    Sampler,
    DescriptorSet,
    QueryPool,
    CommandBuffer,
    Fence,
    PipelineTime { micros: u64 },
}

/// One tally of objects by kind: the created ones, or the destroyed ones.
#[derive(Debug, Default)]
struct Tally {
    graphics_pipelines: AtomicU64,
    compute_pipelines: AtomicU64,
    images: AtomicU64,
    buffers: AtomicU64,
    samplers: AtomicU64,
    descriptor_sets: AtomicU64,
    query_pools: AtomicU64,
    command_buffers: AtomicU64,
    fences: AtomicU64,
    pipeline_create_us: AtomicU64,
    allocations: AtomicU64,
    allocated_bytes: AtomicU64,
}

impl Tally {
    fn add(&self, what: Created) {
        let bump = |c: &AtomicU64, n: u64| {
            c.fetch_add(n, Ordering::Relaxed);
        };
        match what {
            Created::GraphicsPipeline => bump(&self.graphics_pipelines, 1),
            Created::ComputePipeline => bump(&self.compute_pipelines, 1),
            Created::Sampler => bump(&self.samplers, 1),
            Created::DescriptorSet => bump(&self.descriptor_sets, 1),
            Created::QueryPool => bump(&self.query_pools, 1),
            Created::CommandBuffer => bump(&self.command_buffers, 1),
            Created::Fence => bump(&self.fences, 1),
            Created::PipelineTime { micros } => bump(&self.pipeline_create_us, micros),
            Created::Image { bytes } | Created::Buffer { bytes } => {
                let counter = if matches!(what, Created::Image { .. }) {
                    &self.images
                } else {
                    &self.buffers
                };
                bump(counter, 1);
                bump(&self.allocations, 1);
                bump(&self.allocated_bytes, bytes);
            }
        }
    }

    fn snapshot(&self) -> ObjectCounts {
        let get = |c: &AtomicU64| c.load(Ordering::Relaxed);
        ObjectCounts {
            graphics_pipelines: get(&self.graphics_pipelines),
            compute_pipelines: get(&self.compute_pipelines),
            images: get(&self.images),
            buffers: get(&self.buffers),
            samplers: get(&self.samplers),
            descriptor_sets: get(&self.descriptor_sets),
            query_pools: get(&self.query_pools),
            command_buffers: get(&self.command_buffers),
            fences: get(&self.fences),
            pipeline_create_us: get(&self.pipeline_create_us),
            allocations: get(&self.allocations),
            allocated_bytes: get(&self.allocated_bytes),
        }
    }
}

/// The live counters a context keeps.
#[derive(Debug, Default)]
pub(crate) struct ObjectCounters {
    created: Tally,
    destroyed: Tally,
}

impl ObjectCounters {
    /// Counts an object created (or the time spent creating pipelines).
    pub(crate) fn record(&self, what: Created) {
        self.created.add(what);
    }

    /// Counts an object destroyed: `what` as it was counted when created.
    pub(crate) fn release(&self, what: Created) {
        self.destroyed.add(what);
    }

    pub(crate) fn snapshot(&self) -> ObjectCounts {
        self.created.snapshot()
    }

    /// What is alive now. Destructions are read first, so a creation and destruction racing
    /// with the read never make a count negative.
    pub(crate) fn alive(&self) -> LiveObjects {
        let gone = self.destroyed.snapshot();
        let made = self.created.snapshot();
        let live = |made: u64, gone: u64| made.saturating_sub(gone);
        LiveObjects {
            pipelines: live(
                made.graphics_pipelines + made.compute_pipelines,
                gone.graphics_pipelines + gone.compute_pipelines,
            ),
            images: live(made.images, gone.images),
            buffers: live(made.buffers, gone.buffers),
            samplers: live(made.samplers, gone.samplers),
            descriptor_sets: live(made.descriptor_sets, gone.descriptor_sets),
            query_pools: live(made.query_pools, gone.query_pools),
            command_buffers: live(made.command_buffers, gone.command_buffers),
            fences: live(made.fences, gone.fences),
            allocations: live(made.allocations, gone.allocations),
            allocated_bytes: live(made.allocated_bytes, gone.allocated_bytes),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{Created, ObjectCounters};

    #[test]
    fn alive_is_created_less_destroyed() {
        let c = ObjectCounters::default();
        c.record(Created::Buffer { bytes: 256 });
        c.record(Created::Buffer { bytes: 64 });
        c.record(Created::Image { bytes: 1024 });
        c.record(Created::ComputePipeline);
        c.record(Created::GraphicsPipeline);
        c.release(Created::Buffer { bytes: 256 });
        c.release(Created::GraphicsPipeline);
        let live = c.alive();
        assert_eq!((live.buffers, live.images, live.pipelines), (1, 1, 1));
        assert_eq!((live.allocations, live.allocated_bytes), (2, 64 + 1024));
        // Creations are never decremented.
        assert_eq!(c.snapshot().buffers, 2);
    }
}
