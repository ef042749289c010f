//! The frame-cost section's tables in `report.md`, one writer per table (`frame_costs::report`
//! puts them in order).

use std::fmt::Write as _;

use super::cost_curve::fitted_exponent;
use super::frame_costs::FrameCostSection;
use crate::scene::STACK_QUAD_SIDE;

/// The table of every frame timed, with the frames' legend.
pub(super) fn write_rows(md: &mut String, s: &FrameCostSection) {
    let _ = writeln!(
        md,
        "GPU ms per steady frame (every pass; median of {} frames taken in interleaved rounds). \
         *plain*: one sample, flat ambient light, no tone curve, no shadow maps. *look*: \
         `relief render`'s default (4x MSAA, sky light and background, PCSS shadow maps, PBR \
         Neutral). The default look costs **{:.2}x** the plain frame. The occluder pass \
         (on in every row but *occluders off*) costs the plain frame **{:.2}x** on this scene, \
         where it hides no relief.\n",
        s.frames, s.look_over_plain, s.occluder_cost
    );
    let _ = writeln!(
        md,
        "| frame | size | GPU ms | of it shadow maps | fragment invocations |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|");
    for r in &s.rows {
        let counted = r
            .fragment_invocations
            .map_or("-".to_owned(), |n| n.to_string());
        let _ = writeln!(
            md,
            "| {} | {}x{} | {:.3} | {:.3} | {counted} |",
            r.frame, r.size[0], r.size[1], r.gpu_ms, r.shadow_maps_ms
        );
    }
}

/// The cost against resolution of the plain frame and the look, where their sizes fit a curve.
pub(super) fn write_resolution_curves(md: &mut String, s: &FrameCostSection) {
    let curves: Vec<String> = ["plain", "look"]
        .iter()
        .filter_map(|&frame| {
            let points: Vec<(f64, f64)> = s
                .rows
                .iter()
                .filter(|r| r.frame == frame)
                .map(|r| (f64::from(r.size[0]) * f64::from(r.size[1]), r.gpu_ms))
                .collect();
            let k = fitted_exponent(&points)?;
            Some(format!("*{frame}* k = {k:.3} over {} sizes", points.len()))
        })
        .collect();
    if !curves.is_empty() {
        let _ = writeln!(
            md,
            "\nCost against resolution, time ~ pixels^k fitted over the sizes above (1 is linear \
             in pixels; below 1, fixed costs such as the shadow maps and per-draw setup): {}.",
            curves.join(", ")
        );
    }
}

/// The chain from the plain frame to the look, then deferred lighting against forward.
pub(super) fn write_chains(md: &mut String, s: &FrameCostSection) {
    let _ = writeln!(md, "\n| step | from | to | ratio |");
    let _ = writeln!(md, "|---|---|---|---|");
    for c in &s.chain {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.2}x |",
            c.step, c.from, c.to, c.ratio
        );
    }
    if !s.deferred.is_empty() {
        let _ = writeln!(
            md,
            "\nDeferred lighting (`--lighting deferred`: the surface pass writes shading inputs, \
             a compute pass lights each pixel once) against forward, at one sample:\n"
        );
        let _ = writeln!(md, "| from | to | ratio (to over from) |");
        let _ = writeln!(md, "|---|---|---|");
        for c in &s.deferred {
            let _ = writeln!(md, "| {} | {} | {:.2}x |", c.from, c.to, c.ratio);
        }
    }
}

/// The hidden-relief table: each stack with and without the occluder pass.
pub(super) fn write_stacks(md: &mut String, s: &FrameCostSection) {
    let _ = writeln!(
        md,
        "\nHidden relief: eight QDM quads ({STACK_QUAD_SIDE} x {STACK_QUAD_SIDE} units, 0.3 units of relief, \
         one 256^2 fbm field), one behind the other, the nearest filling the {}x{} view, plain \
         frame; *forward* is the same without the occluder pass (`--occluders off`).\n",
        s.stack_size[0], s.stack_size[1]
    );
    let _ = writeln!(
        md,
        "| spacing | frame | one quad ms | eight, nearest first | eight, farthest first | eight vs one |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    for r in &s.stacks {
        let mut lines = vec![(
            "occluders",
            [r.one_ms, r.nearest_first_ms, r.farthest_first_ms],
        )];
        lines.extend(r.forward.map(|f| ("forward", f)));
        let pass = r.occluders_ms;
        let _ = writeln!(
            md,
            "| {} | of it the occluder pass | {:.3} | {:.3} | {:.3} | |",
            r.spacing, pass[0], pass[1], pass[2]
        );
        for (frame, [one, nearest, farthest]) in lines {
            let _ = writeln!(
                md,
                "| {} | {frame} | {one:.3} | {nearest:.3} | {farthest:.3} | {:.2}x |",
                r.spacing,
                nearest.max(farthest) / one.max(1e-9)
            );
        }
    }
}
