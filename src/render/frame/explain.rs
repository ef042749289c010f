//! The plan as `relief render --explain` prints it: one JSON object with the pipelines built, the
//! maps built (kind, size, ms), the lights' shadow maps (kind, views, size, filter, casters), the
//! cell complexes built, the meshes drawn as prism shells, the passes recorded and what was
//! skipped, and why.

use serde::Serialize;
use serde_json::{json, Value};

use super::mesh_pipeline::describe;
use super::single_frame::BuiltMap;
use crate::render::cells::cells_pass::BuiltComplex;
use crate::render::lighting::deferred_refusal;
use crate::render::plan::frame_plan::Plan;
use crate::render::shells::shell_upload::BuiltShell;
use crate::vk::ObjectCounts;

#[derive(Serialize)]
struct PipelineEntry {
    name: String,
    shader: String,
    method: Option<&'static str>,
    max_steps: Option<u32>,
    double_sided: bool,
    blend: bool,
    shadows: &'static str,
    lod: bool,
    curved: bool,
    shells: bool,
    /// Whether the frame's depth holds the displaced hit's depth (else the polygon's).
    write_depth: bool,
}

/// The explanation of what `plan` built; `maps` are the maps built for it, `cells` its cell
/// complexes, `shells` its meshes drawn as prism shells and `created` what was created on the
/// device.
pub fn explain(
    plan: &Plan,
    maps: &[BuiltMap],
    cells: &[BuiltComplex],
    shells: &[BuiltShell],
    created: &ObjectCounts,
) -> Value {
    let pipelines: Vec<PipelineEntry> = plan
        .pipelines
        .iter()
        .map(|p| PipelineEntry {
            name: describe(p),
            shader: p.shader(),
            method: p.method.map(|m| m.id()),
            max_steps: p.max_steps,
            double_sided: p.double_sided,
            blend: p.blend,
            shadows: p.shadows.mode.id(),
            lod: p.lod.is_some(),
            curved: p.curved,
            shells: p.shells,
            write_depth: p.write_depth,
        })
        .collect();
    let heights: Vec<Value> = plan
        .heights
        .iter()
        .map(|h| {
            json!({
                "source": h.source,
                "size": [h.size.0, h.size.1],
                "pyramid": h.pyramid,
                "map": h.map.map(|m| m.name()),
                "averaged_pyramid": h.mean_pyramid,
            })
        })
        .collect();
    let ao_maps: Vec<Value> = plan
        .ao_maps
        .iter()
        .map(|a| {
            json!({
                "heights": plan.heights[a.heights].source,
                "mode": a.mode.to_string(),
                "depth_scale": a.depth_scale,
            })
        })
        .collect();
    // Where the frame is lit, and when forward, whether it could have been lit deferred.
    let lighting = if plan.deferred {
        let shadows = if plan.traced_shadows {
            "traced"
        } else {
            "maps"
        };
        json!({"path": "deferred", "shadows": shadows, "deferred_refused": null})
    } else {
        json!({"path": "forward", "shadows": "maps", "deferred_refused": deferred_refusal(plan, false)})
    };
    json!({
        "pipelines": pipelines,
        "lighting": lighting,
        "maps": maps,
        "heights": heights,
        "ao_maps": ao_maps,
        "shadow_maps": plan.shadow_maps,
        "msaa": plan.msaa,
        "supersample": plan.supersample,
        "tone_mapping": plan.tone_mapping,
        "environment": plan.environment,
        "cells": cells,
        "shells": shells,
        "passes": plan.passes,
        "skipped": plan.skipped,
        "draws": plan.surface_draws().count(),
        "caster_only_draws": plan.draws.len() - plan.surface_draws().count(),
        "lights": plan.lights.len(),
        "created": created,
    })
}
