//! Painting a layered material's weights while it is drawn: `paint` strokes move its splat map
//! (kept on the CPU, the one source of both the shading's splat image and the blend's weights),
//! and only what they changed is rebuilt on the GPU — the stack weights that read a painted splat
//! texel are weighed again (`SplatMap::stack_weights`, as the first build weighed them) and
//! re-staged, then [`BlendedPyramid::record_weights`] rebuilds the pyramid nodes and blended
//! texels above them. The renderer copies those regions into the height map it draws and
//! rebuilds the AO near them (`Renderer::paint_layers`).
//!
//! The strokes run on the CPU: a stroke covers a few hundred splat texels, fewer than one GPU
//! dispatch's setup costs, and the splat map must be on the CPU anyway to weigh the stack again
//! exactly as the full build does, which keeps a partial rebuild equal to a full one bit for bit.

use ash::vk;
use serde::Serialize;

use super::blended_pyramid_pass::BlendedPyramid;
use crate::render::maps::pyramid_pass::Region;
use crate::terrain::{SplatMap, Stroke, StrokeError, StrokeTarget, TexelRect};
use crate::vk::{
    record_copy_regions, transition_images, Image, ImageTransition, Recording, StagedRegions,
    VkResult,
};

/// A layered material's blend inputs on the GPU and its splat map, ready to be painted.
pub struct LayerPainter {
    pyramid: BlendedPyramid,
    splat: SplatMap,
    /// The stack's side (the blended field's resolution).
    size: u32,
    /// Per splat texel, whether a stroke painted it: weights set from elsewhere (rules over an
    /// edited elevation) leave those, so a hand's work is not undone by the ground moving.
    by_hand: Vec<bool>,
}

/// What one list of paint strokes rebuilt, for `--explain` and the bench.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct PaintReport {
    /// Strokes applied.
    pub strokes: usize,
    /// Splat-map texels in the strokes' squares (counted once per stroke).
    pub splat_texels: u64,
    /// Per level of the blended pyramid (0: the blended field), the texels blended again.
    pub blended_texels: Vec<u64>,
    /// AO texels computed again (0 without an AO map or before the first frame built it).
    pub ao_texels: u64,
    /// GPU ms of the copies, pyramids, blend and AO.
    pub gpu_ms: f64,
}

impl PaintReport {
    /// Adds `other`'s counts and time to these.
    pub fn add(&mut self, other: &PaintReport) {
        self.strokes += other.strokes;
        self.splat_texels += other.splat_texels;
        if self.blended_texels.len() < other.blended_texels.len() {
            self.blended_texels.resize(other.blended_texels.len(), 0);
        }
        for (a, b) in self.blended_texels.iter_mut().zip(&other.blended_texels) {
            *a += b;
        }
        self.ao_texels += other.ao_texels;
        self.gpu_ms += other.gpu_ms;
    }
}

/// A painted list, staged for the GPU.
pub struct StagedPaint {
    /// The splat texels each stroke may have changed.
    pub splat_rects: Vec<TexelRect>,
    /// The stack texels whose weights read them.
    pub stack_rects: Vec<TexelRect>,
    weights: [StagedRegions; 2],
}

impl LayerPainter {
    /// `pyramid` built from a stack of side `size` weighed by `splat`.
    pub fn new(pyramid: BlendedPyramid, splat: SplatMap, size: u32) -> LayerPainter {
        let (w, h) = splat.size();
        LayerPainter {
            pyramid,
            splat,
            size,
            by_hand: vec![false; w as usize * h as usize],
        }
    }

    /// The blended pyramid on the GPU that painting re-blends.
    pub fn pyramid(&self) -> &BlendedPyramid {
        &self.pyramid
    }

    /// The CPU copy of the splat map: the weights as painted so far, quantized as the GPU holds
    /// them.
    pub fn splat(&self) -> &SplatMap {
        &self.splat
    }

    /// Checks `strokes` (centres and radii in splat texels) before any is applied: each a
    /// `paint` stroke on one of the material's layers that meets the splat map.
    pub fn check(&self, strokes: &[Stroke]) -> Result<(), StrokeError> {
        let (w, h) = self.splat.size();
        let layers = self.pyramid.layers();
        for (index, s) in strokes.iter().enumerate() {
            s.check(index, w, h)?;
            if !s.paints() {
                return Err(StrokeTarget::ShapeOnWeights {
                    index,
                    kind: s.kind,
                }
                .into());
            }
            if s.layer as usize >= layers {
                return Err(StrokeTarget::Layer {
                    index,
                    layer: s.layer,
                    layers,
                }
                .into());
            }
        }
        Ok(())
    }

    /// Applies `strokes` (checked first; a bad one applies none) to the splat map and stages the
    /// stack weights they changed.
    pub fn paint(&mut self, strokes: &[Stroke]) -> Result<StagedPaint, PaintError> {
        self.check(strokes)?;
        let splat_rects: Vec<TexelRect> = strokes
            .iter()
            .filter_map(|s| {
                let rect = self.splat.paint(s)?;
                // The shading's splat image holds 16 bits: the weights blended must be those.
                self.splat.quantize_unorm16(&rect);
                let width = self.splat.size().0 as usize;
                for j in rect.y0..=rect.y1 {
                    for i in rect.x0..=rect.x1 {
                        if s.covers(i, j) {
                            self.by_hand[j as usize * width + i as usize] = true;
                        }
                    }
                }
                Some(rect)
            })
            .collect();
        let stack_rects = splat_rects
            .iter()
            .map(|r| self.splat.stack_rect(r, self.size, self.size))
            .collect();
        Ok(self.stage(splat_rects, stack_rects)?)
    }

    /// Sets the weights of splat texels `rect` (clipped to the map) not painted by hand to
    /// `weights(i, j)` (finite, at least 0) and stages what that changed; `None` when nothing did.
    pub fn reweigh(
        &mut self,
        rect: TexelRect,
        weights: impl Fn(u32, u32) -> [f32; 4],
    ) -> VkResult<Option<StagedPaint>> {
        let (w, h) = self.splat.size();
        if rect.x0 >= w || rect.y0 >= h {
            return Ok(None);
        }
        let rect = TexelRect {
            x1: rect.x1.min(w - 1),
            y1: rect.y1.min(h - 1),
            ..rect
        };
        let mut changed = false;
        for j in rect.y0..=rect.y1 {
            for i in rect.x0..=rect.x1 {
                if self.by_hand[j as usize * w as usize + i as usize] {
                    continue;
                }
                let before = self.splat.texel(i, j);
                self.splat.set_texel(i, j, weights(i, j));
                let texel = TexelRect {
                    x0: i,
                    y0: j,
                    x1: i,
                    y1: j,
                };
                self.splat.quantize_unorm16(&texel);
                changed |= self.splat.texel(i, j) != before;
            }
        }
        if !changed {
            return Ok(None);
        }
        let stack = self.splat.stack_rect(&rect, self.size, self.size);
        self.stage(vec![rect], vec![stack]).map(Some)
    }

    /// Stages every stack weight, as a full rebuild does.
    pub fn stage_all(&self) -> VkResult<StagedPaint> {
        let (w, h) = self.splat.size();
        let whole = |w: u32, h: u32| TexelRect {
            x0: 0,
            y0: 0,
            x1: w - 1,
            y1: h - 1,
        };
        self.stage(vec![whole(w, h)], vec![whole(self.size, self.size)])
    }

    fn stage(
        &self,
        splat_rects: Vec<TexelRect>,
        stack_rects: Vec<TexelRect>,
    ) -> VkResult<StagedPaint> {
        let layers = self.pyramid.layers();
        let texels: Vec<Vec<[f32; 4]>> = stack_rects
            .iter()
            .map(|r| {
                let mut out = Vec::with_capacity(r.texels() as usize);
                for j in r.y0..=r.y1 {
                    for i in r.x0..=r.x1 {
                        let w = self.splat.stack_weights(i, j, self.size, self.size);
                        // Channels past the layers weigh nothing, as in the first build.
                        out.push(std::array::from_fn(|k| if k < layers { w[k] } else { 0.0 }));
                    }
                }
                out
            })
            .collect();
        let weights = self.pyramid.stage_weights(&stack_rects, &texels)?;
        Ok(StagedPaint {
            splat_rects,
            stack_rects,
            weights,
        })
    }

    /// Records the rebuild of what `staged` changed; the blended regions per level, level 0
    /// first (all in [`BlendedPyramid::blended`], in `SHADER_READ_ONLY_OPTIMAL`).
    pub fn record(&self, rec: &Recording, staged: &StagedPaint) -> VkResult<Vec<Vec<Region>>> {
        self.pyramid
            .record_weights(rec, &staged.weights, &staged.stack_rects)
    }

    /// Splat texels `rect` as the shading's 16-bit splat image holds them, as bytes.
    pub fn splat_bytes(&self, rect: &TexelRect) -> Vec<u8> {
        bytemuck::cast_slice(&self.splat.unorm16_rect(rect)).to_vec()
    }
}

/// Why a paint list was not applied.
#[derive(Debug, thiserror::Error)]
pub enum PaintError {
    /// A stroke fails [`LayerPainter::check`] (a shape stroke, an unknown layer, outside the
    /// splat map, ...); none of the list was applied.
    #[error(transparent)]
    Stroke(#[from] StrokeError),
    /// Staging the changed weights for the GPU failed; the CPU splat map already holds the
    /// strokes.
    #[error(transparent)]
    Vulkan(#[from] crate::vk::VkError),
}

/// Records the copies of `regions` (per level, from [`LayerPainter::record`]) from the painter's
/// blended pyramid into `target`, the height map drawn (its levels past the target's are not
/// drawn and not copied), and of the staged splat texels into the shading's `splat` image. Every
/// image goes from and back to `SHADER_READ_ONLY_OPTIMAL`, readable by fragment and compute
/// shaders (the AO rebuilt next reads `target`).
pub fn record_paint_copies(
    rec: &Recording,
    painter: &LayerPainter,
    regions: &[Vec<Region>],
    target: &Image,
    splat: Option<(&Image, &StagedRegions)>,
) -> VkResult<()> {
    let blended = painter.pyramid().blended();
    let copies: Vec<(u32, [u32; 4])> = regions
        .iter()
        .enumerate()
        .take(target.desc().mip_levels as usize)
        .flat_map(|(level, rs)| rs.iter().map(move |r| (level as u32, *r)))
        .collect();
    let (src, dst) = (
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        vk::ImageLayout::TRANSFER_DST_OPTIMAL,
    );
    let mut images = vec![(blended, src), (target, dst)];
    images.extend(splat.map(|(image, _)| (image, dst)));
    transition_images(rec, &paint_transitions(&images, true));
    record_copy_regions(rec, (blended, src), (target, dst), &copies)?;
    if let Some((image, staged)) = splat {
        staged.record(rec, image, dst)?;
    }
    transition_images(rec, &paint_transitions(&images, false));
    Ok(())
}

/// Whole-image transitions between `SHADER_READ_ONLY_OPTIMAL` and each image's transfer layout,
/// into it (`to_transfer`) or back.
fn paint_transitions<'a>(
    images: &[(&'a Image, vk::ImageLayout)],
    to_transfer: bool,
) -> Vec<ImageTransition<'a>> {
    let shaders = (
        vk::PipelineStageFlags2::FRAGMENT_SHADER | vk::PipelineStageFlags2::COMPUTE_SHADER,
        vk::AccessFlags2::SHADER_SAMPLED_READ,
    );
    let transfer = (
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ | vk::AccessFlags2::TRANSFER_WRITE,
    );
    images
        .iter()
        .map(|&(image, layout)| {
            let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
            let (old, new, src, dst) = if to_transfer {
                (read, layout, shaders, transfer)
            } else {
                (layout, read, transfer, shaders)
            };
            ImageTransition {
                image,
                aspect: vk::ImageAspectFlags::COLOR,
                base_mip: 0,
                mip_count: image.desc().mip_levels,
                old,
                new,
                src,
                dst,
            }
        })
        .collect()
}
