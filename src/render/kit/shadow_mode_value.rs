//! The value a self-shadow mode takes in the shaders' `SPEC_SHADOW_MODE` constant.

use crate::render::shader_interface::{
    SHADOW_MODE_CONE, SHADOW_MODE_HARD, SHADOW_MODE_HORIZON, SHADOW_MODE_NONE, SHADOW_MODE_POM_SOFT,
};
use crate::scene::ShadowMode;

/// `mode` as `shaders/include/shadows.glsl` tests it.
pub(in crate::render) fn shadow_mode_value(mode: ShadowMode) -> u32 {
    match mode {
        ShadowMode::None => SHADOW_MODE_NONE,
        ShadowMode::Hard => SHADOW_MODE_HARD,
        ShadowMode::PomSoft => SHADOW_MODE_POM_SOFT,
        ShadowMode::Horizon => SHADOW_MODE_HORIZON,
        ShadowMode::Cone => SHADOW_MODE_CONE,
    }
}
