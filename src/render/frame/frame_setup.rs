//! What a renderer's options make of a scene's plan before anything is built: samples,
//! supersampling, the occluder pass, the G-buffer, where the frame is lit, its shadows (maps, or
//! rays through the scene's structures, built here), work counting and tone mapping, each
//! refused with its reason when the device or the frame cannot have it.

use std::sync::Arc;

use super::occluders::plan_occluders;
use super::single_frame::{choose_supersample, RenderOptions};
use crate::heightfield::Heightfield;
use crate::render::kit::frame_uniforms::MAX_LIGHTS;
use crate::render::kit::render_error::RenderError;
use crate::render::kit::tone_curves::ToneMapping;
use crate::render::lighting::{plan_lighting, traced_shadows_for, FrameTracedShadows};
use crate::render::plan::frame_plan::Plan;
use crate::render::plan::msaa::MsaaPlan;
use crate::render::shadows::shadow_plan::{plan_shadow_maps, ShadowOptions};
use crate::scene::Scene;
use crate::vk::{Context, VkError};

/// The plan `opts` make of `scene` on `ctx`'s device, and the structures its shadow rays go
/// through when the frame traces them.
pub(super) fn plan_frame(
    ctx: &Arc<Context>,
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    opts: &RenderOptions,
) -> Result<(Plan, Option<FrameTracedShadows>), RenderError> {
    let selection = opts.cells.as_ref().map(|c| &c.selection);
    let mut plan = Plan::derive_with_cells(scene, frame_heights, selection)?;
    let probe = opts.shadow_probe.is_some();
    plan.msaa = MsaaPlan::choose(opts.msaa, ctx.info().max_samples, probe)?;
    plan.supersample = choose_supersample(opts, ctx.info().max_image_dimension_2d, probe)?;
    plan_occluders(&mut plan, scene, opts.occluders);
    plan.gbuffer = opts.gbuffer;
    plan_lighting(&mut plan, opts.lighting, probe)?;
    // After the lighting's checks, so a frame refused for them builds no structure.
    let traced = traced_shadows_for(
        ctx,
        scene,
        frame_heights,
        (opts.traced_shadows, opts.lighting),
        (opts.height_format, opts.address),
    )?;
    match traced {
        Some(_) => {
            plan.traced_shadows = true;
            plan_shadow_maps(&mut plan, scene, &ShadowOptions::OFF);
            plan.skip("shadow maps", "ray-traced shadows (--traced-shadows)");
        }
        None => plan_shadow_maps(&mut plan, scene, &opts.shadows),
    }
    if opts.count_work && !ctx.info().fragment_stores {
        return Err(VkError::Unsupported(
            "counting work per pixel (fragmentStoresAndAtomics)".into(),
        )
        .into());
    }
    plan.count_work = opts.count_work;
    // The probe's colours are visibilities, not radiance.
    plan.tone_mapping = if probe {
        ToneMapping::NONE
    } else {
        opts.tone_mapping
    };
    if !plan.tone_mapping.exposure_ev.is_finite() {
        return Err(VkError::Invalid(format!(
            "--exposure must be a finite number of stops, got {}",
            plan.tone_mapping.exposure_ev
        ))
        .into());
    }
    if let Some(k) = opts
        .shadow_probe
        .filter(|&k| k >= plan.lights.len().min(MAX_LIGHTS))
    {
        return Err(VkError::Invalid(format!(
            "shadow probe of light {k}: the frame has {} light(s)",
            plan.lights.len().min(MAX_LIGHTS)
        ))
        .into());
    }
    Ok((plan, traced))
}
