//! The stability matrix's shading rows: every shadow mode under extreme lights (overhead, on the
//! horizon, below it, 45-degree disks) on degenerate fields (1x1, 3x5, flat, sparse spikes, depth
//! scale 50). Each cell counts fractions that are NaN or outside [0, 1] and the worst difference
//! from the exact visible fraction.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::shadow_stats::shadow_stats;
use super::trace_stats::ray_direction;
use crate::heightfield::visibility::LightDir;
use crate::heightfield::{build_method_map, Address, Generator, Heightfield};
use crate::method::Method;
use crate::render::{trace_on_gpu, HeightFormat, ShadowTrace, TraceRequest};
use crate::scene::ShadowMode;
use crate::vk::Context;

/// One mode under one extreme light on one degenerate field.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ShadowStabilityCell {
    /// The shadow mode's name.
    pub mode: String,
    /// The degenerate case's name.
    pub case: String,
    /// Fractions that are NaN or outside [0, 1].
    pub bad_values: usize,
    /// Largest `|fraction - exact|` of the visible fraction, in [0, 1]; NaN when the case failed.
    #[serde(deserialize_with = "super::nan_null::f64_or_nan")]
    pub max_error: f64,
    /// Mean `|fraction - exact|`; NaN when the case failed.
    #[serde(deserialize_with = "super::nan_null::f64_or_nan")]
    pub mean_error: f64,
    /// Why the case could not run, if it could not.
    pub failed: Option<String>,
}

struct Field {
    name: &'static str,
    hf: Heightfield,
    depth_scale: f32,
}

fn fields() -> Vec<Field> {
    let field = |name, hf, depth_scale| Field {
        name,
        hf,
        depth_scale,
    };
    let flat = Heightfield::new(16, 16, vec![0.25; 256]).ok();
    let mut list = vec![
        field("map 1x1", Generator::Fbm.generate(1, 1, 1), 0.1),
        field("map 3x5", Generator::Fbm.generate(3, 5, 1), 0.1),
        field(
            "spikes 64^2 depth 0.5",
            Generator::Spikes.generate(64, 64, 1),
            0.5,
        ),
        field(
            "bricks depth 50",
            Generator::Bricks.generate(32, 32, 1),
            50.0,
        ),
    ];
    if let Some(hf) = flat {
        list.insert(2, field("flat 16^2", hf, 0.1));
    }
    list
}

/// Lights as (elevation, radius) in degrees.
const LIGHTS: [(f64, f64); 6] = [
    (90.0, 0.0),
    (0.0, 0.0),
    (-10.0, 0.0),
    (-10.0, 45.0),
    (0.5, 45.0),
    (45.0, 45.0),
];

const GRID: u32 = 16;
const REFERENCE_SAMPLES: u32 = 8;

/// Runs every mode under every extreme light on every degenerate field.
pub fn shadow_stability(ctx: &Arc<Context>) -> Vec<ShadowStabilityCell> {
    let mut cells = Vec::new();
    for field in fields() {
        for (elevation, radius) in LIGHTS {
            let case = format!("{}, light {elevation} deg r {radius}", field.name);
            for mode in ShadowMode::ALL[1..].iter().copied() {
                let light = LightDir {
                    elevation_deg: elevation,
                    azimuth_deg: 130.0,
                    radius_deg: radius,
                };
                cells.push(match run(ctx, &field, mode, light) {
                    Ok(mut cell) => {
                        cell.case = case.clone();
                        cell
                    }
                    Err(e) => ShadowStabilityCell {
                        mode: mode.id().to_owned(),
                        case: case.clone(),
                        bad_values: 0,
                        max_error: f64::NAN,
                        mean_error: f64::NAN,
                        failed: Some(format!("{e:#}")),
                    },
                });
            }
        }
    }
    cells
}

fn run(
    ctx: &Arc<Context>,
    field: &Field,
    mode: ShadowMode,
    light: LightDir,
) -> anyhow::Result<ShadowStabilityCell> {
    let hf = field.hf.quantized_unorm16();
    let method = Method::QDM;
    let map = build_method_map(method, &hf, Address::Repeat);
    let req = TraceRequest {
        method,
        dir: ray_direction(40.0, 20.0).map(|x| x as f32),
        depth_scale: field.depth_scale,
        grid: (GRID, GRID),
        budget: method.info().default_budget,
        address: Address::Repeat,
        format: HeightFormat::R16Unorm,
        map: map.as_ref().map(|(m, _)| m),
        shadow: Some(ShadowTrace::directional(
            mode,
            light.elevation_deg,
            light.azimuth_deg,
            light.radius_deg,
        )),
    };
    let out = trace_on_gpu(ctx, &hf, &req)?;
    let s = f64::from(field.depth_scale);
    let stats = shadow_stats(
        &hf,
        &out.hits,
        &out.visible,
        s,
        Address::Repeat,
        light,
        REFERENCE_SAMPLES,
    )?;
    Ok(ShadowStabilityCell {
        mode: mode.id().to_owned(),
        case: String::new(),
        bad_values: stats.bad_values,
        max_error: stats.abs_error.max,
        mean_error: stats.abs_error.mean,
        failed: None,
    })
}
