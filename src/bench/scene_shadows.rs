//! Scene shadows measured against the exact reference: a probe frame gives each pixel's surface
//! point and relief's visible fraction of the light there; the exact scene reference traces the
//! same points against every triangle and every relief field; the two are compared (hard
//! agreement outside a one-texel band around shadow edges, mean absolute error, acne, leaks).
//! Used by `relief shadows`, the bench's scene-shadow section and the tests.

use std::sync::Arc;

use glam::Vec3;
use serde::Serialize;

use super::traced_shadows::{traced_shadows, TracedShadows};
use crate::heightfield::{Address, Heightfield};
use crate::render::{
    probe_shadows, Pass, RenderError, RenderOptions, ShadowFilter, ShadowOptions, ShadowProbe,
};
use crate::scene::{
    default_heightfield, default_scene, shadow_scene, Light, Scene, ShadowScene,
    DEFAULT_SCENE_METHOD,
};
use crate::shadow_reference::{
    measure_agreement, shadow_edge_band, SceneOccluders, ShadowAgreement,
};
use crate::vk::Context;

/// The value of pixels whose surface faces away from the light, in both dumps.
pub const TURNED_AWAY: f32 = -2.0;

/// How far toward the eye a read-back point moves before the reference traces it, as a share of
/// its distance.
const RECEIVER_NUDGE: f32 = 1e-4;

/// One scene-shadow measurement.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SceneShadowConfig {
    /// The test scene, or `None` for the default scene.
    pub scene: Option<ShadowScene>,
    /// Test scenes: the sun's elevation, degrees.
    pub elevation_deg: f32,
    /// The light's angular radius in degrees (test scenes; the default scene keeps its own
    /// unless this is given).
    pub radius_deg: Option<f32>,
    /// Image size.
    pub width: u32,
    /// Image size.
    pub height: u32,
    /// Map size, cascades and filter.
    pub shadows: ShadowOptions,
    /// Exact reference rays per pixel per side (soft lights; one ray for a hard light).
    pub samples_per_side: u32,
    /// Also trace the reference with relief materials casting as their flat polygons.
    pub flat_reference: bool,
    /// Also trace the shadows by ray query (the device must have ray queries).
    pub traced: bool,
}

impl Default for SceneShadowConfig {
    fn default() -> Self {
        SceneShadowConfig {
            scene: None,
            elevation_deg: 25.0,
            radius_deg: None,
            width: 240,
            height: 135,
            shadows: ShadowOptions::DEFAULT,
            samples_per_side: 6,
            flat_reference: false,
            traced: false,
        }
    }
}

/// What a measurement found.
#[derive(Debug, Clone, Serialize)]
pub struct SceneShadowRun {
    /// The scene's name.
    pub scene: String,
    /// The map size, cascades and filter of the light's map.
    pub map_size: u32,
    /// Cascades (directional lights).
    pub cascades: u32,
    /// The filter.
    pub filter: ShadowFilter,
    /// The light's angular radius, degrees.
    pub light_radius_deg: f32,
    /// Relief against the exact reference, outside the one-texel band around shadow edges: the
    /// hard verdicts, acne and leaks.
    pub agreement: ShadowAgreement,
    /// The same over every receiver pixel, band included: its mean absolute error is the soft
    /// shadows' error, penumbrae and all.
    pub everywhere: ShadowAgreement,
    /// The shadow maps' term alone against the exact reference: its acne counts lit points the
    /// maps darken (the height field's own shadows, the other term, are measured apart in the
    /// bench's shading section); its leaks count what the maps alone leave to that term.
    pub map_term: ShadowAgreement,
    /// The exact reference with flat casters against the exact reference: how well a perfect
    /// flat caster could agree (only with `flat_reference`).
    pub flat_caster: Option<ShadowAgreement>,
    /// Where the displaced and the flat casters' exact verdicts differ, and whom relief follows
    /// there (only with `flat_reference`).
    pub caster_difference: Option<CasterDifference>,
    /// GPU ms of the shadow maps in the probe frame (debug builds run with validation; bench
    /// timings come from release frames).
    pub shadow_maps_ms: f64,
    /// GPU ms of the probe frame's surface pass.
    pub surface_ms: f64,
    /// Per pixel: exact visible fraction (-1 background, -2 turned away from the light).
    #[serde(skip)]
    pub exact: Vec<f32>,
    /// Per pixel: relief's visible fraction (-1 background, -2 turned away from the light).
    #[serde(skip)]
    pub relief: Vec<f32>,
    /// Per pixel: the flat-caster reference, when traced.
    #[serde(skip)]
    pub flat: Vec<f32>,
    /// Per pixel: relief's shadow-map term alone.
    #[serde(skip)]
    pub maps: Vec<f32>,
    /// Per pixel: relief's own (height-field) term alone.
    #[serde(skip)]
    pub own: Vec<f32>,
    /// Pixels where a term was not a number (NaN or infinite), flagged by the shader.
    pub non_finite: usize,
    /// The same light traced by ray query, against the same reference (only with `traced`).
    pub traced: Option<TracedShadows>,
}

/// The pixels whose exact lit-or-shadowed verdict changes when relief casters are taken flat.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct CasterDifference {
    /// Receiver pixels (band included) where the two references disagree.
    pub pixels: usize,
    /// Of those, the share where relief's verdict is the displaced caster's (a flat caster
    /// scores 0 there by definition).
    pub relief_follows_displaced: f64,
}

impl CasterDifference {
    fn measure(exact: &[f32], flat: &[f32], relief: &[f32]) -> CasterDifference {
        let lit = |v: f32| v > 0.5;
        let differing: Vec<usize> = (0..exact.len())
            .filter(|&k| exact[k] >= 0.0 && flat[k] >= 0.0 && relief[k] >= 0.0)
            .filter(|&k| lit(exact[k]) != lit(flat[k]))
            .collect();
        let follows = differing
            .iter()
            .filter(|&&k| lit(relief[k]) == lit(exact[k]))
            .count();
        CasterDifference {
            pixels: differing.len(),
            relief_follows_displaced: follows as f64 / differing.len().max(1) as f64,
        }
    }
}

/// Why a measurement failed.
#[derive(Debug, thiserror::Error)]
pub enum SceneShadowError {
    /// The frame could not be rendered.
    #[error(transparent)]
    Render(#[from] RenderError),
    /// The reference could not be built from the scene.
    #[error("shadow reference: {0}")]
    Reference(String),
}

/// The scene, its frame height map and address for `config`.
pub(super) fn scene_of(config: &SceneShadowConfig) -> (Scene, Heightfield, Address, String) {
    match config.scene {
        Some(kind) => (
            shadow_scene(kind, config.elevation_deg, config.radius_deg.unwrap_or(0.0)),
            default_heightfield(),
            kind.address(),
            format!("{kind} (sun at {} deg)", config.elevation_deg),
        ),
        None => {
            let mut scene = default_scene(DEFAULT_SCENE_METHOD);
            if let Some(r) = config.radius_deg {
                for l in &mut scene.lights {
                    l.radius = r.to_radians();
                }
            }
            (
                scene,
                default_heightfield(),
                Address::Repeat,
                "default".into(),
            )
        }
    }
}

/// Screen-space band radii: one shadow-map texel as it lands on the receiver (stretched by
/// the light's slant over it), in pixels at the point's distance, and at least one pixel.
fn band_radii(probe: &ShadowProbe, eye: Vec3, yfov: f32, l: Vec3) -> Vec<f32> {
    let (w, h) = (probe.width as usize, probe.height as usize);
    let pixel_angle = 2.0 * (yfov * 0.5).tan() / h as f32;
    (0..w * h)
        .map(|k| {
            let Some(p) = probe.world[k] else { return 0.0 };
            let (x, y) = (k % w, k / w);
            let at = |dx: isize, dy: isize| {
                let (nx, ny) = (x as isize + dx, y as isize + dy);
                if nx < 0 || ny < 0 || nx >= w as isize || ny >= h as isize {
                    return None;
                }
                probe.world[ny as usize * w + nx as usize]
            };
            let normal = match (at(1, 0).or(at(-1, 0)), at(0, 1).or(at(0, -1))) {
                (Some(a), Some(b)) => (a - p).cross(b - p).normalize_or_zero(),
                _ => Vec3::ZERO,
            };
            let slant = normal.dot(l).abs().max(0.1);
            let footprint = probe.texel_world[k] / slant;
            // A pixel is a point sample: an edge nearer than one pixel is not placed either way.
            (footprint / (p.distance(eye) * pixel_angle).max(1e-9)).max(1.0)
        })
        .collect()
}

/// Renders the probe frame and traces the reference for `config`.
pub fn measure_scene_shadows(
    ctx: &Arc<Context>,
    config: &SceneShadowConfig,
) -> Result<SceneShadowRun, SceneShadowError> {
    let (scene, heights, address, name) = scene_of(config);
    let opts = RenderOptions {
        width: config.width,
        height: config.height,
        address,
        shadows: config.shadows,
        ..RenderOptions::default()
    };
    let probe = probe_shadows(ctx, &scene, Some(&heights), &opts, 0, None)?;
    let relief = probe.visibility();
    let light = scene.lights[0];
    let occluders = SceneOccluders::new(&scene, Some(&heights.quantized_unorm16()), address)
        .map_err(|e| SceneShadowError::Reference(e.to_string()))?;
    let samples = if light.radius > 0.0 {
        config.samples_per_side
    } else {
        1
    };
    let camera = scene
        .camera
        .unwrap_or_else(|| crate::render::frame_camera(&scene));
    let eye = camera.eye();
    let points = receiver_points(&probe, eye);
    let mut exact = occluders.visible_fractions(&points, &light, samples);
    let mut relief = relief;
    mark_turned_away(&probe, &mut exact, &mut relief);
    let yfov = match camera.projection {
        crate::scene::Projection::Perspective { yfov, .. } => yfov,
        crate::scene::Projection::Orthographic { .. } => 1.0,
    };
    let toward = -light.direction.normalize_or(Vec3::NEG_Y);
    let radii = band_radii(&probe, eye, yfov, toward);
    let band = shadow_edge_band(&exact, probe.width as usize, probe.height as usize, &radii);
    let agreement = measure_agreement(&exact, &relief, &band);
    let everywhere = measure_agreement(&exact, &relief, &[]);
    let map_term = measure_agreement(&exact, &map_term_alone(&relief, &probe), &band);
    let flat = if config.flat_reference {
        flat_reference(&scene, &points, &light, samples)?
    } else {
        Vec::new()
    };
    let traced = if config.traced {
        Some(traced_shadows(
            ctx, &occluders, &points, &light, samples, &exact, &band,
        )?)
    } else {
        None
    };
    let flat_caster = (!flat.is_empty()).then(|| measure_agreement(&exact, &flat, &band));
    let caster_difference =
        (!flat.is_empty()).then(|| CasterDifference::measure(&exact, &flat, &relief));
    let ms = |pass: Pass| pass_ms(&probe, pass);
    let map = light.shadow_map_size.unwrap_or(config.shadows.map_size);
    Ok(SceneShadowRun {
        scene: name,
        map_size: map,
        cascades: light.shadow_cascades.unwrap_or(config.shadows.cascades),
        filter: config.shadows.filter.unwrap_or(if light.radius > 0.0 {
            ShadowFilter::Pcss
        } else {
            ShadowFilter::Hard
        }),
        light_radius_deg: light.radius.to_degrees(),
        agreement,
        everywhere,
        map_term,
        flat_caster,
        caster_difference,
        shadow_maps_ms: ms(Pass::ShadowMaps),
        surface_ms: ms(Pass::Surface),
        exact,
        relief,
        flat,
        non_finite: probe.finite.iter().filter(|&&f| !f).count(),
        maps: probe.maps,
        own: probe.own,
        traced,
    })
}

/// The probe's receivers, as the reference traces them: a point read back from the depth lies a
/// rounding error off its surface, maybe behind it, where the surface itself would block every
/// ray, so each moves toward `eye` by 1e-4 of its distance (ten times the depth buffer's error
/// here), onto the side the pixel sees. Faces turned from the light are no receivers (`None`).
fn receiver_points(probe: &ShadowProbe, eye: Vec3) -> Vec<Option<Vec3>> {
    probe
        .world
        .iter()
        .zip(&probe.facing)
        .map(|(p, &facing)| p.filter(|_| facing).map(|p| p + (eye - p) * RECEIVER_NUDGE))
        .collect()
}

/// Marks the pixels whose faces turn away from the light in both `exact` and `relief`: they are
/// no receivers, and both verdicts are trivially 0 there.
fn mark_turned_away(probe: &ShadowProbe, exact: &mut [f32], relief: &mut [f32]) {
    for k in 0..exact.len() {
        if probe.world[k].is_some() && !probe.facing[k] {
            exact[k] = TURNED_AWAY;
            relief[k] = TURNED_AWAY;
        }
    }
}

/// Relief's shadow-map term alone per pixel, where `relief` has a receiver (its marks elsewhere).
fn map_term_alone(relief: &[f32], probe: &ShadowProbe) -> Vec<f32> {
    relief
        .iter()
        .zip(&probe.maps)
        .map(|(&r, &m)| if r < 0.0 { r } else { m })
        .collect()
}

/// The exact reference at `points` with relief casters taken as their flat polygons.
fn flat_reference(
    scene: &Scene,
    points: &[Option<Vec3>],
    light: &Light,
    samples: u32,
) -> Result<Vec<f32>, SceneShadowError> {
    let flat =
        SceneOccluders::flat(scene).map_err(|e| SceneShadowError::Reference(e.to_string()))?;
    Ok(flat.visible_fractions(points, light, samples))
}

/// The probe frame's GPU ms in `pass`.
fn pass_ms(probe: &ShadowProbe, pass: Pass) -> f64 {
    probe
        .timings
        .iter()
        .filter(|t| t.pass == pass)
        .map(|t| t.gpu_ms)
        .sum::<f64>()
}
