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
//! The upload, the pyramid and the row-by-row submissions are `map_search`'s, shared with the
//! quadric map.

use std::sync::Arc;

use super::map_builder_pass::{GpuMap, MapBuilderPass};
pub use super::map_search::MAX_SIDE;
use super::map_search::{level_offsets, top_level, SearchBuffers, SearchPipeline};
use crate::heightfield::cone_map::bilinear_box_bound;
use crate::heightfield::{Address, Heightfield, MapData};
use crate::render::shader_interface::{ConeMapParams, MODE_REDUCE};
use crate::vk::{Context, VkResult};

/// Relative amount by which a GPU ratio may fall short of the CPU's (never exceed it): the f32
/// search's error plus the step down that makes it conservative (see `cone_map.comp`).
pub const RATIO_TOLERANCE: f32 = 1.0 / 32768.0;

/// The conservative cone-map builder.
pub type ConeMapPass = MapBuilderPass<ConservativeConeMap>;

/// The conservative cone map's search pipeline.
pub struct ConservativeConeMap {
    search: SearchPipeline,
}

impl GpuMap for ConservativeConeMap {
    const NAME: &'static str = "cone map";
    /// A float per pyramid node; ratio and box height per texel.
    const BUFFERS: SearchBuffers = SearchBuffers {
        node_bytes: 4,
        channels: 2,
    };

    fn pipelines(ctx: &Arc<Context>) -> VkResult<ConservativeConeMap> {
        let push = std::mem::size_of::<ConeMapParams>() as u32;
        Ok(ConservativeConeMap {
            search: SearchPipeline::new(ctx, "cone_map.comp", push, 2, Self::NAME)?,
        })
    }

    /// The CPU's bilinear bound is not in the GPU time.
    fn build(
        &self,
        ctx: &Arc<Context>,
        hf: &Heightfield,
        address: Address,
    ) -> VkResult<(MapData, f64)> {
        let (w, h) = (hf.width(), hf.height());
        let bound = bilinear_box_bound(hf, address);
        let base = ConeMapParams {
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
        let params = |mode, level, row0| ConeMapParams {
            mode,
            level,
            row0,
            ..base
        };
        self.search
            .build(ctx, (bound.data(), w, h), 2, Self::NAME, &params)
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
