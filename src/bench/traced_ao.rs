//! Ambient occlusion from the displaced scene by ray query, against the brute-force CPU
//! reference (`shadow_reference::ambient`): a G-buffer frame gives each pixel's surface point and
//! shading normal; both tracers send the same cosine-weighted rays from the same receivers,
//! through every object and relief solid of the scene, and their unblocked shares are compared.

use std::sync::Arc;

use glam::Vec3;
use serde::Serialize;

use super::scene_shadows::{scene_of, SceneShadowConfig, SceneShadowError};
use crate::render::{
    frame_camera, render, time_occlusion, GBufferChannels, OcclusionRay, RenderError,
    RenderOptions, ShadowOptions, TracedScene, TracedSceneStats,
};
use crate::scene::{Camera, ShadowScene};
use crate::shadow_reference::{SceneOccluders, NO_RECEIVER};
use crate::vk::Context;

/// How far toward the eye a read-back point moves before it is traced from, as a share of its
/// distance (as the scene-shadow probe's).
const RECEIVER_NUDGE: f32 = 1e-4;

/// One ambient-occlusion measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TracedAoConfig {
    /// The test scene, or `None` for the default scene.
    pub scene: Option<ShadowScene>,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// How far the rays reach, world units.
    pub radius: f32,
    /// Rays per receiver per side (a stratified, cosine-weighted grid).
    pub samples_per_side: u32,
}

impl Default for TracedAoConfig {
    fn default() -> Self {
        TracedAoConfig {
            scene: Some(ShadowScene::BoxOverRelief),
            width: 160,
            height: 90,
            radius: 1.0,
            samples_per_side: 4,
        }
    }
}

/// What a measurement found.
#[derive(Debug, Clone, Serialize)]
pub struct TracedAoRun {
    /// The scene's name.
    pub scene: String,
    /// Receiver pixels (covered, with a normal).
    pub pixels: usize,
    /// Rays traced by each tracer.
    pub rays: usize,
    /// Mean absolute difference of the unblocked share, traced against the reference.
    pub mean_abs_error: f64,
    /// The largest difference at any pixel.
    pub max_abs_error: f32,
    /// Pixels whose shares differ at all (each ray is 1 / samples^2 of one).
    pub differing_pixels: usize,
    /// The reference's mean unblocked share over the receivers.
    pub mean_visibility: f64,
    /// Receivers the reference finds partly occluded.
    pub occluded_pixels: usize,
    /// GPU ms of one dispatch over every ray (median of three).
    pub trace_ms: f64,
    /// Prisms the rays asked the shader to test.
    pub prisms_tested: u64,
    /// Rays whose height-field walk ran out of budget.
    pub capped: usize,
    /// The acceleration structures.
    pub structures: TracedSceneStats,
    /// Per pixel, the reference's share (-1 where there is no receiver).
    #[serde(skip)]
    pub exact: Vec<f32>,
    /// Per pixel, the traced share (-1 where there is no receiver).
    #[serde(skip)]
    pub traced: Vec<f32>,
}

/// Renders `config`'s G-buffer frame, traces its receivers' ambient rays both ways and compares.
pub fn measure_traced_ao(
    ctx: &Arc<Context>,
    config: &TracedAoConfig,
) -> Result<TracedAoRun, SceneShadowError> {
    // Before the reference's CPU work: without ray queries there is nothing to compare it with.
    if !ctx.info().ray_query {
        return Err(RenderError::NoRayQueries {
            device: ctx.info().name.clone(),
        }
        .into());
    }
    let shadow_config = SceneShadowConfig {
        scene: config.scene,
        ..SceneShadowConfig::default()
    };
    let (scene, heights, address, _) = scene_of(&shadow_config);
    let name = config.scene.map_or("default".into(), |k| k.to_string());
    let opts = RenderOptions {
        width: config.width,
        height: config.height,
        address,
        shadows: ShadowOptions::OFF,
        gbuffer: true,
        ..RenderOptions::default()
    };
    let frame = render(ctx, &scene, Some(&heights), &opts)?;
    let gbuffer = frame
        .gbuffer
        .ok_or_else(|| SceneShadowError::Reference("the frame wrote no G-buffer".into()))?;
    let camera = scene.camera.unwrap_or_else(|| frame_camera(&scene));
    let receivers = gbuffer_receivers(&gbuffer, &camera);
    let occluders = SceneOccluders::new(&scene, Some(&heights.quantized_unorm16()), address)
        .map_err(|e| SceneShadowError::Reference(e.to_string()))?;
    let exact = occluders.ambient_visibilities(&receivers, config.samples_per_side, config.radius);
    // The same rays, on the GPU.
    let (rays, ranges) = gpu_rays(&occluders, &receivers, config);
    let traced_scene = TracedScene::new(ctx, &occluders)?;
    let occlusion = time_occlusion(ctx, &traced_scene, &rays, 3)?;
    let traced = traced_shares(&ranges, &receivers, &occlusion.blocked);
    let pairs: Vec<(f32, f32)> = exact
        .iter()
        .zip(&traced)
        .filter(|(e, _)| **e >= 0.0)
        .map(|(&e, &t)| (e, t))
        .collect();
    let pixels = pairs.len();
    let diff = |&(e, t): &(f32, f32)| (e - t).abs();
    Ok(TracedAoRun {
        scene: name,
        pixels,
        rays: rays.len(),
        mean_abs_error: pairs.iter().map(|p| f64::from(diff(p))).sum::<f64>()
            / pixels.max(1) as f64,
        max_abs_error: pairs.iter().map(diff).fold(0.0, f32::max),
        differing_pixels: pairs.iter().filter(|p| diff(p) > 0.0).count(),
        mean_visibility: pairs.iter().map(|&(e, _)| f64::from(e)).sum::<f64>()
            / pixels.max(1) as f64,
        occluded_pixels: pairs.iter().filter(|&&(e, _)| e < 1.0).count(),
        trace_ms: occlusion.gpu_ms,
        prisms_tested: occlusion.prisms_tested,
        capped: occlusion.capped,
        structures: traced_scene.stats(),
        exact,
        traced,
    })
}

/// Each pixel's receiver in `gbuffer` seen by `camera`: its point, nudged toward the eye as the
/// scene-shadow probe's are, and its shading normal; `None` where the pixel is not wholly
/// covered or has no usable point or normal.
fn gbuffer_receivers(gbuffer: &GBufferChannels, camera: &Camera) -> Vec<Option<(Vec3, Vec3)>> {
    let eye = camera.eye();
    gbuffer
        .positions(camera)
        .iter()
        .zip(&gbuffer.normal)
        .zip(&gbuffer.coverage)
        .map(|((&p, &n), &c)| {
            let (p, n) = (Vec3::from(p), Vec3::from(n));
            let usable = c >= 1.0 && p.is_finite() && n.length_squared() > 0.5;
            usable.then(|| (p + (eye - p) * RECEIVER_NUDGE, n))
        })
        .collect()
}

/// The reference's ambient rays of every receiver as GPU rays, and per receiver the range of
/// them it sent (start, end) with its ray count (rays of no reach are counted but not sent).
fn gpu_rays(
    occluders: &SceneOccluders,
    receivers: &[Option<(Vec3, Vec3)>],
    config: &TracedAoConfig,
) -> (Vec<OcclusionRay>, Vec<(usize, usize, usize)>) {
    let mut rays = Vec::new();
    let mut ranges = Vec::with_capacity(receivers.len());
    for r in receivers {
        let start = rays.len();
        let mut count = 0;
        if let Some((p, n)) = *r {
            let set = occluders.ambient_rays(p, n, config.samples_per_side, config.radius);
            count = set.directions.len();
            if set.reach > 0.0 {
                rays.extend(set.directions.iter().map(|&d| OcclusionRay {
                    origin: set.receiver + d * set.epsilon,
                    t_min: 0.0,
                    dir: d,
                    t_max: set.reach,
                }));
            }
        }
        ranges.push((start, rays.len(), count));
    }
    (rays, ranges)
}

/// Each receiver's unblocked share from the GPU's `blocked` verdicts over its `ranges`
/// (`NO_RECEIVER` where there is none, 1 where it sent no ray).
fn traced_shares(
    ranges: &[(usize, usize, usize)],
    receivers: &[Option<(Vec3, Vec3)>],
    blocked: &[bool],
) -> Vec<f32> {
    ranges
        .iter()
        .zip(receivers)
        .map(|(&(start, end, count), r)| match (r, count) {
            (None, _) => NO_RECEIVER,
            (Some(_), 0) => 1.0,
            (Some(_), _) => {
                let blocked = blocked[start..end].iter().filter(|&&b| b).count();
                (count - blocked) as f32 / count as f32
            }
        })
        .collect()
}
