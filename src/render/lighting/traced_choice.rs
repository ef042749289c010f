//! Ray-traced shadows in the frame (`RenderOptions::traced_shadows`): the scene's occluders in
//! acceleration structures, built once with the renderer, for the lighting pass to cast every
//! shadow-casting light's rays through instead of looking shadow maps up.

use std::sync::Arc;

use crate::heightfield::{Address, Heightfield};
use crate::render::kit::gpu_heightfield::HeightFormat;
use crate::render::kit::render_error::RenderError;
use crate::render::traced::traced_scene::TracedScene;
use crate::scene::Scene;
use crate::shadow_reference::SceneOccluders;
use crate::vk::Context;

use super::Lighting;

/// Rays per side of the grid over a light with a size: 16 rays per pixel and light.
pub const TRACED_SAMPLES_PER_SIDE: u32 = 4;

/// The structures a frame's shadow rays go through, and how far a ray starts off its receiver.
pub struct FrameTracedShadows {
    /// The scene's occluders on the GPU.
    pub scene: TracedScene,
    /// The exact reference's receiver offset for the scene (world units).
    pub offset: f32,
}

/// The traced scene of `scene` when `wanted`, its relief reading `frame_heights` as the frame
/// uploads them (`format`, `address`); refused unless the frame is lit deferred (`lighting`)
/// and the device has ray queries.
pub fn traced_shadows_for(
    ctx: &Arc<Context>,
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    (wanted, lighting): (bool, Lighting),
    (format, address): (HeightFormat, Address),
) -> Result<Option<FrameTracedShadows>, RenderError> {
    if !wanted {
        return Ok(None);
    }
    if lighting != Lighting::Deferred {
        return Err(RenderError::Traced(
            "--traced-shadows casts its rays in the lighting pass: add --lighting deferred (with --msaa 1)"
                .into(),
        ));
    }
    if !ctx.info().ray_query {
        return Err(RenderError::NoRayQueries {
            device: ctx.info().name.clone(),
        });
    }
    // The reference reads the heights as the GPU holds them, so both trace one field.
    let stored = match (format, frame_heights) {
        (HeightFormat::R16Unorm, Some(h)) => Some(h.quantized_unorm16()),
        (_, h) => h.cloned(),
    };
    let occluders = SceneOccluders::new(scene, stored.as_ref(), address)
        .map_err(|e| RenderError::Traced(format!("the scene's occluders: {e}")))?;
    let offset = occluders.epsilon();
    let scene = TracedScene::new(ctx, &occluders)?;
    Ok(Some(FrameTracedShadows { scene, offset }))
}
