//! The blending section's table in `report.md`, with a note on every row whose blended surface
//! costs more than 10% extra iterations (Drobot's claim for blended quadtrees).

use std::fmt::Write as _;

use super::blending::{BlendCost, BlendingSection, ONE_HOT};

/// The iteration ratio above which a row gets a note.
pub const STEPS_RATIO_NOTED: f64 = 1.10;

/// The section's table (nothing when it was not run).
pub fn report(md: &mut String, section: &BlendingSection) {
    let s = section;
    let _ = writeln!(md, "\n## Terrain blending\n");
    let _ = writeln!(
        md,
        "Layers {} at {}^2 ({:?}, repeat addressing) weighed by a {}^2 painted splat map; depth \
         scale {}, azimuth {} degrees, {}x{} rays, GPU time the median of {} timed dispatches after \
         {} warm-up. *Blended*: pyramid methods through the conservative blended pyramid \
         (`terrain::blended_pyramid`), the others through the stored blended field. *Single*: the \
         same rays through the exact pyramid of the blended field, what a single field of that \
         shape costs; for methods that read no pyramid it is the same trace (shown as =). \
         `alpha` and `height` define one surface (they differ in shading only), so their steps \
         and errors agree and their times differ by noise alone. `one-hot` is the first layer alone; *ms / one layer* divides by its time. Error and gross \
         rate are the blended trace's, against the exact reference of the blended surface.\n",
        s.layers.join(", "),
        s.size,
        s.format,
        s.splat_side,
        s.depth_scale,
        s.azimuth_deg,
        s.rays[0],
        s.rays[1],
        s.frames,
        s.warmup
    );
    if !s.left_out.is_empty() {
        let _ = writeln!(
            md,
            "Left out (they read a method map built from the field): {}.\n",
            s.left_out.join(", ")
        );
    }
    let _ = writeln!(
        md,
        "| method | blend | angle | blended ms | single ms | ratio | blended steps | single steps | ratio | ms / one layer | mean error | gross |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|");
    for r in &s.rows {
        let (single_ms, ms_ratio, single_steps, steps_ratio) = if r.through_bound {
            (
                format!("{:.3}", r.single.gpu_ms.median),
                format!("{:.2}", r.ms_ratio()),
                format!("{:.2}", r.single.steps.mean),
                format!("{:.3}", r.steps_ratio()),
            )
        } else {
            ("=".into(), "=".into(), "=".into(), "=".into())
        };
        let per_layer = one_layer_ms(s, r)
            .map(|ms| format!("{:.2}", r.blended.gpu_ms.median / ms.max(1e-9)))
            .unwrap_or_default();
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.3} | {single_ms} | {ms_ratio} | {:.2} | {single_steps} | {steps_ratio} | {per_layer} | {:.4} | {:.4} |",
            r.method,
            r.blend,
            r.angle_deg,
            r.blended.gpu_ms.median,
            r.blended.steps.mean,
            r.blended.error_texels.mean,
            r.blended.gross_rate
        );
    }
    let notes = notes(s);
    if !notes.is_empty() {
        let _ = writeln!(md);
        for n in notes {
            let _ = writeln!(md, "- {n}");
        }
    }
}

/// The one-hot row's median ms for `row`'s method and angle.
fn one_layer_ms(section: &BlendingSection, row: &BlendCost) -> Option<f64> {
    section
        .rows
        .iter()
        .find(|o| o.blend == ONE_HOT && o.method == row.method && o.angle_deg == row.angle_deg)
        .map(|o| o.blended.gpu_ms.median)
}

/// One line per blend with rows traced through the bound at more than [`STEPS_RATIO_NOTED`] times
/// the exact pyramid's iterations, naming them and saying why the bound is loose there.
pub fn notes(section: &BlendingSection) -> Vec<String> {
    let mut blends: Vec<&str> = Vec::new();
    for r in &section.rows {
        if !blends.contains(&r.blend.as_str()) {
            blends.push(&r.blend);
        }
    }
    blends
        .into_iter()
        .filter_map(|blend| {
            let over: Vec<String> = section
                .rows
                .iter()
                .filter(|r| {
                    r.blend == blend && r.through_bound && r.steps_ratio() > STEPS_RATIO_NOTED
                })
                .map(|r| format!("{} {} deg {:.2}x", r.method, r.angle_deg, r.steps_ratio()))
                .collect();
            (!over.is_empty()).then(|| {
                format!(
                    "`{blend}` above {STEPS_RATIO_NOTED:.2}x the exact pyramid's iterations ({}): {}.",
                    over.join(", "),
                    why(blend)
                )
            })
        })
        .collect()
}

fn why(blend: &str) -> &'static str {
    match blend {
        "height-intersect" => {
            "max(H) * max(W) over a node pairs the highest height with the highest weight even \
             where they lie on different texels, loosest in blend zones"
        }
        ONE_HOT => "a one-hot bound is the layer's own pyramid, so this is a defect",
        _ => {
            "a convex blend's node bound, the lower of the highest weighted layer and sum(W H) \
             over the node's least weight sum, is looser than height-intersect's max(H) * max(W) \
             (see src/terrain/blended_pyramid.rs)"
        }
    }
}
