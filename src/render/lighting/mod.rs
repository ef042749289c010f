//! The deferred frame: the surface pass writes, beside the G-buffer, what lighting needs (the
//! shaded point, its normals, roughness and metallic, the height field's own shadow toward each
//! light) and its emission, and one compute pass lights every pixel once after the scene is
//! drawn: ambient or image-based light, and each punctual light with its shadow-map lookup.
//! Forward lighting (every fragment lit as it is drawn) stays the reference and the default.

mod deferred_choice;
mod lighting_pass;
mod shading_inputs;
mod traced_choice;

pub(in crate::render) use deferred_choice::{deferred_refusal, plan_lighting};
pub(in crate::render) use lighting_pass::{
    lighting_pass_for, LightingPass, LitImages, TracedShadows,
};
pub(in crate::render) use shading_inputs::ShadingInputs;
pub(in crate::render) use traced_choice::{
    traced_shadows_for, FrameTracedShadows, TRACED_SAMPLES_PER_SIDE,
};

/// Where a frame's surfaces are lit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Lighting {
    /// In the surface pass's fragments, as each is drawn (the reference).
    #[default]
    Forward,
    /// Once per pixel, in a lighting pass after the scene is drawn (`--lighting deferred`):
    /// one sample per pixel, no supersampling, shadow probe, cell complexes or blended
    /// materials, at most four self-shadowing lights; a frame that has any of them is refused
    /// with the reason.
    Deferred,
}

impl Lighting {
    /// The name `--lighting` takes and `--explain` prints.
    pub fn name(self) -> &'static str {
        match self {
            Lighting::Forward => "forward",
            Lighting::Deferred => "deferred",
        }
    }
}

impl std::fmt::Display for Lighting {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
