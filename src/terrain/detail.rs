//! A layered material's blended field at the resolution the method traces: each layer resampled
//! onto one grid over the height uv, repeated `tiling` times, scaled by its depth, and weighed by
//! the splat map at every texel centre. A layer minified onto the grid is box-filtered first
//! (halved until at most one of its texels falls in a grid texel), so that its heights do not
//! alias into the blended surface.

use super::layers::{LayerError, LayerStack, SplatMap};
use crate::heightfield::reference::{surface_depth, SurfaceModel};
use crate::heightfield::{Address, Heightfield};

/// One layer's heights as a material tiles them.
#[derive(Debug, Clone, Copy)]
pub struct TiledLayer<'a> {
    /// The layer's heights, one tile.
    pub heights: &'a Heightfield,
    /// Repeats across the grid.
    pub tiling: f32,
    /// Scale of its heights, 0..=1.
    pub depth: f32,
}

/// The layers on a `size` x `size` grid over the height uv, weighed by `splat`.
pub fn tiled_stack(
    layers: &[TiledLayer],
    splat: &SplatMap,
    size: u32,
) -> Result<LayerStack, LayerError> {
    let resampled = layers.iter().map(|l| resample(l, size)).collect::<Vec<_>>();
    LayerStack::from_splat(resampled, splat)
}

/// `layer` on the grid: bilinear between its texel centres, wrapping.
fn resample(layer: &TiledLayer, size: u32) -> Heightfield {
    let mut source = layer.heights.clone();
    // Source texels per grid texel, along the longer side.
    let per_texel = |hf: &Heightfield| {
        f64::from(hf.width().max(hf.height())) * f64::from(layer.tiling) / f64::from(size)
    };
    while per_texel(&source) > 1.0 && source.width() > 1 && source.height() > 1 {
        source = halved(&source);
    }
    let n = f64::from(size);
    let tiling = f64::from(layer.tiling);
    let data = (0..size * size)
        .map(|t| {
            let (i, j) = (f64::from(t % size), f64::from(t / size));
            let (u, v) = ((i + 0.5) / n * tiling, (j + 0.5) / n * tiling);
            let h =
                1.0 - surface_depth(&source, u, v, 1.0, SurfaceModel::Bilinear, Address::Repeat);
            (h as f32).clamp(0.0, 1.0) * layer.depth
        })
        .collect();
    Heightfield::from_valid(size, size, data)
}

/// The 2x2 box mean of `hf` (odd last rows and columns fold into their neighbours' average).
fn halved(hf: &Heightfield) -> Heightfield {
    let (w, h) = ((hf.width() / 2).max(1), (hf.height() / 2).max(1));
    let data = (0..w * h)
        .map(|t| {
            let (i, j) = (t % w, t / w);
            let at = |di: u32, dj: u32| {
                hf.get(
                    (2 * i + di).min(hf.width() - 1),
                    (2 * j + dj).min(hf.height() - 1),
                )
            };
            (at(0, 0) + at(1, 0) + at(0, 1) + at(1, 1)) * 0.25
        })
        .collect();
    Heightfield::from_valid(w, h, data)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Generator;

    /// `field` alone, one tile at full depth, on a `size`^2 grid.
    fn one_layer_on(field: &Heightfield, size: u32) -> Heightfield {
        let splat = SplatMap::new(1, 1, vec![[1.0, 0.0, 0.0, 0.0]]).unwrap();
        let layer = TiledLayer {
            heights: field,
            tiling: 1.0,
            depth: 1.0,
        };
        tiled_stack(&[layer], &splat, size).unwrap().heights()[0].clone()
    }

    #[test]
    fn a_layer_at_its_own_size_and_one_tile_comes_back_unchanged() {
        let field = Generator::Fbm.generate(32, 32, 3);
        for (a, b) in one_layer_on(&field, 32).data().iter().zip(field.data()) {
            assert!((a - b).abs() < 1e-6, "{a} vs {b}");
        }
    }

    #[test]
    fn tiling_repeats_the_layer_and_depth_scales_it() {
        let field = Generator::Fbm.generate(16, 16, 4);
        let splat = SplatMap::new(1, 1, vec![[0.0, 1.0, 0.0, 0.0]]).unwrap();
        let layers = [
            TiledLayer {
                heights: &field,
                tiling: 2.0,
                depth: 0.5,
            },
            TiledLayer {
                heights: &field,
                tiling: 1.0,
                depth: 1.0,
            },
        ];
        let stack = tiled_stack(&layers, &splat, 32).unwrap();
        let tiled = &stack.heights()[0];
        for j in 0..16 {
            for i in 0..16 {
                let expected = field.get(i, j) * 0.5;
                assert!((tiled.get(i, j) - expected).abs() < 1e-6);
                assert!((tiled.get(i + 16, j + 16) - expected).abs() < 1e-6);
            }
        }
        assert_eq!(stack.weights()[1].get(5, 5), 1.0);
        assert_eq!(stack.weights()[0].get(5, 5), 0.0);
    }

    #[test]
    fn a_minified_layer_is_box_filtered_not_point_sampled() {
        // A checkerboard of single texels averages to 0.5 when squeezed 2:1.
        let data = (0..64 * 64)
            .map(|t| f32::from(u8::from((t % 64 + t / 64) % 2 == 0)))
            .collect();
        let field = Heightfield::from_valid(64, 64, data);
        for h in one_layer_on(&field, 32).data() {
            assert!((h - 0.5).abs() < 1e-6, "{h}");
        }
    }
}
