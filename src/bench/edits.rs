//! The bench's terrain-edit section: what a brush stroke costs against rebuilding the whole
//! pyramid (issue: a radius-32 stroke on a 4096^2 field within 1/20 of a full rebuild's GPU time).
//! Each size gets an fbm elevation in the sweep's height format; the full rebuild is timed three
//! times, then strokes of each kind at spread-out centres, each applied and its touched nodes
//! rebuilt; medians of both.

use std::fmt::Write as _;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::median::median;
use crate::heightfield::{Address, Generator};
use crate::render::{ElevationEditor, HeightFormat};
use crate::terrain::{BrushKind, Stroke};
use crate::vk::{Context, VkResult};

/// Strokes timed per size.
const STROKES: usize = 8;
/// Full rebuilds timed per size.
const FULL_REBUILDS: usize = 3;

/// One size's edit costs.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct EditCost {
    /// Side of the edited height field, in texels.
    pub size: u32,
    /// Stroke radius, in texels.
    pub radius: f32,
    /// Texel format of the edited height image.
    pub format: HeightFormat,
    /// Median GPU ms of rebuilding every pyramid level.
    pub full_ms: f64,
    /// Median GPU ms of one stroke with its partial rebuild.
    pub stroke_ms: f64,
    /// Pyramid nodes (levels 1 up) a stroke rebuilt, median.
    pub stroke_nodes: u64,
    /// Nodes of levels 1 up in all.
    pub all_nodes: u64,
}

/// Measures strokes of `radius` texels on fields of each of `sizes`.
pub fn run_edit_section(
    ctx: &Arc<Context>,
    sizes: &[u32],
    radius: f32,
    format: HeightFormat,
) -> VkResult<Vec<EditCost>> {
    let mut out = Vec::with_capacity(sizes.len());
    for &size in sizes {
        let elevation = Generator::Fbm.generate(size, size, 1);
        let mut editor = ElevationEditor::new(ctx, &elevation, format, Address::Repeat)?;
        let full: Vec<f64> = (0..FULL_REBUILDS)
            .map(|_| editor.rebuild_all())
            .collect::<VkResult<_>>()?;
        let kinds = [
            BrushKind::Raise,
            BrushKind::Lower,
            BrushKind::Flatten,
            BrushKind::Crater,
        ];
        let mut stroke_ms = Vec::with_capacity(STROKES);
        let mut nodes = Vec::with_capacity(STROKES);
        for k in 0..STROKES {
            // Spread over the map, away from its edges.
            let t = (k as f32 + 0.5) / STROKES as f32;
            let stroke = Stroke {
                kind: kinds[k % kinds.len()],
                x: size as f32 * (0.15 + 0.7 * t),
                y: size as f32 * (0.85 - 0.7 * t),
                radius,
                strength: 0.05,
                target: 0.5,
                layer: 0,
            };
            let report = editor
                .apply(&[stroke])
                .map_err(|e| crate::vk::VkError::Invalid(e.to_string()))?;
            stroke_ms.push(report.gpu_ms);
            nodes.push(report.texels_per_level[1..].iter().sum::<u64>());
        }
        let levels = crate::heightfield::mip_level_count(size, size);
        let all_nodes = (1..levels)
            .map(|l| u64::from((size >> l).max(1)).pow(2))
            .sum();
        nodes.sort_unstable();
        out.push(EditCost {
            size,
            radius,
            format,
            full_ms: median(full),
            stroke_ms: median(stroke_ms),
            stroke_nodes: nodes[nodes.len() / 2],
            all_nodes,
        });
    }
    Ok(out)
}

/// The section's table (nothing when it was not run).
pub fn report(md: &mut String, costs: &[EditCost]) {
    if costs.is_empty() {
        return;
    }
    let _ = writeln!(md, "\n## Terrain edits\n");
    let _ = writeln!(
        md,
        "A brush stroke (`relief::terrain::Stroke`, applied by `brush.comp`) and the rebuild of only \
         the max-pyramid nodes that read a texel it changed, against rebuilding every level; fbm \
         elevation, repeat addressing; GPU time from timestamps, medians of {STROKES} strokes (each \
         kind twice, spread over the map) and {FULL_REBUILDS} full rebuilds.\n"
    );
    let _ = writeln!(
        md,
        "| size | format | stroke radius | full rebuild ms | stroke + partial rebuild ms | share | nodes rebuilt |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|");
    for c in costs {
        let _ = writeln!(
            md,
            "| {0}^2 | {1:?} | {2} | {3:.2} | {4:.3} | 1/{5:.0} | {6} of {7} |",
            c.size,
            c.format,
            c.radius,
            c.full_ms,
            c.stroke_ms,
            c.full_ms / c.stroke_ms.max(1e-9),
            c.stroke_nodes,
            c.all_nodes
        );
    }
}
