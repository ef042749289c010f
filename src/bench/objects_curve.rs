//! The cost curve over relief objects on screen: 1 to 16 small QDM quads side by side in one
//! view (a 4x4 grid filled row by row, none hiding another), the plain frame's GPU ms with the
//! exponent `k` of `time ~ quads^k`, and the surface shader's own counts of the traced pixels,
//! steps and texel fetches. The traced work grows with the quads' area on screen; the time grows
//! slower wherever a part of the frame (the passes' setup, the background) does not.

use std::fmt::Write as _;
use std::sync::Arc;

use glam::{Mat4, Vec3};
use serde::{Deserialize, Serialize};

use super::cost_curve::fitted_exponent;
use super::frame_timing::{time_setups_interleaved, FrameSetup, MapRate, SteadyFrames};
use crate::heightfield::Heightfield;
use crate::method::Method;
use crate::render::{FrameRequest, RenderError, RenderOptions, Renderer, WorkSummary};
use crate::scene::{relief_stack_scene, Scene};
use crate::vk::Context;

/// The grid's columns and rows: 16 slots inside the stack scene's 16:9 view.
const GRID: (usize, usize) = (4, 4);
/// World units between slot centres across and up, and the quads' scale (the stack's 6-unit quad
/// made 0.6 units, so neighbours leave gaps and the outer ones stay inside the view).
const PITCH: (f32, f32) = (1.2, 0.7);
const QUAD_SCALE: f32 = 0.1;

/// One point of the curve.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ObjectsRow {
    /// Relief quads on screen.
    pub quads: u32,
    /// GPU ms per steady frame, every pass (median).
    pub gpu_ms: f64,
    /// Of that, the surface pass.
    pub surface_ms: f64,
    /// Fragment shader invocations of a steady frame as the device counts them, where it can.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fragment_invocations: Option<u64>,
    /// The surface shader's counts of one frame drawn with `count_work`.
    pub work: WorkSummary,
}

/// `quads` QDM quads in the first slots of the grid, in the stack scene's view and light.
pub fn objects_scene(quads: usize) -> Scene {
    let mut scene = relief_stack_scene(1, 1.0, true, Method::QDM);
    let quad = scene.meshes.remove(0);
    scene.meshes = (0..quads.min(GRID.0 * GRID.1))
        .map(|k| {
            let (col, row) = ((k % GRID.0) as f32, (k / GRID.0) as f32);
            let at = Vec3::new((col - 1.5) * PITCH.0, (1.5 - row) * PITCH.1, 0.0);
            let mut q = quad.clone();
            q.name = format!("quad {k}");
            q.transform = Mat4::from_translation(at)
                * Mat4::from_scale(Vec3::splat(QUAD_SCALE))
                * quad.transform;
            q
        })
        .collect();
    scene
}

/// Times the plain frame `opts` of every count of `quads` in turn over `frames` rounds, and counts
/// one frame of each; returns the rows and each renderer's timed frames.
pub fn run_objects_curve(
    ctx: &Arc<Context>,
    heights: &Heightfield,
    opts: &RenderOptions,
    quads: &[u32],
    frames: u32,
) -> Result<(Vec<ObjectsRow>, Vec<SteadyFrames>), RenderError> {
    let scenes: Vec<Scene> = quads.iter().map(|&n| objects_scene(n as usize)).collect();
    let setups: Vec<FrameSetup> = scenes
        .iter()
        .map(|scene| FrameSetup {
            scene,
            heights: Some(heights),
            opts,
        })
        .collect();
    let timed = time_setups_interleaved(ctx, &setups, frames, MapRate::AsNeeded)?;
    let counting = RenderOptions {
        count_work: true,
        ..opts.clone()
    };
    let mut rows = Vec::new();
    for ((&n, scene), t) in quads.iter().zip(&scenes).zip(&timed) {
        let mut renderer = Renderer::new(ctx, scene, Some(heights), &counting)?;
        let request = FrameRequest {
            camera: renderer.default_camera(),
            read_back: false,
        };
        let frame = renderer.draw(&request)?;
        let work = frame.work.map(|w| w.summary()).ok_or_else(|| {
            RenderError::Vulkan(crate::vk::VkError::Invalid(
                "a counting frame returned no counts".into(),
            ))
        })?;
        rows.push(ObjectsRow {
            quads: n,
            gpu_ms: t.total_ms,
            surface_ms: t.surface_ms,
            fragment_invocations: t.fragment_invocations,
            work,
        });
    }
    Ok((rows, timed))
}

/// k of time, and of steps, against the quads on screen; `None` with fewer than two counts.
pub fn objects_exponents(rows: &[ObjectsRow]) -> (Option<f64>, Option<f64>) {
    let fit = |value: fn(&ObjectsRow) -> f64| {
        let points: Vec<(f64, f64)> = rows
            .iter()
            .map(|r| (f64::from(r.quads), value(r)))
            .collect();
        fitted_exponent(&points)
    };
    (fit(|r| r.gpu_ms), fit(|r| r.work.steps as f64))
}

/// The curve's table and exponents, for the frame-cost report.
pub fn report(md: &mut String, rows: &[ObjectsRow], size: [u32; 2]) {
    if rows.is_empty() {
        return;
    }
    let (k_time, k_steps) = objects_exponents(rows);
    let k = |k: Option<f64>| k.map_or("-".into(), |k| format!("{k:.3}"));
    let _ = writeln!(
        md,
        "\nRelief objects on screen: 1 to 16 small QDM quads side by side in one {}x{} view, none \
         hiding another, plain frame; the traced pixels, steps and texel fetches are the surface \
         shader's own counts of one frame. Time ~ quads^k: **k = {}**; steps: k = {}.\n",
        size[0],
        size[1],
        k(k_time),
        k(k_steps)
    );
    let _ = writeln!(
        md,
        "| quads | GPU ms | of it the surface pass | traced pixels | steps | texel fetches |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    for r in rows {
        let _ = writeln!(
            md,
            "| {} | {:.3} | {:.3} | {} | {} | {} |",
            r.quads, r.gpu_ms, r.surface_ms, r.work.traced_pixels, r.work.steps, r.work.fetches
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_grid_fills_row_by_row_and_stops_at_sixteen() {
        let one = objects_scene(1);
        assert_eq!(one.meshes.len(), 1);
        let all = objects_scene(40);
        assert_eq!(all.meshes.len(), 16);
        let centre = |m: &crate::geometry::Mesh| m.transform.transform_point3(Vec3::ZERO);
        let (first, last) = (centre(&all.meshes[0]), centre(&all.meshes[15]));
        assert!(first.x < last.x && first.y > last.y, "{first} {last}");
        assert_eq!(
            centre(&all.meshes[4]).x,
            first.x,
            "a new row starts at the left"
        );
    }

    #[test]
    fn exponents_fit_time_and_steps() {
        let row = |quads: u32, gpu_ms: f64, steps: u64| ObjectsRow {
            quads,
            gpu_ms,
            surface_ms: gpu_ms,
            fragment_invocations: None,
            work: WorkSummary {
                traced_fragments: 0,
                traced_pixels: 0,
                fragments_per_traced_pixel: 0.0,
                most_fragments_at_a_pixel: 0,
                steps,
                steps_per_traced_pixel: 0.0,
                fetches: 0,
                fetches_per_traced_pixel: 0.0,
            },
        };
        let rows = [row(1, 2.0, 100), row(4, 4.0, 400), row(16, 8.0, 1600)];
        let (time, steps) = objects_exponents(&rows);
        assert!((time.unwrap() - 0.5).abs() < 1e-12);
        assert!((steps.unwrap() - 1.0).abs() < 1e-12);
        let mut md = String::new();
        report(&mut md, &rows, [240, 135]);
        assert!(md.contains("**k = 0.500**"), "{md}");
        assert!(md.contains("| 16 | 8.000 | 8.000 | 0 | 1600 | 0 |"), "{md}");
    }
}
