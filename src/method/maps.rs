//! Building the precomputed map a method reads (binding 3) on the CPU, by the method's row in
//! the table. The max pyramid is not one of these: it is built on the GPU in the height image.

use std::time::{Duration, Instant};

use super::{MapKind, Method};
use crate::heightfield::cone_map::{ConeKind, ConeMap};
use crate::heightfield::quadric_map::QuadricMap;
use crate::heightfield::reference::Address;
use crate::heightfield::Heightfield;
use crate::render::MapData;

/// The method's map for `hf` and the time it took to build, or `None` if it reads none.
pub fn build_method_map(
    method: Method,
    hf: &Heightfield,
    address: Address,
) -> Option<(MapData, Duration)> {
    let kind = method
        .info()
        .needs
        .iter()
        .copied()
        .find(|k| *k != MapKind::MaxPyramid)?;
    let started = Instant::now();
    let data = build(kind, hf, address)?;
    Some((data, started.elapsed()))
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
