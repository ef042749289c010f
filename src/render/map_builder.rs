//! Building a method's map (binding 3) where it is cheapest: on the GPU where a GPU builder
//! exists and takes the map's size (the conservative cone map), else on the CPU with
//! `heightfield::build_method_map`, the reference the GPU builders are tested against.

use std::sync::Arc;

use super::cone_map_pass::{build_cone_map_on_gpu, MAX_SIDE as CONE_MAP_GPU_MAX_SIDE};
use crate::heightfield::{build_method_map, Address, Heightfield, MapData};
use crate::method::{MapKind, Method};
use crate::vk::{Context, VkResult};

/// Where [`build_method_map_with`] builds a map.
#[derive(Clone, Copy)]
pub enum MapBuilder<'a> {
    /// Always on the CPU.
    Cpu,
    /// On this device where a GPU builder exists and takes the map's size, else on the CPU.
    Gpu(&'a Arc<Context>),
}

/// A built map and how it was built.
#[derive(Debug, Clone)]
pub struct BuiltMethodMap {
    pub data: MapData,
    /// GPU ms when built on the GPU (as for the pyramid), CPU wall ms when on the CPU.
    pub ms: f64,
    /// "gpu" or "cpu".
    pub on: &'static str,
}

/// The method's map for `hf` built by `builder`, or `None` if it reads none.
pub fn build_method_map_with(
    method: Method,
    hf: &Heightfield,
    address: Address,
    builder: MapBuilder<'_>,
) -> VkResult<Option<BuiltMethodMap>> {
    let fits = hf.width().max(hf.height()) <= CONE_MAP_GPU_MAX_SIDE;
    if let (Some(MapKind::ConservativeCone), MapBuilder::Gpu(ctx), true) =
        (method.info().method_map(), builder, fits)
    {
        let (data, ms) = build_cone_map_on_gpu(ctx, hf, address)?;
        return Ok(Some(BuiltMethodMap {
            data,
            ms,
            on: "gpu",
        }));
    }
    Ok(
        build_method_map(method, hf, address).map(|(data, took)| BuiltMethodMap {
            data,
            ms: took.as_secs_f64() * 1e3,
            on: "cpu",
        }),
    )
}
