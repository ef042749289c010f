//! Building a method's map (binding 3) where it is cheapest: on the GPU where a GPU builder
//! exists and takes the map's size (the conservative and relaxed cone maps, the quadric map),
//! else on the CPU with
//! `heightfield::build_method_map`, the reference the GPU builders are tested against.

use std::sync::Arc;

use super::cone_map_pass::{build_cone_map_on_gpu, ConeMapPass};
use super::quadric_map_pass::{build_quadric_map_on_gpu, QuadricMapPass};
use super::relaxed_cone_map_pass::{build_relaxed_cone_map_on_gpu, RelaxedConeMapPass};
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
    /// The map's texels, one per height texel.
    pub data: MapData,
    /// GPU ms when built on the GPU (as for the pyramid), CPU wall ms when on the CPU.
    pub ms: f64,
    /// "gpu" or "cpu".
    pub on: &'static str,
}

/// Whether `ctx` has a GPU builder for maps of `kind` that takes a `w` x `h` map (its buffers
/// within the device's storage buffer range).
pub fn gpu_builds(ctx: &Context, kind: MapKind, w: u32, h: u32) -> bool {
    match kind {
        MapKind::ConservativeCone => ConeMapPass::fits(ctx, w, h),
        MapKind::RelaxedCone => RelaxedConeMapPass::fits(ctx, w, h),
        MapKind::Quadric => QuadricMapPass::fits(ctx, w, h),
        MapKind::MaxPyramid => false,
    }
}

/// The method's map for `hf` built by `builder`, or `None` if it reads none.
pub fn build_method_map_with(
    method: Method,
    hf: &Heightfield,
    address: Address,
    builder: MapBuilder<'_>,
) -> VkResult<Option<BuiltMethodMap>> {
    let gpu = match (method.info().method_map(), builder) {
        (Some(kind), MapBuilder::Gpu(ctx)) if gpu_builds(ctx, kind, hf.width(), hf.height()) => {
            Some((kind, ctx))
        }
        _ => None,
    };
    if let Some((kind, ctx)) = gpu {
        let gpu = match kind {
            MapKind::ConservativeCone => Some(build_cone_map_on_gpu(ctx, hf, address)?),
            MapKind::Quadric => Some(build_quadric_map_on_gpu(ctx, hf, address)?),
            MapKind::RelaxedCone => Some(build_relaxed_cone_map_on_gpu(ctx, hf, address)?),
            MapKind::MaxPyramid => None,
        };
        if let Some((data, ms)) = gpu {
            return Ok(Some(BuiltMethodMap {
                data,
                ms,
                on: "gpu",
            }));
        }
    }
    Ok(
        build_method_map(method, hf, address).map(|(data, took)| BuiltMethodMap {
            data,
            ms: took.as_secs_f64() * 1e3,
            on: "cpu",
        }),
    )
}
