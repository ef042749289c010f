//! A layered material's heights on the GPU: its layers decoded from the scene's images, tiled onto
//! the grid its blended field is traced at (`terrain::tiled_stack`), weighed by its splat map,
//! and blended with the conservative pyramid built on the GPU (`blended_pyramid_pass`). What comes
//! back is a height field with its pyramid like any other, so every method, shadow mode and AO
//! map reads the blended surface unchanged.

use std::sync::Arc;
use std::time::Instant;

use super::blended_pyramid_pass::{time_on_gpu, BlendedPyramid};
use super::layer_paint::LayerPainter;
use crate::heightfield::{Address, Heightfield, LoadOptions, MaxPyramid, PyramidLevel};
use crate::render::kit::gpu_heightfield::HeightFormat;
use crate::scene::{Layers, LayersError, Scene, SceneImage};
use crate::terrain::{tiled_stack, SplatMap, TiledLayer};
use crate::vk::Context;

use crate::render::kit::render_error::RenderError;

/// A blended field and how long it took.
pub struct BlendedHeights {
    pub pyramid: MaxPyramid,
    /// CPU ms of decoding, tiling and weighing the layers.
    pub stack_ms: f64,
    /// GPU ms of the layers' and weights' pyramids and the blend.
    pub gpu_ms: f64,
    /// The blend's inputs kept for painting, when asked for.
    pub painter: Option<LayerPainter>,
}

/// The splat map of `image`: its RGBA channels as weights (8 or 16 bits, as stored).
pub fn splat_of(image: &SceneImage) -> Result<SplatMap, RenderError> {
    let rgba = image.pixels.to_rgba16();
    let texels = rgba
        .pixels()
        .map(|p| p.0.map(|c| f32::from(c) / f32::from(u16::MAX)))
        .collect();
    SplatMap::new(rgba.width(), rgba.height(), texels)
        .map_err(|e| RenderError::Layers(format!("splat map {}: {e}", image.name)))
}

/// The blended heights of `layers` (checked by the plan) in `format`; with the painter of its
/// weights when `paintable`.
pub fn blended_heights(
    ctx: &Arc<Context>,
    scene: &Scene,
    layers: &Layers,
    format: HeightFormat,
    paintable: bool,
) -> Result<BlendedHeights, RenderError> {
    let started = Instant::now();
    let fields = layers
        .layers
        .iter()
        .map(|l| {
            let image = &scene.images[l.height.image];
            let opts = LoadOptions {
                channel: l.height_channel,
                invert: false,
            };
            let source = format!("layer {:?} height ({})", l.name, image.name);
            Heightfield::from_dynamic_image(&image.pixels, &opts, &source)
        })
        .collect::<Result<Vec<_>, _>>()?;
    let tiled: Vec<TiledLayer> = fields
        .iter()
        .zip(&layers.layers)
        .map(|(heights, l)| TiledLayer {
            heights,
            tiling: l.tiling,
            depth: l.depth,
        })
        .collect();
    let splat = layers
        .splat()
        .ok_or_else(|| RenderError::Layers(LayersError::Unbaked.to_string()))?;
    let splat = splat_of(&scene.images[splat.image])?;
    let stack = tiled_stack(&tiled, &splat, layers.resolution)
        .map_err(|e| RenderError::Layers(e.to_string()))?;
    let stack_ms = started.elapsed().as_secs_f64() * 1e3;
    let built = BlendedPyramid::new(ctx, &stack, layers.mode, format, Address::Clamp)?;
    let gpu_ms = time_on_gpu(ctx, |rec| built.record_build(rec))?;
    let levels = built
        .read_levels()?
        .into_iter()
        .enumerate()
        .map(|(k, data)| PyramidLevel {
            width: (layers.resolution >> k).max(1),
            height: (layers.resolution >> k).max(1),
            data,
        })
        .collect();
    let painter = paintable.then(|| LayerPainter::new(built, splat, layers.resolution));
    Ok(BlendedHeights {
        pyramid: MaxPyramid::from_levels(levels),
        stack_ms,
        gpu_ms,
        painter,
    })
}
