//! The one image every shadow map of a frame lives in: each view (cascade, spot map, cube face)
//! a square tile of it, so the surface pass binds a single texture whatever the lights, and the
//! shadow pass renders every view in one rendering with a viewport per tile. The casters write
//! their depth twice: into a depth attachment, for the depth test, and into an R32F colour
//! image, which is what the surface pass samples. (On lavapipe, binding a depth image to the
//! surface pass slows every surface fragment by half, lookup or not: measured at 960x540, 138
//! against 92 GPU ms with the lookups skipped; a colour copy costs nothing of the kind.) A scene
//! without shadow maps creates nothing: its draws bind a stand-in the shaders never read (no
//! light has a map), and the pass records nothing.

use std::sync::Arc;

use ash::vk;

use crate::render::kit::depth_as_colour::{DepthAsColour, DEPTH_COLOUR_FORMAT};
use crate::render::shader_interface::BINDING_SHADOW_ATLAS;
use crate::vk::{Bind, Context, ImageView, Recording, Sampler, VkError, VkResult};

/// Format of the sampled depths.
pub const SHADOW_FORMAT: vk::Format = DEPTH_COLOUR_FORMAT;
/// Where one view lives in the atlas, in texels.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Tile {
    /// Column of its left edge.
    pub x: u32,
    /// Row of its top edge.
    pub y: u32,
    /// Texels per side.
    pub size: u32,
}

/// The atlas's images.
struct AtlasImages {
    /// The depths the surface pass samples, and their depth test.
    target: DepthAsColour,
    sampler: Sampler,
}

/// The atlas and the sampler the surface pass reads it with (none without shadow maps).
pub struct ShadowAtlas {
    images: Option<AtlasImages>,
    tiles: Vec<Tile>,
}

/// Tiles for views of `sizes` texels, in a grid of cells as large as the largest.
pub fn layout_tiles(sizes: &[u32]) -> (Vec<Tile>, u32, u32) {
    let cell = sizes.iter().copied().max().unwrap_or(1);
    let n = sizes.len().max(1) as u32;
    let cols = (n as f32).sqrt().ceil() as u32;
    let rows = n.div_ceil(cols);
    let tiles = sizes
        .iter()
        .enumerate()
        .map(|(k, &size)| Tile {
            x: (k as u32 % cols) * cell,
            y: (k as u32 / cols) * cell,
            size,
        })
        .collect();
    (tiles, cols * cell, rows * cell)
}

impl ShadowAtlas {
    /// An atlas holding views of `sizes` texels per side; nothing when `sizes` is empty.
    pub fn new(ctx: &Arc<Context>, sizes: &[u32]) -> VkResult<ShadowAtlas> {
        if sizes.is_empty() {
            return Ok(ShadowAtlas {
                images: None,
                tiles: Vec::new(),
            });
        }
        let (tiles, width, height) = layout_tiles(sizes);
        let limit = ctx.info().max_image_dimension_2d;
        if width > limit || height > limit {
            return Err(VkError::Invalid(format!(
                "the shadow maps' {} view(s) need a {width}x{height} atlas, above this device's {limit} per side; lower --shadow-map-size or --shadow-cascades",
                sizes.len()
            )));
        }
        let target = DepthAsColour::new(ctx, width, height, "shadow atlas")?;
        let sampler = Sampler::new(
            ctx,
            vk::Filter::NEAREST,
            vk::SamplerAddressMode::CLAMP_TO_EDGE,
            "shadow atlas sampler",
        )?;
        Ok(ShadowAtlas {
            images: Some(AtlasImages { target, sampler }),
            tiles,
        })
    }

    /// The descriptor of the atlas for set 0, or of `stand_in` (any sampled 2D image, never read)
    /// when there are no maps.
    pub fn bind<'a>(&'a self, stand_in: &'a (ImageView, Sampler)) -> Bind<'a> {
        match &self.images {
            Some(a) => Bind::Texture(BINDING_SHADOW_ATLAS, a.target.depths.view(), &a.sampler),
            None => Bind::Texture(BINDING_SHADOW_ATLAS, &stand_in.0, &stand_in.1),
        }
    }

    /// Where each view lives.
    pub fn tiles(&self) -> &[Tile] {
        &self.tiles
    }

    /// Begins rendering into the whole atlas, cleared to the far plane. The previous frame (same
    /// queue) may still sample it, so its fragment shaders finish first.
    pub fn begin(&self, rec: &Recording) {
        if let Some(a) = &self.images {
            a.target.begin(rec);
        }
    }

    /// Ends the rendering and hands the depths to the surface pass's fragment shaders.
    pub fn end(&self, rec: &Recording) {
        if let Some(a) = &self.images {
            a.target.end(rec);
        }
    }

    /// Whether the atlas holds maps to render.
    pub fn is_rendered(&self) -> bool {
        self.images.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tiles_do_not_overlap_and_fit_the_atlas() {
        let sizes = [1024, 1024, 512, 256, 256, 256, 256, 256];
        let (tiles, w, h) = layout_tiles(&sizes);
        for (k, a) in tiles.iter().enumerate() {
            assert!(a.x + a.size <= w && a.y + a.size <= h);
            for b in &tiles[k + 1..] {
                let apart = a.x + a.size <= b.x
                    || b.x + b.size <= a.x
                    || a.y + a.size <= b.y
                    || b.y + b.size <= a.y;
                assert!(apart, "{a:?} {b:?}");
            }
        }
        assert_eq!((w, h), (3 * 1024, 3 * 1024));
    }
}
