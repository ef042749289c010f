//! The bench's weight-painting section, beside the terrain-edit one: what a `paint` stroke on a
//! layered material costs (the splat map painted and the stack weights weighed again on the CPU,
//! then the weights' and slack's pyramid nodes and the blended texels of every level above them
//! rebuilt on the GPU, `render::LayerPainter`) against re-staging every weight and rebuilding
//! every node and blended level in place. Each size gets four fbm layers of that side weighed by
//! a splat map an eighth of it, in the sweep's height format; medians of strokes at spread-out
//! centres and of a few full rebuilds.

use std::fmt::Write as _;
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::median::median;
use crate::heightfield::{mip_level_count, Address, Generator};
use crate::render::{time_on_gpu, BlendedPyramid, HeightFormat, LayerPainter, PaintError};
use crate::terrain::{BlendMode, BrushKind, LayerStack, SplatMap, Stroke, MAX_LAYERS};
use crate::vk::{Context, VkError, VkResult};

/// Strokes timed per size.
const STROKES: usize = 8;
/// Full rebuilds timed per size.
const FULL_REBUILDS: usize = 3;
/// The splat map's side is the stack's over this (a terrain's splat is much coarser than its field).
const SPLAT_DIVISOR: u32 = 8;
/// The blend timed: the terrain's default.
const MODE: BlendMode = BlendMode::Height;

/// One size's painting costs.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct PaintCost {
    /// The stack's (blended field's) side.
    pub size: u32,
    /// The splat map's side.
    pub splat_size: u32,
    /// Layers in the stack.
    pub layers: usize,
    /// The blend mode's id.
    pub mode: String,
    /// Texel format of the blended height image.
    pub format: HeightFormat,
    /// The stroke's radius in stack texels, and in splat texels (what the stroke is given).
    pub radius: f32,
    /// The stroke's radius in splat texels.
    pub splat_radius: f32,
    /// Median GPU ms of rebuilding every weight and slack node and every blended level.
    pub full_ms: f64,
    /// Median CPU ms of weighing and staging every stack texel for it.
    pub full_cpu_ms: f64,
    /// Median GPU ms of one stroke's partial rebuild.
    pub stroke_ms: f64,
    /// Median CPU ms of one stroke's painting and staging (`LayerPainter::paint`).
    pub paint_cpu_ms: f64,
    /// Blended texels (all levels) a stroke rebuilt, median.
    pub stroke_texels: u64,
    /// Blended texels of all levels.
    pub all_texels: u64,
}

/// Measures `paint` strokes of `radius` stack texels on stacks of each of `sizes`.
pub fn run_paint_section(
    ctx: &Arc<Context>,
    sizes: &[u32],
    radius: f32,
    format: HeightFormat,
) -> VkResult<Vec<PaintCost>> {
    sizes
        .iter()
        .map(|&size| measure(ctx, size, radius, format))
        .collect()
}

fn invalid(e: impl std::fmt::Display) -> VkError {
    VkError::Invalid(e.to_string())
}

fn paint_error(e: PaintError) -> VkError {
    match e {
        PaintError::Vulkan(e) => e,
        PaintError::Stroke(e) => invalid(e),
    }
}

/// A splat map of side `side` with four smooth, unrelated weights per texel.
fn splat_map(side: u32) -> VkResult<SplatMap> {
    let channels: Vec<_> = (0..MAX_LAYERS as u64)
        .map(|k| Generator::Fbm.generate(side, side, 100 + k))
        .collect();
    let texels = (0..side as usize * side as usize)
        .map(|t| std::array::from_fn(|k| channels[k].data()[t]))
        .collect();
    SplatMap::new(side, side, texels).map_err(invalid)
}

fn measure(
    ctx: &Arc<Context>,
    size: u32,
    radius: f32,
    format: HeightFormat,
) -> VkResult<PaintCost> {
    let splat_size = (size / SPLAT_DIVISOR).max(1);
    let splat = splat_map(splat_size)?;
    let layers = MAX_LAYERS;
    let heights = (1..=layers as u64)
        .map(|seed| Generator::Fbm.generate(size, size, seed))
        .collect();
    let pyramid = {
        let stack = LayerStack::from_splat(heights, &splat).map_err(invalid)?;
        BlendedPyramid::new(ctx, &stack, MODE, format, Address::Clamp)?
    };
    time_on_gpu(ctx, |rec| pyramid.record_build(rec))?;
    let mut painter = LayerPainter::new(pyramid, splat, size);

    let (mut full_ms, mut full_cpu_ms) = (Vec::new(), Vec::new());
    for _ in 0..FULL_REBUILDS {
        let start = Instant::now();
        let all = painter.stage_all()?;
        full_cpu_ms.push(start.elapsed().as_secs_f64() * 1e3);
        full_ms.push(time_on_gpu(ctx, |rec| painter.record(rec, &all).map(drop))?);
    }

    let splat_radius = radius * splat_size as f32 / size as f32;
    let (mut stroke_ms, mut paint_cpu_ms, mut texels) = (Vec::new(), Vec::new(), Vec::new());
    for k in 0..STROKES {
        // Spread over the map, away from its edges, each layer in turn.
        let t = (k as f32 + 0.5) / STROKES as f32;
        let stroke = Stroke {
            kind: BrushKind::Paint,
            x: splat_size as f32 * (0.15 + 0.7 * t),
            y: splat_size as f32 * (0.85 - 0.7 * t),
            radius: splat_radius,
            strength: 0.5,
            target: 0.0,
            layer: (k % layers) as u32,
        };
        let start = Instant::now();
        let staged = painter.paint(&[stroke]).map_err(paint_error)?;
        paint_cpu_ms.push(start.elapsed().as_secs_f64() * 1e3);
        let mut regions = Vec::new();
        stroke_ms.push(time_on_gpu(ctx, |rec| {
            regions = painter.record(rec, &staged)?;
            Ok(())
        })?);
        texels.push(
            regions
                .iter()
                .flatten()
                .map(|r| u64::from(r[2]) * u64::from(r[3]))
                .sum::<u64>(),
        );
    }
    texels.sort_unstable();
    let all_texels = (0..mip_level_count(size, size))
        .map(|l| u64::from((size >> l).max(1)).pow(2))
        .sum();
    Ok(PaintCost {
        size,
        splat_size,
        layers,
        mode: MODE.id().to_owned(),
        format,
        radius,
        splat_radius,
        full_ms: median(full_ms),
        full_cpu_ms: median(full_cpu_ms),
        stroke_ms: median(stroke_ms),
        paint_cpu_ms: median(paint_cpu_ms),
        stroke_texels: texels[texels.len() / 2],
        all_texels,
    })
}

/// The section's table (nothing when it was not run).
pub fn report(md: &mut String, costs: &[PaintCost]) {
    if costs.is_empty() {
        return;
    }
    let _ = writeln!(md, "\n### Painting weights\n");
    let _ = writeln!(
        md,
        "A `paint` stroke on one layer of a four-layer {} blend (`relief::render::LayerPainter`: \
         the splat map, an eighth of the field's side, painted and the stack weights that read it \
         weighed again and staged on the CPU, then the weights' and slack's pyramid nodes and the \
         blended texels of every level above them rebuilt on the GPU), against re-staging every \
         weight and rebuilding every node and blended level in place; fbm layers, clamp \
         addressing; GPU time from timestamps, medians of {STROKES} strokes (spread over the map, \
         each layer in turn) and {FULL_REBUILDS} full rebuilds.\n",
        MODE.id()
    );
    let _ = writeln!(
        md,
        "| size | splat | format | stroke radius | full rebuild ms | stroke + partial rebuild ms | share | paint + stage CPU ms | full stage CPU ms | blended texels rebuilt |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
    for c in costs {
        let _ = writeln!(
            md,
            "| {0}^2 | {1}^2 | {2:?} | {3} ({4} splat) | {5:.2} | {6:.3} | 1/{7:.0} | {8:.3} | {9:.1} | {10} of {11} |",
            c.size,
            c.splat_size,
            c.format,
            c.radius,
            c.splat_radius,
            c.full_ms,
            c.stroke_ms,
            c.full_ms / c.stroke_ms.max(1e-9),
            c.paint_cpu_ms,
            c.full_cpu_ms,
            c.stroke_texels,
            c.all_texels
        );
    }
}
