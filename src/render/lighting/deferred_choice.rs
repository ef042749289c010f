//! Whether a planned frame can be lit deferred, and if not, why: the lighting pass lights one
//! sample per pixel of the surface pass's own draws, so whatever draws otherwise keeps the
//! forward path.

use super::Lighting;
use crate::render::kit::frame_uniforms::MAX_LIGHTS;
use crate::render::plan::frame_plan::Plan;
use crate::render::shader_interface::DEFERRED_SELF_SHADOW_LIGHTS;
use crate::vk::{VkError, VkResult};

/// Why `plan` (with a shadow probe when `probe`) cannot be lit deferred, naming what to change;
/// `None` when it can.
pub fn deferred_refusal(plan: &Plan, probe: bool) -> Option<String> {
    if probe {
        return Some(
            "a shadow probe writes light visibilities, which only forward lighting computes".into(),
        );
    }
    if plan.msaa.samples > 1 {
        return Some(format!(
            "the lighting pass lights one sample per pixel and the frame draws {}: add --msaa 1",
            plan.msaa.samples
        ));
    }
    if plan.supersample > 1 {
        return Some(
            "the lighting pass lights the frame at its own size: leave out --supersample".into(),
        );
    }
    if !plan.cells.is_empty() {
        return Some("cell complexes light their own fragments: leave out --cells".into());
    }
    if plan.pipelines.iter().any(|k| k.blend) {
        return Some(
            "blended materials are lit as they are drawn over the frame, which needs forward lighting"
                .into(),
        );
    }
    let self_shadowed = plan.pipelines.iter().any(|k| k.shadows.mode.is_some());
    let casting = plan
        .lights
        .iter()
        .take(MAX_LIGHTS)
        .skip(DEFERRED_SELF_SHADOW_LIGHTS as usize)
        .any(|l| l.casts_shadows);
    if self_shadowed && casting {
        return Some(format!(
            "the shading inputs carry the height field's own shadow toward the first {DEFERRED_SELF_SHADOW_LIGHTS} lights, and a later light casts one"
        ));
    }
    None
}

/// Sets `plan.deferred` as `lighting` asks, refusing deferred lighting for a frame that cannot
/// have it (with a shadow probe when `probe`), with the reason and what to change.
pub fn plan_lighting(plan: &mut Plan, lighting: Lighting, probe: bool) -> VkResult<()> {
    plan.deferred = false;
    if lighting == Lighting::Deferred {
        if let Some(why) = deferred_refusal(plan, probe) {
            return Err(VkError::Invalid(format!("--lighting deferred: {why}")));
        }
        plan.deferred = true;
    }
    Ok(())
}
