//! The quadric map built on the GPU (`shaders/passes/quadric_map.comp`): a map in the layout of
//! `QuadricMap::build(hf, address)` (`[a, b, c, h]` per texel, `MapData` with 4 channels) that
//! keeps the CPU map's guarantee, an upper bound of the bilinear surface around every point of
//! each texel, for maps where the CPU's seconds to minutes would dominate a run.
//!
//! Not the CPU's numbers: the CPU prunes a concave hull of the radial bound through its pyramid,
//! the GPU covers the plane per texel with fixed rings of pyramid nodes (the shader's `RING`
//! nodes each side, per level) and fits the profile to their points directly, its cone to the near texels only.
//! Its points stand for their texels from a little nearer than the CPU's (see the shader's
//! header), so its profiles are a little higher: the tests bound how much (and the steps a tracer
//! takes through it), and check the upper bound itself point by point.
//!
//! Builds run through `map_search` (upload, pyramid, row-by-row submissions) like the cone map.

use std::sync::Arc;

use super::map_builder_pass::{GpuMap, MapBuilderPass};
use super::map_search::{level_offsets, top_level, SearchBuffers, SearchPipeline};
use crate::heightfield::{Address, Heightfield, MapData};
use crate::render::shader_interface::{QuadricMapParams, MODE_REDUCE};
use crate::vk::{Context, VkResult};

/// The quadric-map builder.
pub type QuadricMapPass = MapBuilderPass<QuadricMapSearch>;

/// The quadric map's search pipeline.
pub struct QuadricMapSearch {
    search: SearchPipeline,
}

impl GpuMap for QuadricMapSearch {
    const NAME: &'static str = "quadric map";
    /// A float per pyramid node; `[a, b, c, h]` per texel.
    const BUFFERS: SearchBuffers = SearchBuffers {
        node_bytes: 4,
        channels: 4,
    };

    fn pipelines(ctx: &Arc<Context>) -> VkResult<QuadricMapSearch> {
        let push = std::mem::size_of::<QuadricMapParams>() as u32;
        Ok(QuadricMapSearch {
            search: SearchPipeline::new(ctx, "quadric_map.comp", push, 2, Self::NAME)?,
        })
    }

    fn build(
        &self,
        ctx: &Arc<Context>,
        hf: &Heightfield,
        address: Address,
    ) -> VkResult<(MapData, f64)> {
        let (w, h) = (hf.width(), hf.height());
        let base = QuadricMapParams {
            mode: MODE_REDUCE,
            width: w,
            height: h,
            repeat_address: u32::from(address == Address::Repeat),
            level: 0,
            row0: 0,
            top: top_level(w, h),
            offsets: level_offsets(w, h),
        };
        let params = |mode, level, row0| QuadricMapParams {
            mode,
            level,
            row0,
            ..base
        };
        self.search
            .build(ctx, (hf.data(), w, h), 4, Self::NAME, &params)
    }
}

/// Builds the quadric map of `hf` under `address` on the GPU: the layout of the CPU builder's
/// `MapData` (`[a, b, c, h]` per texel), and the GPU time in ms.
pub fn build_quadric_map_on_gpu(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    address: Address,
) -> VkResult<(MapData, f64)> {
    QuadricMapPass::new(ctx)?.build(hf, address)
}
