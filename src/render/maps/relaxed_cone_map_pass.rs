//! The relaxed cone map built on the GPU (`shaders/passes/relaxed_cone_*.comp`): a map in the
//! layout of `ConeMap::build(hf, ConeKind::Relaxed, address)` (`MapData`: ratio, bound height),
//! never wider than the CPU's.
//!
//! Steps: the bilinear bound (`bilinear_box_bound`, on the CPU, so the surface channel is the
//! CPU's bit for bit) and `1 - bound` uploaded into one storage buffer and reduced to a max and a
//! min pyramid; per texel, the reaches (the CPU's `reach`), reduced to a pyramid of minima; per
//! texel, the relaxed ratio (the CPU's `relaxed`). The searches are exact, their arithmetic f32.
//!
//! Not the CPU's numbers: the GPU cuts directions into quadrants, not the CPU's 16 sectors (the
//! shader's header says why). A quadrant's reach is at most each of its sectors', and every
//! rounding goes toward a narrower cone, so every ratio is at most the CPU's and the relaxed
//! property (a ray crosses the surface at most once inside the cone) holds as for the CPU's map.
//! On every test field each ratio is also within `RATIO_TOLERANCE` below the CPU's
//! (`tests/cone_map_gpu.rs`), and on fbm at 1024^2 too.
//!
//! Cost (lavapipe, two cores, fbm 1024^2, release): 4.0-4.4 s of GPU time against 16 s for the
//! CPU builder run right after (the README's map table): the reaches about 1.7 s, the ratios about
//! 3 s. The relaxed search opens about as many nodes per texel as the conservative one, but each
//! bound costs more, and its work per texel grows with the cones' span in texels (about 3x per
//! texel from 256^2 to 1024^2 on fbm).

use std::sync::Arc;

use ash::vk;

use super::map_builder_pass::{GpuMap, MapBuilderPass};
use super::map_search::{
    level_offsets, pyramid_floats, record_reductions, record_row_dispatch, row_chunks, top_level,
    warm_up, SearchBuffers, SearchPipeline, TimedSubmissions, COMPUTE_RW, COPIED, SHADER_WROTE,
};
use crate::heightfield::cone_map::{bilinear_box_bound, REACH_CAP_TEXELS, REACH_CAP_UV};
use crate::heightfield::{Address, Heightfield, MapData};
use crate::render::compute_pass::ComputePass;
use crate::render::shader_interface::{
    RelaxedConeParams, BINDING_SEARCH_MAP, BINDING_SEARCH_PYRAMID,
};
use crate::vk::{
    memory_barrier, Bind, Buffer, Context, MemoryLocation, Readback, Recording, VkResult,
};

/// Bytes per pyramid node: the maximum height, the maximum of 1 - height (f32 bits each) and
/// the least reach of each quadrant (u16).
const NODE_BYTES: u64 = 16;

/// The relaxed cone-map builder.
pub type RelaxedConeMapPass = MapBuilderPass<RelaxedConeMap>;

/// The relaxed-cone pipelines, one per kernel, sharing one set.
pub struct RelaxedConeMap {
    /// The set and the REDUCE kernel.
    search: SearchPipeline,
    reach: ComputePass,
    reach_reduce: ComputePass,
    relaxed: ComputePass,
}

impl GpuMap for RelaxedConeMap {
    const NAME: &'static str = "relaxed cone map";
    /// The node records ([`NODE_BYTES`] each: about 360 MB at 4096^2); ratio and box height per
    /// texel.
    const BUFFERS: SearchBuffers = SearchBuffers {
        node_bytes: NODE_BYTES,
        channels: 2,
    };

    fn pipelines(ctx: &Arc<Context>) -> VkResult<RelaxedConeMap> {
        let push = std::mem::size_of::<RelaxedConeParams>() as u32;
        let search = SearchPipeline::new(ctx, "relaxed_cone_reduce.comp", push, 2, Self::NAME)?;
        let kernel = |key, name| search.kernel(ctx, key, push, name);
        Ok(RelaxedConeMap {
            reach: kernel("relaxed_cone_reach.comp", "relaxed cone map reaches")?,
            reach_reduce: kernel(
                "relaxed_cone_reach_reduce.comp",
                "relaxed cone map reach pyramid",
            )?,
            relaxed: kernel("relaxed_cone_search.comp", "relaxed cone map search")?,
            search,
        })
    }

    /// The GPU time is every submission's; the CPU's bilinear bound is not in it.
    fn build(
        &self,
        ctx: &Arc<Context>,
        hf: &Heightfield,
        address: Address,
    ) -> VkResult<(MapData, f64)> {
        let (w, h) = (hf.width(), hf.height());
        let bound = bilinear_box_bound(hf, address);
        let nodes = pyramid_floats(w, h);
        let base = RelaxedConeParams {
            width: w,
            height: h,
            repeat_address: u32::from(address == Address::Repeat),
            level: 0,
            row0: 0,
            aspect: (f64::from(w) / f64::from(h)) as f32,
            top: top_level(w, h),
            reach_unit: (reach_cap_texels(w) / 65535.0) as f32,
            reach_cap: reach_cap_texels(w) as f32,
            offsets: level_offsets(w, h),
        };
        let params = |level, row0| RelaxedConeParams {
            level,
            row0,
            ..base
        };
        let buffers = Buffers::new(ctx, bound.data(), nodes)?;
        // SAFETY: every submission that bound the set was a one-shot (warm-ups and timed
        // submissions), and one-shots return only once their work has finished.
        unsafe {
            self.search.set.rewrite(&[
                Bind::Storage(BINDING_SEARCH_PYRAMID, &buffers.nodes),
                Bind::Storage(BINDING_SEARCH_MAP, &buffers.map),
            ])
        }?;
        let set = Some(&self.search.set);
        for pipeline in [&self.reach, &self.relaxed] {
            let past_end = params(0, h);
            warm_up(
                ctx,
                pipeline.pipeline(),
                &self.search.set,
                bytemuck::bytes_of(&past_end),
            )?;
        }
        let chunks = row_chunks(w, h);
        let submissions = 2 + 2 * chunks.len() as u32;
        let mut timed = TimedSubmissions::new(ctx, submissions, "relaxed cone map")?;
        timed.submit(ctx, |rec| {
            rec.copy_buffer(&buffers.staging, &buffers.nodes);
            memory_barrier(rec, COPIED, COMPUTE_RW);
            let reduce = self.search.pass.pipeline();
            reduce.bind(rec, set);
            record_reductions(rec, reduce, w, h, |level| params(level, 0))
        })?;
        let record_rows = |rec: &Recording, pipeline: &ComputePass, (row0, count): (u32, u32)| {
            let push = params(0, row0);
            record_row_dispatch(
                rec,
                pipeline.pipeline(),
                &self.search.set,
                bytemuck::bytes_of(&push),
                w,
                count,
            )
        };
        for &chunk in &chunks {
            timed.submit(ctx, |rec| record_rows(rec, &self.reach, chunk))?;
        }
        timed.submit(ctx, |rec| {
            let reach_reduce = self.reach_reduce.pipeline();
            reach_reduce.bind(rec, set);
            record_reductions(rec, reach_reduce, w, h, |level| params(level, 0))
        })?;
        for &chunk in &chunks {
            timed.submit(ctx, |rec| record_rows(rec, &self.relaxed, chunk))?;
        }
        let back = Readback::new(ctx, buffers.map.size(), "relaxed cone map readback")?;
        ctx.one_shot(|rec| back.record_copy_from_buffer(rec, &buffers.map, SHADER_WROTE))?;
        let gpu_ms = timed.total_ms()?;
        let map = MapData {
            width: w,
            height: h,
            channels: 2,
            texels: bytemuck::pod_collect_to_vec(back.bytes()?),
        };
        Ok((map, gpu_ms))
    }
}

/// The CPU's reach cap in u-texels (`Field::reach_cap`), whose 65535th part is a reach unit.
fn reach_cap_texels(w: u32) -> f64 {
    (REACH_CAP_UV * f64::from(w)).min(REACH_CAP_TEXELS)
}

/// The pass's buffers for one build.
struct Buffers {
    /// Level 0 of `nodes` (heights and 1 - heights, no reaches yet), zeros above.
    staging: Buffer,
    nodes: Buffer,
    map: Buffer,
}

impl Buffers {
    fn new(ctx: &Arc<Context>, bound: &[f32], nodes: u64) -> VkResult<Buffers> {
        let mut words = vec![0u32; 4 * nodes as usize];
        for (node, &h) in words.chunks_exact_mut(4).zip(bound) {
            node[0] = h.to_bits();
            // Rounded as the shader computes 1 - h for the texel searched, so h < hq gives
            // 1 - h >= 1 - hq.
            node[1] = (1.0 - h).to_bits();
        }
        let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
        let gpu = MemoryLocation::GpuOnly;
        Ok(Buffers {
            staging: Buffer::with_data(
                ctx,
                bytemuck::cast_slice(&words),
                vk::BufferUsageFlags::TRANSFER_SRC,
                "relaxed cone map levels",
            )?,
            nodes: Buffer::new(
                ctx,
                nodes * NODE_BYTES,
                storage | vk::BufferUsageFlags::TRANSFER_DST,
                gpu,
                "relaxed cone map pyramid",
            )?,
            map: Buffer::new(
                ctx,
                bound.len() as u64 * 2 * 4,
                storage | vk::BufferUsageFlags::TRANSFER_SRC,
                gpu,
                "relaxed cone map",
            )?,
        })
    }
}

/// Builds the relaxed cone map of `hf` under `address` on the GPU: the layout of the CPU
/// builder's `MapData` (ratio, bound height per texel), and the GPU time in ms.
pub fn build_relaxed_cone_map_on_gpu(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    address: Address,
) -> VkResult<(MapData, f64)> {
    RelaxedConeMapPass::new(ctx)?.build(hf, address)
}
