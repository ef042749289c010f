//! The conservative cone map built on the GPU (`shaders/passes/cone_map.comp`): the same map as
//! `ConeMap::build(hf, ConeKind::Conservative, address)` in the same `MapData` layout (ratio, bound
//! height), for maps where the CPU's seconds to minutes would dominate a run.
//!
//! Steps: the bilinear bound (`bilinear_box_bound`, linear time) is computed on the CPU, so the
//! surface channel is the CPU's bit for bit; it is uploaded into a storage buffer that the shader
//! turns into a max pyramid (one dispatch per level); then one invocation per texel searches that
//! pyramid over the 3x3 tiles (Repeat) or the map (Clamp). The search is exact, its arithmetic f32.
//!
//! Guarantee: every GPU ratio is at most the exact conservative ratio (never a wider cone) and at
//! least `(1 - RATIO_TOLERANCE)` times the CPU builder's ratio; the shader's header derives it
//! from the Vulkan precision rules.
//!
//! Large maps run as several submissions of [`ROWS_TEXELS`] texels each, so no submission holds
//! the queue for seconds (real GPUs reset a device that does; lavapipe has no such watchdog).

use std::sync::Arc;

use ash::vk;

use crate::heightfield::cone_map::bilinear_box_bound;
use crate::heightfield::{Address, Heightfield, MapData};
use crate::shaders;
use crate::vk::{
    compute_pipeline, memory_barrier, Bind, Buffer, Context, DescriptorLayout, DescriptorPool,
    DescriptorSet, MemoryLocation, Pipeline, Readback, Recording, SpecConstants, TimestampPool,
    VkError, VkResult,
};

/// The workgroup is 8x8 texels.
const GROUP: u32 = 8;
/// About this many texels per submission of the search.
const ROWS_TEXELS: u32 = 1 << 20;
/// The largest side the GPU builder takes: the stack packs texel indices in 14 bits (and the push
/// constants hold 15 level offsets). Larger maps are built on the CPU.
pub const MAX_SIDE: u32 = 16384;
/// `MAX_LEVELS` in the shader: levels of a `MAX_SIDE` map.
const MAX_LEVELS: usize = 15;
/// Relative amount by which a GPU ratio may fall short of the CPU's (never exceed it): the f32
/// search's error plus the step down that makes it conservative (see `cone_map.comp`).
pub const RATIO_TOLERANCE: f32 = 1.0 / 32768.0;

const MODE_REDUCE: u32 = 0;
const MODE_CONE: u32 = 1;

/// The shader's push constants (`Params` in cone_map.comp).
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Params {
    mode: u32,
    width: u32,
    height: u32,
    repeat_address: u32,
    level: u32,
    row0: u32,
    aspect: f32,
    top: u32,
    // Spelled out: with `MAX_LEVELS` here, rustc 1.95 hit an internal error ("broken MIR")
    // when a closure captured a copy of `Params`.
    offsets: [u32; 15],
}

const _: () = assert!(MAX_LEVELS == 15, "Params::offsets holds MAX_LEVELS offsets");

/// The cone-map pipeline with its layout and one descriptor set, rewritten for every build (builds
/// wait for their submissions, so the set is never in use when it is rewritten).
pub struct ConeMapPass {
    ctx: Arc<Context>,
    _layout: DescriptorLayout,
    _pool: DescriptorPool,
    set: DescriptorSet,
    pipeline: Pipeline,
}

impl ConeMapPass {
    /// Creates the pipeline, its layout and its set.
    pub fn new(ctx: &Arc<Context>) -> VkResult<ConeMapPass> {
        let key = "cone_map.comp";
        let spirv =
            shaders::spirv(key).ok_or_else(|| VkError::Invalid(format!("no shader {key}")))?;
        let storage = vk::DescriptorType::STORAGE_BUFFER;
        let layout = DescriptorLayout::new(
            ctx,
            &[(0, storage), (1, storage)],
            vk::ShaderStageFlags::COMPUTE,
            "cone map layout",
        )?;
        let push = std::mem::size_of::<Params>() as u32;
        let pipeline = compute_pipeline(
            ctx,
            spirv,
            &[layout.raw()],
            push,
            &SpecConstants::default(),
            "cone map",
        )?;
        let pool = DescriptorPool::new(ctx, 1, 2, "cone map sets")?;
        let set = pool.allocate(&layout, &[])?;
        Ok(ConeMapPass {
            ctx: ctx.clone(),
            _layout: layout,
            _pool: pool,
            set,
            pipeline,
        })
    }

    /// Builds the conservative cone map of `hf` under `address`, with the GPU time in ms (the
    /// pyramid and every search submission; the CPU's bilinear bound and the transfers are not in
    /// it).
    pub fn build(&self, hf: &Heightfield, address: Address) -> VkResult<(MapData, f64)> {
        let (w, h) = (hf.width(), hf.height());
        if w > MAX_SIDE || h > MAX_SIDE {
            return Err(VkError::Invalid(format!(
                "cone map of {w}x{h}: the GPU builder takes at most {MAX_SIDE} texels a side"
            )));
        }
        let bound = bilinear_box_bound(hf, address);
        let ctx = &self.ctx;
        let texels = u64::from(w) * u64::from(h);
        let staging = Buffer::with_data(
            ctx,
            bytemuck::cast_slice(bound.data()),
            vk::BufferUsageFlags::TRANSFER_SRC,
            "cone map heights",
        )?;
        let pyramid = Buffer::new(
            ctx,
            pyramid_floats(w, h) * 4,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST,
            MemoryLocation::GpuOnly,
            "cone map pyramid",
        )?;
        let out = Buffer::new(
            ctx,
            texels * 8,
            vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
            MemoryLocation::GpuOnly,
            "cone map",
        )?;
        let back = Readback::new(ctx, texels * 8, "cone map readback")?;
        self.set.rewrite(
            ctx,
            &[Bind::Storage(0, pyramid.raw()), Bind::Storage(1, out.raw())],
        );
        let rows = rows_per_submission(w, h);
        let chunks = h.div_ceil(rows);
        let timestamps = TimestampPool::new(ctx, 2 * (chunks + 1), "cone map timestamps")?;
        let params = Params {
            mode: MODE_REDUCE,
            width: w,
            height: h,
            repeat_address: u32::from(address == Address::Repeat),
            level: 0,
            row0: 0,
            aspect: (f64::from(w) / f64::from(h)) as f32,
            top: top_level(w, h),
            offsets: level_offsets(w, h),
        };
        let all = vk::PipelineStageFlags2::ALL_COMMANDS;
        ctx.one_shot(|rec| {
            timestamps.write(rec, all, 0)?;
            self.record_pyramid(rec, &staging, &pyramid, params)?;
            timestamps.write(rec, all, 1)?;
            Ok(())
        })?;
        for chunk in 0..chunks {
            let row0 = chunk * rows;
            let count = rows.min(h - row0);
            let mut rows_params = params;
            rows_params.row0 = row0;
            ctx.one_shot(|rec| {
                timestamps.write(rec, all, 2 * chunk + 2)?;
                self.record_rows(rec, rows_params, count)?;
                timestamps.write(rec, all, 2 * chunk + 3)?;
                Ok(())
            })?;
        }
        // Outside the timed submissions: the map reaches the host by a copy and the host barrier.
        let written = (
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        ctx.one_shot(|rec| back.record_copy_from_buffer(rec, &out, written))?;
        let ticks = timestamps.read_ticks(2 * (chunks + 1))?;
        let gpu_ms = ticks
            .chunks_exact(2)
            .map(|t| timestamps.ticks_to_ms(t[0], t[1]))
            .sum();
        let map = MapData {
            width: w,
            height: h,
            channels: 2,
            texels: bytemuck::pod_collect_to_vec(back.bytes()?),
        };
        Ok((map, gpu_ms))
    }

    /// Copies level 0 in and reduces it to 1x1, a barrier after every step.
    fn record_pyramid(
        &self,
        rec: &Recording,
        staging: &Buffer,
        pyramid: &Buffer,
        params: Params,
    ) -> VkResult<()> {
        rec.copy_buffer(staging, pyramid);
        let write_read =
            vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE;
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        memory_barrier(
            rec,
            (
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (compute, write_read),
        );
        self.pipeline.bind(rec, Some(self.set));
        for level in 1..=top_level(params.width, params.height) {
            let (lw, lh) = level_size(params.width, params.height, level);
            let mut level_params = params;
            level_params.level = level;
            self.pipeline.push(rec, bytemuck::bytes_of(&level_params))?;
            rec.dispatch([lw.div_ceil(GROUP), lh.div_ceil(GROUP), 1]);
            memory_barrier(rec, (compute, write_read), (compute, write_read));
        }
        Ok(())
    }

    /// Searches `count` rows from `params.row0`, then makes the results visible to the host.
    fn record_rows(&self, rec: &Recording, params: Params, count: u32) -> VkResult<()> {
        self.pipeline.bind(rec, Some(self.set));
        let mut params = params;
        params.mode = MODE_CONE;
        self.pipeline.push(rec, bytemuck::bytes_of(&params))?;
        rec.dispatch([params.width.div_ceil(GROUP), count.div_ceil(GROUP), 1]);
        memory_barrier(
            rec,
            (
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_STORAGE_WRITE,
            ),
            (vk::PipelineStageFlags2::HOST, vk::AccessFlags2::HOST_READ),
        );
        Ok(())
    }
}

/// Builds the conservative cone map of `hf` under `address` on the GPU: the same layout as the CPU
/// builder's `MapData` (ratio, bound height per texel), and the GPU time in ms.
pub fn build_cone_map_on_gpu(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    address: Address,
) -> VkResult<(MapData, f64)> {
    ConeMapPass::new(ctx)?.build(hf, address)
}

/// The level whose single node covers the map (`top_level` in the shader).
fn top_level(w: u32, h: u32) -> u32 {
    w.max(h).max(1).next_power_of_two().trailing_zeros()
}

/// Level `level` of the shader's pyramid: node `i` covers level-0 texels `[i, i + 1) * 2^level`.
fn level_size(w: u32, h: u32, level: u32) -> (u32, u32) {
    (w.div_ceil(1 << level), h.div_ceil(1 << level))
}

/// Where each level starts in the pyramid buffer, in floats (zero past the top).
fn level_offsets(w: u32, h: u32) -> [u32; MAX_LEVELS] {
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

fn pyramid_floats(w: u32, h: u32) -> u64 {
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
