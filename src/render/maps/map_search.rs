//! The host side shared by the GPU map builders that search a max pyramid per texel
//! (`cone_map.comp`, `quadric_map.comp`): the pyramid's layout in one storage buffer
//! (`shaders/include/buffer_pyramid.glsl`), and one build: upload level 0, reduce it to 1x1 (a
//! dispatch per level), search the texels in submissions of about [`ROWS_TEXELS`] texels (so no
//! submission holds the queue for seconds: real GPUs reset a device that does; lavapipe has no
//! such watchdog), read the map back, and sum the GPU time of every submission.
//!
//! Each shader's push constants start with `mode, width, height, repeat_address, level, row0`;
//! the builder fills in the rest. Binding 0 is the pyramid, binding 1 the map.

use std::sync::Arc;

use ash::vk;

use crate::heightfield::MapData;
use crate::render::compute_pass::ComputePass;
use crate::render::shader_interface::{
    self, BINDING_SEARCH_MAP, BINDING_SEARCH_PYRAMID, MODE_REDUCE, MODE_SEARCH,
};
use crate::vk::{
    memory_barrier, Bind, Buffer, Context, DescriptorPool, DescriptorSet, MemoryLocation, Pipeline,
    Readback, Recording, TimestampPool, VkError, VkResult,
};

/// The workgroup is 8x8 texels.
pub(in crate::render) const GROUP: u32 = 8;
/// About this many texels per submission of the search.
const ROWS_TEXELS: u32 = 1 << 20;
/// The largest side the GPU builders take: the cone search packs texel indices in 14 bits, and
/// the push constants hold `MAX_LEVELS` level offsets. Larger maps are built on the CPU.
pub const MAX_SIDE: u32 = crate::heightfield::MAX_SIDE;
/// Levels of a [`MAX_SIDE`] map.
pub(in crate::render) const MAX_LEVELS: usize = shader_interface::MAX_LEVELS as usize;

/// A search shader's pipeline with its layout (bindings 0 and 1, storage buffers) and one
/// descriptor set, rewritten for every build (builds wait for their submissions, so the set is
/// never in use when it is rewritten).
pub(in crate::render) struct SearchPipeline {
    pub pass: ComputePass,
    _pool: DescriptorPool,
    pub set: DescriptorSet,
    /// Storage buffers at `0..bindings`.
    bindings: u32,
}

impl SearchPipeline {
    /// The pipeline of shader `key` with `push` bytes of push constants, named `name`, and
    /// storage buffers at bindings `0..bindings`.
    pub fn new(
        ctx: &Arc<Context>,
        key: &str,
        push: u32,
        bindings: u32,
        name: &str,
    ) -> VkResult<SearchPipeline> {
        let pass = ComputePass::plain(ctx, key, &storage_slots(bindings), push, name)?;
        let pool = DescriptorPool::new(ctx, 1, bindings, &format!("{name} sets"))?;
        let set = pool.allocate(pass.layout(), &[])?;
        Ok(SearchPipeline {
            pass,
            _pool: pool,
            set,
            bindings,
        })
    }

    /// The pipeline of another kernel, shader `key` with `push` bytes of push constants, whose
    /// set layout is defined as this one's, so the one set serves both.
    pub fn kernel(
        &self,
        ctx: &Arc<Context>,
        key: &str,
        push: u32,
        name: &str,
    ) -> VkResult<ComputePass> {
        ComputePass::plain(ctx, key, &storage_slots(self.bindings), push, name)
    }

    /// Builds a map of `channels` floats per texel from `level0` (`w` x `h`) with the push
    /// constants `params` gives per mode, level and first row: the map and the GPU ms.
    pub fn build<P: bytemuck::Pod>(
        &self,
        ctx: &Arc<Context>,
        (level0, w, h): (&[f32], u32, u32),
        channels: u32,
        name: &str,
        params: &dyn Fn(u32, u32, u32) -> P,
    ) -> VkResult<(MapData, f64)> {
        let search = MapSearch {
            pipeline: self.pass.pipeline(),
            set: self.set.clone(),
            channels,
            name,
            params,
        };
        let (texels, gpu_ms) = search.run(ctx, level0, w, h)?;
        let map = MapData {
            width: w,
            height: h,
            channels,
            texels,
        };
        Ok((map, gpu_ms))
    }
}

/// Storage buffers at bindings `0..bindings`, the layout of every search shader's set.
fn storage_slots(bindings: u32) -> Vec<(u32, vk::DescriptorType)> {
    (0..bindings)
        .map(|b| (b, vk::DescriptorType::STORAGE_BUFFER))
        .collect()
}

/// What one build holds in single storage buffers: its pyramid of `node_bytes` a node and its
/// map of `channels` floats a texel.
#[derive(Clone, Copy)]
pub struct SearchBuffers {
    pub node_bytes: u64,
    pub channels: u32,
}

impl SearchBuffers {
    /// The largest buffer a `w` x `h` build needs, in bytes.
    pub fn largest(self, w: u32, h: u32) -> u64 {
        let map = u64::from(w) * u64::from(h) * u64::from(self.channels) * 4;
        (pyramid_floats(w, h) * self.node_bytes).max(map)
    }

    /// Whether this device takes a `w` x `h` build: sides up to [`MAX_SIDE`] and every buffer
    /// within its largest storage buffer (lavapipe's 256 MiB hold a 4096^2 quadric map but no
    /// 8192^2 pyramid).
    pub fn fit(self, ctx: &Context, w: u32, h: u32) -> bool {
        w <= MAX_SIDE
            && h <= MAX_SIDE
            && self.largest(w, h) <= u64::from(ctx.info().max_storage_buffer_range)
    }

    /// Fails for builds [`SearchBuffers::fit`] refuses; `what` names the map.
    pub fn check(self, ctx: &Context, what: &str, w: u32, h: u32) -> VkResult<()> {
        if w > MAX_SIDE || h > MAX_SIDE {
            return Err(VkError::Invalid(format!(
                "{what} of {w}x{h}: the GPU builder takes at most {MAX_SIDE} texels a side"
            )));
        }
        if !self.fit(ctx, w, h) {
            return Err(VkError::Invalid(format!(
                "{what} of {w}x{h}: a buffer of {} MiB exceeds the device's largest storage \
                 buffer ({} MiB)",
                self.largest(w, h) >> 20,
                ctx.info().max_storage_buffer_range >> 20
            )));
        }
        Ok(())
    }
}

/// What one build dispatches: the pipeline, its set (rewritten for the build's buffers) and the
/// push constants for a mode, a level and a first row.
pub(in crate::render) struct MapSearch<'a, P> {
    pub pipeline: &'a Pipeline,
    pub set: DescriptorSet,
    /// Floats per texel of the map.
    pub channels: u32,
    /// Names the buffers (validation messages show it).
    pub name: &'a str,
    pub params: &'a dyn Fn(u32, u32, u32) -> P,
}

impl<P: bytemuck::Pod> MapSearch<'_, P> {
    /// Builds the map of level 0 (`width` x `height` floats): its texels and the GPU ms (the
    /// pyramid and every search submission; not the transfers).
    pub fn run(
        &self,
        ctx: &Arc<Context>,
        level0: &[f32],
        w: u32,
        h: u32,
    ) -> VkResult<(Vec<f32>, f64)> {
        let texels = u64::from(w) * u64::from(h);
        let staging = Buffer::with_data(
            ctx,
            bytemuck::cast_slice(level0),
            vk::BufferUsageFlags::TRANSFER_SRC,
            &format!("{} heights", self.name),
        )?;
        let pyramid = Buffer::new(
            ctx,
            pyramid_floats(w, h) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
            &format!("{} pyramid", self.name),
        )?;
        let bytes = texels * u64::from(self.channels) * 4;
        let out = Buffer::new(
            ctx,
            bytes,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
            self.name,
        )?;
        let back = Readback::new(ctx, bytes, &format!("{} readback", self.name))?;
        // SAFETY: every submission that bound the set was a one-shot (warm-ups and timed
        // submissions), and one-shots return only once their work has finished.
        unsafe {
            self.set.rewrite(&[
                Bind::Storage(BINDING_SEARCH_PYRAMID, &pyramid),
                Bind::Storage(BINDING_SEARCH_MAP, &out),
            ])
        }?;
        let past_end = (self.params)(MODE_SEARCH, 0, h);
        warm_up(ctx, self.pipeline, &self.set, bytemuck::bytes_of(&past_end))?;
        let chunks = row_chunks(w, h);
        let mut timed = TimedSubmissions::new(ctx, 1 + chunks.len() as u32, self.name)?;
        timed.submit(ctx, |rec| {
            rec.copy_buffer(&staging, &pyramid);
            memory_barrier(rec, COPIED, COMPUTE_RW);
            self.pipeline.bind(rec, Some(&self.set));
            record_reductions(rec, self.pipeline, w, h, |level| {
                (self.params)(MODE_REDUCE, level, 0)
            })
        })?;
        for (row0, count) in chunks {
            timed.submit(ctx, |rec| self.record_rows(rec, w, row0, count))?;
        }
        // Outside the timed submissions: the map reaches the host by a copy and the host barrier.
        ctx.one_shot(|rec| back.record_copy_from_buffer(rec, &out, SHADER_WROTE))?;
        let gpu_ms = timed.total_ms()?;
        Ok((bytemuck::pod_collect_to_vec(back.bytes()?), gpu_ms))
    }

    /// Searches `count` rows from `row0`.
    fn record_rows(&self, rec: &Recording, w: u32, row0: u32, count: u32) -> VkResult<()> {
        let params = (self.params)(MODE_SEARCH, 0, row0);
        let push = bytemuck::bytes_of(&params);
        record_row_dispatch(rec, self.pipeline, &self.set, push, w, count)
    }
}

/// Binds `pipeline` and `set`, pushes `push` and dispatches one invocation per texel of `count`
/// rows of a `w`-wide map (the push constants say which), then a barrier for the dispatches
/// after it (the read-back copy adds its own).
pub(in crate::render) fn record_row_dispatch(
    rec: &Recording,
    pipeline: &Pipeline,
    set: &DescriptorSet,
    push: &[u8],
    w: u32,
    count: u32,
) -> VkResult<()> {
    pipeline.bind(rec, Some(set));
    pipeline.push(rec, push)?;
    rec.dispatch([w.div_ceil(GROUP), count.div_ceil(GROUP), 1]);
    memory_barrier(rec, COMPUTE_RW, COMPUTE_RW);
    Ok(())
}

/// Dispatches one workgroup of `pipeline` whose work lies past the end (`push` says so: rows past
/// the map's, no rays), in a submission of its own before the timed ones. Every invocation returns
/// at once, but llvmpipe compiles a pipeline at its first dispatch (over half a second for the
/// quadric search with Mesa's shader cache cold), and a driver's compile is not the build's GPU
/// time; drivers that compile at pipeline creation pay for an empty dispatch.
pub(in crate::render) fn warm_up(
    ctx: &Arc<Context>,
    pipeline: &Pipeline,
    set: &DescriptorSet,
    push: &[u8],
) -> VkResult<()> {
    ctx.one_shot(|rec| {
        pipeline.bind(rec, Some(set));
        pipeline.push(rec, push)?;
        rec.dispatch([1, 1, 1]);
        Ok(())
    })
}

/// A copy's writes, for the shader reads and writes after it.
pub(in crate::render) const COPIED: (vk::PipelineStageFlags2, vk::AccessFlags2) = (
    vk::PipelineStageFlags2::COPY,
    vk::AccessFlags2::TRANSFER_WRITE,
);
/// Compute-shader reads and writes of storage buffers.
pub(in crate::render) const COMPUTE_RW: (vk::PipelineStageFlags2, vk::AccessFlags2) = (
    vk::PipelineStageFlags2::COMPUTE_SHADER,
    vk::AccessFlags2::from_raw(
        vk::AccessFlags2::SHADER_STORAGE_READ.as_raw()
            | vk::AccessFlags2::SHADER_STORAGE_WRITE.as_raw(),
    ),
);
/// Compute-shader writes of storage buffers.
pub(in crate::render) const SHADER_WROTE: (vk::PipelineStageFlags2, vk::AccessFlags2) = (
    vk::PipelineStageFlags2::COMPUTE_SHADER,
    vk::AccessFlags2::SHADER_STORAGE_WRITE,
);

/// Records one dispatch per level 1..=top of a `w` x `h` pyramid with the push constants
/// `params(level)` gives (the pipeline already bound), a barrier after each.
pub(in crate::render) fn record_reductions<P: bytemuck::Pod>(
    rec: &Recording,
    pipeline: &Pipeline,
    w: u32,
    h: u32,
    params: impl Fn(u32) -> P,
) -> VkResult<()> {
    for level in 1..=top_level(w, h) {
        let (lw, lh) = level_size(w, h, level);
        pipeline.push(rec, bytemuck::bytes_of(&params(level)))?;
        rec.dispatch([lw.div_ceil(GROUP), lh.div_ceil(GROUP), 1]);
        memory_barrier(rec, COMPUTE_RW, COMPUTE_RW);
    }
    Ok(())
}

/// Submissions that each wait for their work and are timed start to end; the builders' GPU time
/// is their sum (not the transfers to and from the host between them).
pub(in crate::render) struct TimedSubmissions {
    timestamps: TimestampPool,
    used: u32,
    name: String,
}

impl TimedSubmissions {
    /// Room for `count` submissions.
    pub fn new(ctx: &Arc<Context>, count: u32, name: &str) -> VkResult<TimedSubmissions> {
        let timestamps = TimestampPool::new(ctx, 2 * count, &format!("{name} timestamps"))?;
        Ok(TimedSubmissions {
            timestamps,
            used: 0,
            name: name.to_owned(),
        })
    }

    /// Records `record` between two timestamps, submits it and waits.
    pub fn submit(
        &mut self,
        ctx: &Arc<Context>,
        record: impl FnOnce(&Recording) -> VkResult<()>,
    ) -> VkResult<()> {
        let all = vk::PipelineStageFlags2::ALL_COMMANDS;
        let first = 2 * self.used;
        ctx.one_shot(|rec| {
            self.timestamps.write(rec, all, first)?;
            record(rec)?;
            self.timestamps.write(rec, all, first + 1)
        })?;
        self.used += 1;
        Ok(())
    }

    /// The GPU ms of every submission so far, summed.
    pub fn total_ms(&self) -> VkResult<f64> {
        let ticks = self.timestamps.read_ticks(2 * self.used)?;
        let each: Vec<f64> = ticks
            .chunks_exact(2)
            .map(|t| self.timestamps.ticks_to_ms(t[0], t[1]))
            .collect();
        log::debug!("{}: GPU ms per submission {each:.1?}", self.name);
        Ok(each.iter().sum())
    }
}

/// The level whose single node covers the map (`top` in the shaders).
pub(in crate::render) fn top_level(w: u32, h: u32) -> u32 {
    w.max(h).max(1).next_power_of_two().trailing_zeros()
}

/// Level `level` of the pyramid: node `i` covers level-0 texels `[i, i + 1) * 2^level`.
fn level_size(w: u32, h: u32, level: u32) -> (u32, u32) {
    (w.div_ceil(1 << level), h.div_ceil(1 << level))
}

/// Where each level starts in the pyramid buffer, in floats (zero past the top).
pub(in crate::render) fn level_offsets(w: u32, h: u32) -> [u32; MAX_LEVELS] {
    let mut offsets = [0; MAX_LEVELS];
    let mut at = 0;
    for (l, slot) in offsets
        .iter_mut()
        .enumerate()
        .take(top_level(w, h) as usize + 1)
    {
        *slot = at;
        let (lw, lh) = level_size(w, h, l as u32);
        at += lw * lh;
    }
    offsets
}

/// Nodes of every level of a `w` x `h` pyramid.
pub(in crate::render) fn pyramid_floats(w: u32, h: u32) -> u64 {
    (0..=top_level(w, h))
        .map(|l| {
            let (lw, lh) = level_size(w, h, l);
            u64::from(lw) * u64::from(lh)
        })
        .sum()
}

/// Rows per search submission: about [`ROWS_TEXELS`] texels, whole workgroups, at least one.
fn rows_per_submission(w: u32, h: u32) -> u32 {
    let rows = (ROWS_TEXELS / w.max(1)).max(GROUP);
    (rows.div_ceil(GROUP) * GROUP).min(h.div_ceil(GROUP) * GROUP)
}

/// The search submissions of a `w` x `h` map: `(first row, rows)` each.
pub(in crate::render) fn row_chunks(w: u32, h: u32) -> Vec<(u32, u32)> {
    let rows = rows_per_submission(w, h);
    (0..h.div_ceil(rows))
        .map(|chunk| (chunk * rows, rows.min(h - chunk * rows)))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pyramid_sizes_halve_up_to_one_node() {
        assert_eq!(top_level(1, 1), 0);
        assert_eq!(top_level(3, 5), 3);
        assert_eq!(top_level(256, 256), 8);
        assert_eq!(top_level(257, 129), 9);
        assert_eq!(level_size(257, 129, 9), (1, 1));
        assert_eq!(level_size(3, 5, 1), (2, 3));
        assert_eq!(pyramid_floats(3, 5), 15 + 6 + 2 + 1);
        assert_eq!(level_offsets(3, 5)[..5], [0, 15, 21, 23, 0]);
        assert_eq!(top_level(MAX_SIDE, 1) as usize, MAX_LEVELS - 1);
    }

    #[test]
    fn submissions_cover_every_row_in_whole_groups() {
        assert_eq!(rows_per_submission(4096, 4096), 256);
        assert_eq!(rows_per_submission(3, 5), 8);
        assert_eq!(rows_per_submission(1 << 20, 4), 8);
    }
}
