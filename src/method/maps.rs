//! Building the precomputed map a method reads (binding 3), by the method's row in the table:
//! on the CPU (the reference, and what the tests compare with), or with a device at hand on the
//! GPU where a GPU builder exists (the conservative cone map; the others stay on the CPU). The
//! max pyramid is not one of these: it is built on the GPU in the height image.

use std::sync::Arc;
use std::time::{Duration, Instant};

use super::{MapKind, Method};
use crate::heightfield::cone_map::{ConeKind, ConeMap};
use crate::heightfield::quadric_map::QuadricMap;
use crate::heightfield::reference::Address;
use crate::heightfield::Heightfield;
use crate::render::{build_cone_map_on_gpu, MapData, CONE_MAP_GPU_MAX_SIDE};
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

/// The method's map for `hf` built on the CPU and the time it took, or `None` if it reads none.
pub fn build_method_map(
    method: Method,
    hf: &Heightfield,
    address: Address,
) -> Option<(MapData, Duration)> {
    let kind = map_kind(method)?;
    let started = Instant::now();
    let data = build(kind, hf, address)?;
    Some((data, started.elapsed()))
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
        (map_kind(method), builder, fits)
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

fn map_kind(method: Method) -> Option<MapKind> {
    method
        .info()
        .needs
        .iter()
        .copied()
        .find(|k| *k != MapKind::MaxPyramid)
}

fn build(kind: MapKind, hf: &Heightfield, address: Address) -> Option<MapData> {
    match kind {
        MapKind::MaxPyramid => None,
        MapKind::ConservativeCone | MapKind::RelaxedCone => {
            let cone = if kind == MapKind::RelaxedCone {
                ConeKind::Relaxed
            } else {
                ConeKind::Conservative
            };
            // Per texel the cone ratio and the height of the box surface it is exact for.
            let map = ConeMap::build(hf, cone, address);
            Some(MapData {
                width: map.width,
                height: map.height,
                channels: 2,
                texels: map
                    .ratio
                    .iter()
                    .zip(&map.surface)
                    .flat_map(|(&c, &h)| [c, h])
                    .collect(),
            })
        }
        MapKind::Quadric => {
            let map = QuadricMap::build(hf, address);
            Some(MapData {
                width: map.width,
                height: map.height,
                channels: 4,
                texels: map.texels.iter().flatten().copied().collect(),
            })
        }
    }
}
