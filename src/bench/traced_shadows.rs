//! Scene shadows by ray query, measured beside the shadow maps: each receiver of the probe frame
//! sends the exact reference's own light rays (the same starting points, samples and offsets)
//! through the scene's acceleration structures, and the share that reaches the light is compared
//! with the exact reference, shadow-edge band included and left out.

use std::sync::Arc;

use glam::Vec3;
use serde::Serialize;

use crate::render::{time_occlusion, OcclusionRay, RenderError, TracedScene, TracedSceneStats};
use crate::scene::Light;
use crate::shadow_reference::{light_samples, measure_agreement, SceneOccluders, ShadowAgreement};
use crate::vk::Context;

/// A directional light's rays end here rather than at infinity: far beyond any scene, and a
/// finite bound for the query.
const FAR: f32 = 1e30;

/// Dispatches timed per measurement; the time is the median's.
const TIMED_REPEATS: u32 = 3;

/// What the traced shadows scored and cost.
#[derive(Debug, Clone, Serialize)]
pub struct TracedShadows {
    /// Against the exact reference over every receiver pixel, shadow-edge band included.
    pub everywhere: ShadowAgreement,
    /// The same outside the band the maps' figures leave out.
    pub outside_band: ShadowAgreement,
    /// What the acceleration structures hold and what building them cost.
    pub structures: TracedSceneStats,
    /// Rays traced (receivers times light samples).
    pub rays: usize,
    /// Relief prisms tested by the shader, over all rays.
    pub prisms_tested: u64,
    /// Height-field walk iterations over all those tests.
    pub walk_steps: u64,
    /// Rays whose height-field walk ran out of budget.
    pub capped: usize,
    /// GPU ms of one occlusion dispatch over every ray, the median of three (debug builds run
    /// with validation).
    pub trace_ms: f64,
    /// Per pixel: the traced visible fraction (negative where `exact` is).
    #[serde(skip)]
    pub visible: Vec<f32>,
}

/// Traces `points`' light rays (`samples_per_side` per side for a soft light) through
/// `occluders` on the GPU and scores them against `exact` (band given by `band`).
pub fn traced_shadows(
    ctx: &Arc<Context>,
    occluders: &SceneOccluders,
    points: &[Option<Vec3>],
    light: &Light,
    samples_per_side: u32,
    exact: &[f32],
    band: &[bool],
) -> Result<TracedShadows, RenderError> {
    let scene = TracedScene::new(ctx, occluders)?;
    let epsilon = occluders.epsilon();
    // Per pixel, its rays' range in `rays`.
    let mut rays = Vec::new();
    let mut ranges = Vec::with_capacity(points.len());
    for p in points {
        let start = rays.len();
        let mut samples = 0;
        if let Some(p) = p.filter(|p| p.is_finite()) {
            let p = occluders.receiver(p);
            for s in light_samples(p, light, samples_per_side) {
                samples += 1;
                let reach = s.max_t.min(FAR) - epsilon;
                // A light nearer than the offset is reached: nothing fits between.
                if reach > 0.0 {
                    rays.push(OcclusionRay {
                        origin: p + s.dir * epsilon,
                        t_min: 0.0,
                        dir: s.dir,
                        t_max: reach,
                    });
                }
            }
        }
        ranges.push((start, rays.len(), samples));
    }
    let occlusion = time_occlusion(ctx, &scene, &rays, TIMED_REPEATS)?;
    let visible: Vec<f32> = ranges
        .iter()
        .zip(exact)
        .map(|(&(start, end, samples), &e)| {
            if e < 0.0 {
                return e;
            }
            if samples == 0 {
                return 1.0;
            }
            let blocked = occlusion.blocked[start..end].iter().filter(|&&b| b).count();
            (samples - blocked) as f32 / samples as f32
        })
        .collect();
    Ok(TracedShadows {
        everywhere: measure_agreement(exact, &visible, &[]),
        outside_band: measure_agreement(exact, &visible, band),
        structures: scene.stats(),
        rays: rays.len(),
        prisms_tested: occlusion.prisms_tested,
        walk_steps: occlusion.walk_steps,
        capped: occlusion.capped,
        trace_ms: occlusion.gpu_ms,
        visible,
    })
}
