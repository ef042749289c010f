//! The renderer's environment: the light built from the options' environment, the background
//! pass that shows it, and what the plan and the built maps say of them.

use std::sync::Arc;

use super::single_frame::{BuiltMap, RenderOptions};
use crate::environment::Background;
use crate::render::environment::{BackgroundPass, EnvironmentLight};
use crate::render::kit::formats::scene_extra_formats;
use crate::render::kit::render_error::RenderError;
use crate::render::plan::frame_plan::Plan;
use crate::vk::Context;

/// The environment light `opts` ask for (none for a shadow probe, whose colours are
/// visibilities) and the background pass that shows it; notes in `plan` what is left out.
pub(super) fn environment_passes(
    ctx: &Arc<Context>,
    opts: &RenderOptions,
    plan: &mut Plan,
    probe: bool,
) -> Result<(Option<EnvironmentLight>, Option<BackgroundPass>), RenderError> {
    // The probe's colours are visibilities: no ambient light to build.
    let behind = opts.background == Background::Environment;
    let environment = match opts.environment.load()? {
        Some(env) if !probe => Some(EnvironmentLight::build(ctx, &env, behind)?),
        _ => None,
    };
    let background = match &environment {
        Some(e) if behind => Some(BackgroundPass::new(
            ctx,
            e,
            plan.msaa.samples,
            scene_extra_formats(plan.gbuffer, plan.deferred),
        )?),
        _ => None,
    };
    if environment.is_none() && !probe {
        plan.skip(
            "environment maps",
            "flat ambient light (--environment none, the library's default)",
        );
    }
    if behind && background.is_none() {
        plan.skip(
            "background: environment",
            "the frame has no environment (--environment none, or a shadow probe)",
        );
    }
    Ok((environment, background))
}

/// Records `environment`, when there is one, in `plan` and among the built `maps`, with its
/// build time (the GPU's when the queue has timestamps).
pub(super) fn note_environment(
    plan: &mut Plan,
    maps: &mut Vec<BuiltMap>,
    environment: Option<&EnvironmentLight>,
) {
    let Some(e) = environment else {
        return;
    };
    plan.environment = Some(e.plan().clone());
    let (ms, on) = match e.build_gpu_ms() {
        Some(ms) => (ms, "gpu"),
        None => (e.build_ms(), "cpu"),
    };
    maps.push(BuiltMap {
        kind: "environment maps",
        source: e.plan().name.clone(),
        size: e.plan().specular_size,
        ms,
        on,
    });
}
