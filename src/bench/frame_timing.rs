//! Steady frames of one renderer, timed: what the bench's frame-level sections (scene shadows,
//! frame features) compare.

use std::sync::Arc;

use super::median::median;
use crate::heightfield::Heightfield;
use crate::render::{BuiltMap, FrameRequest, Pass, RenderError, RenderOptions, Renderer};
use crate::scene::Scene;
use crate::vk::Context;

/// Median GPU ms per pass of a renderer's steady frames, and the maps its first frame built.
#[derive(Debug, Clone)]
pub struct SteadyFrames {
    /// The shadow maps' pass.
    pub shadow_maps_ms: f64,
    /// The surface pass (tone mapping included).
    pub surface_ms: f64,
    /// Every pass a steady frame records.
    pub total_ms: f64,
    /// The maps built for the renderer (environment maps included), with their cost.
    pub maps: Vec<BuiltMap>,
}

/// Times `frames` frames of `scene` (relief materials without heights of their own read
/// `heights`) after a first, untimed one that builds the static maps.
pub fn time_steady_frames(
    ctx: &Arc<Context>,
    scene: &Scene,
    heights: Option<&Heightfield>,
    opts: &RenderOptions,
    frames: u32,
) -> Result<SteadyFrames, RenderError> {
    let mut all = time_interleaved(ctx, scene, heights, std::slice::from_ref(opts), frames)?;
    all.pop()
        .ok_or_else(|| RenderError::Vulkan(crate::vk::VkError::Invalid("no renderer".into())))
}

/// [`time_steady_frames`] for each of `options` at once, their frames taken in turn (one of
/// each, then the next round), so a machine whose load changes during the run slows them alike.
pub fn time_interleaved(
    ctx: &Arc<Context>,
    scene: &Scene,
    heights: Option<&Heightfield>,
    options: &[RenderOptions],
    frames: u32,
) -> Result<Vec<SteadyFrames>, RenderError> {
    let mut renderers = options
        .iter()
        .map(|opts| Renderer::new(ctx, scene, heights, opts))
        .collect::<Result<Vec<_>, _>>()?;
    let mut samples = vec![(Vec::new(), Vec::new(), Vec::new()); renderers.len()];
    for round in 0..=frames {
        for (renderer, (maps, surface, total)) in renderers.iter_mut().zip(&mut samples) {
            let request = FrameRequest {
                camera: renderer.default_camera(),
                read_back: false,
            };
            let out = renderer.draw(&request)?;
            // The first round builds the static maps.
            if round == 0 {
                continue;
            }
            let ms = |pass: Pass| {
                out.timings
                    .iter()
                    .filter(|t| t.pass == pass)
                    .map(|t| t.gpu_ms)
                    .sum::<f64>()
            };
            maps.push(ms(Pass::ShadowMaps));
            surface.push(ms(Pass::Surface));
            total.push(out.timings.iter().map(|t| t.gpu_ms).sum::<f64>());
        }
    }
    Ok(renderers
        .iter()
        .zip(samples)
        .map(|(renderer, (maps, surface, total))| SteadyFrames {
            shadow_maps_ms: median(maps),
            surface_ms: median(surface),
            total_ms: median(total),
            maps: renderer.maps().to_vec(),
        })
        .collect())
}
