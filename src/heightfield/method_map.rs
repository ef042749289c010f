//! A method's precomputed map (binding 3) on the CPU: the cone or quadric map of a height field,
//! flattened to the float texels the GPU reads. Which map a method reads is its row in the method
//! table; this builds it. The max pyramid is not one of these: it lives in the height image.

use std::time::{Duration, Instant};

use super::cone_map::{ConeKind, ConeMap};
use super::quadric_map::QuadricMap;
use super::reference::Address;
use super::Heightfield;
use crate::method::{MapKind, Method};

/// A map on the CPU: `channels` (1, 2 or 4) floats per texel, rows of `width` texels.
#[derive(Debug, Clone, PartialEq)]
pub struct MapData {
    /// Texels along u (the height field's width).
    pub width: u32,
    /// Texels along v (the height field's height).
    pub height: u32,
    /// Floats per texel: 2 for a cone map (ratio, then the box-surface height of [`ConeMap::surface`]), 4 for a
    /// quadric map (`[a, b, c, h]`, see [`QuadricMap`]).
    pub channels: u32,
    /// `width * height * channels` floats, row-major, the channels of one texel adjacent.
    pub texels: Vec<f32>,
}

impl MapData {
    /// The map of `kind` for `hf`, or `None` for the pyramid (not a method map).
    pub fn build(kind: MapKind, hf: &Heightfield, address: Address) -> Option<MapData> {
        match kind {
            MapKind::MaxPyramid => None,
            MapKind::ConservativeCone => Some(Self::cone(hf, ConeKind::Conservative, address)),
            MapKind::RelaxedCone => Some(Self::cone(hf, ConeKind::Relaxed, address)),
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

    /// Per texel the cone ratio and the height of the box surface it is exact for.
    fn cone(hf: &Heightfield, kind: ConeKind, address: Address) -> MapData {
        let map = ConeMap::build(hf, kind, address);
        MapData {
            width: map.width,
            height: map.height,
            channels: 2,
            texels: map
                .ratio
                .iter()
                .zip(&map.surface)
                .flat_map(|(&c, &h)| [c, h])
                .collect(),
        }
    }
}

/// The method's map for `hf` built on the CPU and the time it took, or `None` if it reads none.
pub fn build_method_map(
    method: Method,
    hf: &Heightfield,
    address: Address,
) -> Option<(MapData, Duration)> {
    let kind = method.info().method_map()?;
    let started = Instant::now();
    let data = MapData::build(kind, hf, address)?;
    Some((data, started.elapsed()))
}
