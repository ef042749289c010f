//! Steady frames of one renderer, timed: what the bench's frame-level sections (scene shadows,
//! frame features, frame costs) compare.

use std::sync::Arc;

use super::median::median;
use crate::heightfield::Heightfield;
use crate::render::{
    BuiltMap, FrameRequest, FrameTimeline, Pass, RenderError, RenderOptions, Renderer,
};
use crate::scene::Scene;
use crate::vk::Context;

/// Median GPU ms per pass of a renderer's steady frames, and the maps its first frame built.
#[derive(Debug, Clone)]
pub struct SteadyFrames {
    /// The shadow maps' pass.
    pub shadow_maps_ms: f64,
    /// The surface pass (tone mapping included).
    pub surface_ms: f64,
    /// The occluder pass.
    pub occluders_ms: f64,
    /// Every pass a steady frame records.
    pub total_ms: f64,
    /// The fragment shader invocations of a steady frame's passes, as the device counts them
    /// (pipeline statistics; the same in every steady frame of a still view); `None` where the
    /// device cannot count or some pass was not counted.
    pub fragment_invocations: Option<u64>,
    /// Every frame's timeline, the first (untimed) one included.
    pub timelines: Vec<FrameTimeline>,
    /// The maps built for the renderer (environment maps included), with their cost.
    pub maps: Vec<BuiltMap>,
}

/// How often the timed frames render their shadow maps.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MapRate {
    /// As the renderer decides: only when a view moved or the casters changed, so a still
    /// view's steady frames render none.
    AsNeeded,
    /// Every frame, as a moving view would: what rendering the maps costs.
    EveryFrame,
}

/// One renderer to time: its scene, the heights of relief materials without their own, and its
/// options.
#[derive(Clone, Copy)]
pub struct FrameSetup<'a> {
    /// The scene drawn, from its own camera.
    pub scene: &'a Scene,
    /// The heights of relief materials without a height texture of their own.
    pub heights: Option<&'a Heightfield>,
    /// How it is drawn.
    pub opts: &'a RenderOptions,
}

/// Times `frames` frames of `scene` (relief materials without heights of their own read
/// `heights`) after a first, untimed one that builds the static maps.
pub fn time_steady_frames(
    ctx: &Arc<Context>,
    scene: &Scene,
    heights: Option<&Heightfield>,
    opts: &RenderOptions,
    frames: u32,
    maps: MapRate,
) -> Result<SteadyFrames, RenderError> {
    let setup = FrameSetup {
        scene,
        heights,
        opts,
    };
    let mut all = time_setups_interleaved(ctx, &[setup], frames, maps)?;
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
    let setups: Vec<FrameSetup> = options
        .iter()
        .map(|opts| FrameSetup {
            scene,
            heights,
            opts,
        })
        .collect();
    time_setups_interleaved(ctx, &setups, frames, MapRate::AsNeeded)
}

/// [`time_interleaved`] over renderers of different scenes or options.
pub fn time_setups_interleaved(
    ctx: &Arc<Context>,
    setups: &[FrameSetup],
    frames: u32,
    maps: MapRate,
) -> Result<Vec<SteadyFrames>, RenderError> {
    let mut renderers = setups
        .iter()
        .map(|s| Renderer::new(ctx, s.scene, s.heights, s.opts))
        .collect::<Result<Vec<_>, _>>()?;
    let mut samples = vec![(Vec::new(), Vec::new(), Vec::new(), Vec::new()); renderers.len()];
    let mut kept: Vec<(Option<u64>, Vec<FrameTimeline>)> =
        vec![(None, Vec::new()); renderers.len()];
    for round in 0..=frames {
        for ((renderer, (shadow, surface, occluders, total)), (counted, lines)) in
            renderers.iter_mut().zip(&mut samples).zip(&mut kept)
        {
            if maps == MapRate::EveryFrame {
                renderer.invalidate_shadow_maps();
            }
            let request = FrameRequest {
                camera: renderer.default_camera(),
                read_back: false,
            };
            let out = renderer.draw(&request)?;
            lines.push(out.timeline.clone());
            // The first round builds the static maps.
            if round == 0 {
                continue;
            }
            // A fold from +0.0: an empty sum of floats is -0.0, which prints as "-0.000".
            let ms = |pass: Pass| {
                out.timings
                    .iter()
                    .filter(|t| t.pass == pass)
                    .fold(0.0, |sum, t| sum + t.gpu_ms)
            };
            shadow.push(ms(Pass::ShadowMaps));
            surface.push(ms(Pass::Surface));
            occluders.push(ms(Pass::Occluders));
            total.push(out.timings.iter().map(|t| t.gpu_ms).sum::<f64>());
            *counted = out
                .timings
                .iter()
                .map(|t| t.counts.map(|c| c.fragment_invocations))
                .sum::<Option<u64>>();
        }
    }
    Ok(renderers
        .iter()
        .zip(samples)
        .zip(kept)
        .map(
            |(
                (renderer, (shadow, surface, occluders, total)),
                (fragment_invocations, timelines),
            )| {
                SteadyFrames {
                    fragment_invocations,
                    timelines,
                    shadow_maps_ms: median(shadow),
                    surface_ms: median(surface),
                    occluders_ms: median(occluders),
                    total_ms: median(total),
                    maps: renderer.maps().to_vec(),
                }
            },
        )
        .collect())
}
