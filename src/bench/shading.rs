//! The shading section of `relief bench`: every shadow mode's visible fractions against the exact
//! reference (`heightfield::visibility`) over light elevations and sizes, next to the GPU time the
//! shadow adds to a traced view. The view rays are QDM's (the default scene's method), the same for
//! every mode, so the exact fractions are computed once per light and shared by the modes.

use std::time::Instant;

use serde::{Deserialize, Serialize};

use super::results::GpuMs;
use super::runner::Runner;
use super::shadow_stats::{compare_fractions, reference_fractions, ShadowStats};
use super::sweep::FieldSource;
use super::trace_stats::ray_direction;
use crate::heightfield::visibility::LightDir;
use crate::method::Method;
use crate::render::{time_method, trace_on_gpu, BenchRequest, ShadowTrace, TraceRequest};
use crate::scene::ShadowMode;

/// What the shading section sweeps.
#[derive(Debug, Clone)]
pub struct ShadingConfig {
    /// Shadow modes to measure.
    pub modes: Vec<ShadowMode>,
    /// Light elevations above the surface plane, in degrees.
    pub elevations: Vec<f64>,
    /// Angular radii in degrees.
    pub radii: Vec<f64>,
    /// Light azimuth from +u toward +v, in degrees.
    pub light_azimuth: f64,
    /// The view every hit comes from.
    pub view_angle: f64,
    /// View azimuth from +u toward +v, in degrees.
    pub view_azimuth: f64,
    /// Rays whose visible fractions are compared with the reference.
    pub error_grid: (u32, u32),
    /// Exact rays per point: this squared, over the light's disk.
    pub reference_samples: u32,
}

impl ShadingConfig {
    /// The full sweep: the elevations and radii, every mode but `none`.
    pub fn full() -> ShadingConfig {
        ShadingConfig {
            modes: ShadowMode::ALL[1..].to_vec(),
            elevations: vec![5.0, 15.0, 30.0, 60.0],
            radii: vec![0.0, 0.5, 2.0, 8.0],
            light_azimuth: 200.0,
            view_angle: 45.0,
            view_azimuth: 10.0,
            error_grid: (48, 48),
            reference_samples: 12,
        }
    }

    /// The CI sweep: fewer lights, fewer points.
    pub fn quick() -> ShadingConfig {
        ShadingConfig {
            elevations: vec![15.0, 30.0],
            radii: vec![0.0, 2.0],
            error_grid: (24, 24),
            reference_samples: 6,
            ..ShadingConfig::full()
        }
    }
}

/// One shadow mode under one light on one field.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShadowRun {
    /// The shadow mode's name.
    pub mode: String,
    /// The height field's name.
    pub heightfield: String,
    /// Map width and height, in texels.
    pub size: [u32; 2],
    /// Depth of height 0 below the top plane, in uv units.
    pub depth_scale: f64,
    /// View elevation above the surface plane, in degrees.
    pub view_angle_deg: f64,
    /// Light elevation above the surface plane, in degrees.
    pub light_elevation_deg: f64,
    /// Light azimuth from +u toward +v, in degrees.
    pub light_azimuth_deg: f64,
    /// The light disk's angular radius, in degrees (0: a directional light).
    pub light_radius_deg: f64,
    /// `SHADOW_STEPS`: samples (pom-soft, horizon) or the pyramid walk's cap (cone).
    pub steps: u32,
    /// GPU time of the traced view with this shadow, per frame.
    pub gpu_ms: GpuMs,
    /// Median GPU time of the same view without shadows, per frame.
    pub base_ms: f64,
    /// What the shadow adds: `gpu_ms.median - base_ms`.
    pub shadow_ms: f64,
    /// Rays per timed frame, `[width, height]`.
    pub resolution: [u32; 2],
    /// The mode's visible fraction at each hit of the error grid against
    /// [`crate::heightfield::visibility::light_visibility`].
    pub error: ShadowStats,
}

/// Measures every mode of `cfg` under every light on `field`; `note` hears what runs next.
pub fn measure_shadows(
    runner: &mut Runner,
    cfg: &ShadingConfig,
    field: &FieldSource,
    note: &mut dyn FnMut(&str),
) -> anyhow::Result<Vec<ShadowRun>> {
    let sweep = runner.config().clone();
    let size = sweep.main_size();
    let hf = runner.field(field, size)?;
    // The default scene's method: its hits are the ones shaded.
    let method = Method::QDM;
    let map = runner.map(field, size, method, &hf)?;
    let depth_scale = sweep.main_depth_scale();
    let view = TraceRequest {
        method,
        dir: ray_direction(cfg.view_angle, cfg.view_azimuth).map(|x| x as f32),
        depth_scale: depth_scale as f32,
        grid: cfg.error_grid,
        budget: method.info().default_budget,
        address: sweep.address,
        format: sweep.format,
        map: map.as_deref(),
        shadow: None,
    };
    let ctx = runner.ctx().clone();
    let timed = |shadow: Option<ShadowTrace>| {
        let req = BenchRequest {
            trace: TraceRequest {
                grid: sweep.resolution,
                shadow,
                ..view
            },
            warmup: sweep.warmup,
            frames: sweep.frames,
            dispatches: 1,
        };
        time_method(&ctx, &hf, &req).map(|t| GpuMs::of(&t.frame_ms))
    };
    let base_ms = timed(None)?.median;
    let hits = trace_on_gpu(&ctx, &hf, &view)?.hits;
    let s = f64::from(view.depth_scale);
    let mut runs = Vec::new();
    for &elevation_deg in &cfg.elevations {
        for &radius_deg in &cfg.radii {
            let light = LightDir {
                elevation_deg,
                azimuth_deg: cfg.light_azimuth,
                radius_deg,
            };
            note(&format!(
                "shading: exact visibility on {}, light {elevation_deg} deg radius {radius_deg}",
                field.name()
            ));
            let started = Instant::now();
            let reference =
                reference_fractions(&hf, &hits, s, sweep.address, light, cfg.reference_samples)?;
            log::info!("reference in {:.1} s", started.elapsed().as_secs_f64());
            for &mode in &cfg.modes {
                note(&format!("shading: {mode} on {}", field.name()));
                let shadow =
                    ShadowTrace::directional(mode, elevation_deg, cfg.light_azimuth, radius_deg);
                let traced = trace_on_gpu(
                    &ctx,
                    &hf,
                    &TraceRequest {
                        shadow: Some(shadow),
                        ..view
                    },
                )?;
                anyhow::ensure!(
                    traced.hits == hits,
                    "the view's hits changed with the shadow mode"
                );
                let gpu_ms = timed(Some(shadow))?;
                runs.push(ShadowRun {
                    mode: mode.id().to_owned(),
                    heightfield: field.name(),
                    size: [hf.width(), hf.height()],
                    depth_scale,
                    view_angle_deg: cfg.view_angle,
                    light_elevation_deg: elevation_deg,
                    light_azimuth_deg: cfg.light_azimuth,
                    light_radius_deg: radius_deg,
                    steps: shadow.steps,
                    shadow_ms: gpu_ms.median - base_ms,
                    gpu_ms,
                    base_ms,
                    resolution: [sweep.resolution.0, sweep.resolution.1],
                    error: compare_fractions(&traced.visible, &reference),
                });
            }
        }
    }
    Ok(runs)
}
