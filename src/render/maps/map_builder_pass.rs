//! The one shape of the GPU builders of a method's map (cone, relaxed cone, quadric): a pass made
//! once per device, asked whether it takes a map's size, then building maps. What differs per map
//! (its shaders, push constants and dispatches) is a [`GpuMap`]; the rest is [`MapBuilderPass`].

use std::sync::Arc;

use super::map_search::SearchBuffers;
use crate::heightfield::{Address, Heightfield, MapData};
use crate::vk::{Context, VkResult};

/// The part of a GPU map builder that is the map's own.
pub trait GpuMap: Sized {
    /// Names the map in errors and in the names of its Vulkan objects.
    const NAME: &'static str;
    /// What one build holds in single storage buffers, which bounds the sizes the device takes.
    const BUFFERS: SearchBuffers;

    /// Creates the map's pipelines, their layout and set.
    fn pipelines(ctx: &Arc<Context>) -> VkResult<Self>;

    /// Builds the map of `hf` under `address`, a size [`GpuMap::BUFFERS`] takes: the map and the
    /// GPU time in ms (the pyramid and every search submission, not the transfers).
    fn build(
        &self,
        ctx: &Arc<Context>,
        hf: &Heightfield,
        address: Address,
    ) -> VkResult<(MapData, f64)>;
}

/// A GPU map builder: the pipelines of map `M` with one descriptor set, rewritten for every build
/// (builds wait for their submissions, so the set is never in use when it is rewritten).
pub struct MapBuilderPass<M: GpuMap> {
    ctx: Arc<Context>,
    map: M,
}

impl<M: GpuMap> MapBuilderPass<M> {
    /// Creates the pipelines, their layout and set.
    pub fn new(ctx: &Arc<Context>) -> VkResult<MapBuilderPass<M>> {
        Ok(MapBuilderPass {
            ctx: ctx.clone(),
            map: M::pipelines(ctx)?,
        })
    }

    /// Whether this device takes the build of a `w` x `h` map.
    pub fn fits(ctx: &Context, w: u32, h: u32) -> bool {
        M::BUFFERS.fit(ctx, w, h)
    }

    /// Builds the map of `hf` under `address`, with the GPU time in ms (the pyramid and every
    /// search submission; CPU preparation and the transfers are not in it). Fails for sizes
    /// [`MapBuilderPass::fits`] refuses.
    pub fn build(&self, hf: &Heightfield, address: Address) -> VkResult<(MapData, f64)> {
        M::BUFFERS.check(&self.ctx, M::NAME, hf.width(), hf.height())?;
        self.map.build(&self.ctx, hf, address)
    }
}
