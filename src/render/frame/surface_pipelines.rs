//! The surface pass's pipelines: for each pipeline of the plan, the one its shaded draws are
//! drawn with, the one they cast shadows with and the one occluding draws write their bounds
//! with, each built only where some draw needs it.

use std::sync::Arc;

use super::mesh_draws::MeshDraw;
use super::mesh_pipeline::{create_pipeline, MeshStages};
use super::occluders::occluder_taps;
use super::surface_pass::FrameLayouts;
use crate::render::kit::formats::scene_extra_formats;
use crate::render::plan::frame_plan::{PipelineKey, Plan};
use crate::render::shadows::shadow_plan::shadow_filter_max;
use crate::vk::{Context, DescriptorLayout, Pipeline, VkResult};

/// The descriptor set layouts the surface pass's pipelines are built over.
pub(super) struct PipelineLayouts<'a> {
    /// Set 0: plain, or heights with what the key's method reads.
    pub frame: &'a FrameLayouts,
    /// Set 1: the material.
    pub material: &'a DescriptorLayout,
    /// Set 2 of layered variants.
    pub layers: &'a DescriptorLayout,
    /// Set 2 of relief variants without layers: nothing, so set 3 can follow it.
    pub no_layers: &'a DescriptorLayout,
    /// Set 3 of relief variants: the occluder bounds.
    pub occluders: &'a DescriptorLayout,
}

/// By plan pipeline: `build(key)` where `needed`, `None` elsewhere.
fn pipelines_where(
    plan: &Plan,
    needed: &[bool],
    build: impl Fn(&PipelineKey) -> VkResult<Pipeline>,
) -> VkResult<Vec<Option<Pipeline>>> {
    plan.pipelines
        .iter()
        .zip(needed)
        .map(|(key, &need)| need.then(|| build(key)).transpose())
        .collect()
}

/// By plan pipeline: the pipeline its surface draws are shaded with (`None` for a key only
/// caster-only draws use).
pub(super) fn surface_pipelines(
    ctx: &Arc<Context>,
    plan: &Plan,
    layouts: &PipelineLayouts,
) -> VkResult<Vec<Option<Pipeline>>> {
    let shadow_filter = shadow_filter_max(plan);
    let taps = if plan.occluders {
        occluder_taps(plan.msaa.samples)
    } else {
        0
    };
    let mut shading = vec![false; plan.pipelines.len()];
    plan.surface_draws()
        .for_each(|d| shading[d.pipeline] = true);
    pipelines_where(plan, &shading, |key| {
        let set0 = layouts.frame.for_key(key);
        let samples = plan.msaa.samples;
        let extra = scene_extra_formats(plan.gbuffer, plan.deferred);
        let occluder_use = (taps, plan.count_work);
        let stages = MeshStages::surface(key, shadow_filter, samples, occluder_use, extra)
            .lit_deferred(plan.deferred && !key.blend, plan.traced_shadows);
        let layers = if key.layers {
            layouts.layers
        } else {
            layouts.no_layers
        };
        if key.method.is_some() {
            let sets = [set0, layouts.material, layers, layouts.occluders];
            create_pipeline(ctx, key, &stages, &sets)
        } else if key.layers {
            let sets = [set0, layouts.material, layouts.layers];
            create_pipeline(ctx, key, &stages, &sets)
        } else {
            create_pipeline(ctx, key, &stages, &[set0, layouts.material])
        }
    })
}

/// By plan pipeline: the pipeline its draws cast shadows with, when some map has them as
/// casters.
pub(super) fn caster_pipelines(
    ctx: &Arc<Context>,
    plan: &Plan,
    layouts: &PipelineLayouts,
) -> VkResult<Vec<Option<Pipeline>>> {
    pipelines_where(plan, &caster_pipelines_needed(plan), |key| {
        let stages = MeshStages::caster(key);
        create_pipeline(
            ctx,
            key,
            &stages,
            &[layouts.frame.for_key(key), layouts.material],
        )
    })
}

/// By plan pipeline: the pipeline its occluding draws (among `draws`) write their bounds with.
pub(super) fn occluder_pipelines(
    ctx: &Arc<Context>,
    plan: &Plan,
    layouts: &PipelineLayouts,
    draws: &[MeshDraw],
) -> VkResult<Vec<Option<Pipeline>>> {
    let mut occluding = vec![false; plan.pipelines.len()];
    draws
        .iter()
        .filter(|d| d.occludes)
        .for_each(|d| occluding[d.pipeline] = true);
    pipelines_where(plan, &occluding, |key| {
        let stages = MeshStages::occluder(key);
        create_pipeline(
            ctx,
            key,
            &stages,
            &[layouts.frame.for_key(key), layouts.material],
        )
    })
}

/// By plan pipeline: whether some shadow map has a draw of it among its casters.
fn caster_pipelines_needed(plan: &Plan) -> Vec<bool> {
    let mut needed = vec![false; plan.pipelines.len()];
    for map in &plan.shadow_maps {
        for &k in &map.casters {
            needed[plan.draws[k].pipeline] = true;
        }
    }
    needed
}
