//! The stiff and extreme cases every method must survive (issue: stability matrix): grazing and
//! vertical views, zero and huge depth scales, tiny and huge maps, degenerate fields, both
//! storage formats and both addressing modes. Each is traced against the reference; the matrix
//! records NaN hits, capped and gross rates and the worst error, or why the case failed.

use std::sync::Arc;

use super::results::StabilityCell;
use super::trace_stats::{ray_direction, trace_stats};
use crate::heightfield::{Address, Generator};
use crate::method::Method;
use crate::render::{
    build_method_map_with, gpu_builds, trace_on_gpu, HeightFormat, MapBuilder, TraceRequest,
};
use crate::vk::Context;

/// One named stiff case.
#[derive(Debug, Clone)]
pub struct StiffCase {
    /// The name the stability matrix shows.
    pub name: String,
    /// The generator of its height field.
    pub field: Generator,
    /// Map width and height, in texels.
    pub size: (u32, u32),
    /// View elevation above the surface plane, in degrees.
    pub angle: f64,
    /// Degrees; 30 unless a case needs another (the sparse spikes use 71, off the grid's axes).
    pub azimuth: f64,
    /// Depth of height 0 below the top plane, in uv units.
    pub depth_scale: f64,
    /// Texel format the heights are uploaded in.
    pub format: HeightFormat,
    /// Addressing mode of the map.
    pub address: Address,
}

const RAYS: (u32, u32) = (32, 32);
/// Largest map whose method maps (cone, quadric) the matrix builds on the CPU, where the device's
/// GPU builders do not take them.
const CPU_MAP_TEXELS: u64 = 2048 * 2048;

fn case(name: &str, field: Generator, size: (u32, u32), angle: f64, depth_scale: f64) -> StiffCase {
    StiffCase {
        name: name.to_owned(),
        field,
        size,
        angle,
        azimuth: 30.0,
        depth_scale,
        format: HeightFormat::R16Unorm,
        address: Address::Repeat,
    }
}

/// Views and depth scales of the sparse-spike rows: one-texel spikes put a spike under every
/// coarse pyramid node, and a grazing ray over a deep field crosses thousands of texels before
/// it can reach the floor. The quick bench keeps the first of each.
const SPIKE_ANGLES: [f64; 3] = [1.0, 0.5, 2.0];
const SPIKE_DEPTHS: [f64; 3] = [0.5, 1.0, 2.0];

/// The cases, in matrix order. `largest` is the biggest map side to try (8192, or what fits);
/// `quick` keeps one sparse-spike row of nine.
pub fn stiff_cases(largest: u32, quick: bool) -> Vec<StiffCase> {
    let fbm = Generator::Fbm;
    let mut cases = vec![
        case("view 0.5 deg", fbm, (128, 128), 0.5, 0.1),
        case("view 1 deg", fbm, (128, 128), 1.0, 0.1),
        case("view 89.9 deg", fbm, (128, 128), 89.9, 0.1),
        case("view 90 deg (vertical)", fbm, (128, 128), 90.0, 0.1),
        case("depth 0", fbm, (128, 128), 30.0, 0.0),
        case("depth 1e-4", fbm, (128, 128), 30.0, 1e-4),
        case("depth 5", fbm, (128, 128), 30.0, 5.0),
        case("depth 50", fbm, (128, 128), 30.0, 50.0),
        case("map 1x1", fbm, (1, 1), 30.0, 0.1),
        case("map 2x2", fbm, (2, 2), 30.0, 0.1),
        case("map 3x5", fbm, (3, 5), 30.0, 0.1),
        case(
            &format!("map {largest}^2"),
            fbm,
            (largest, largest),
            30.0,
            0.1,
        ),
        case("flat0", Generator::Flat0, (128, 128), 30.0, 0.1),
        case("flat1", Generator::Flat1, (128, 128), 30.0, 0.1),
        case(
            "checker (one texel)",
            Generator::Checker,
            (128, 128),
            30.0,
            0.1,
        ),
        case("isolated spikes", Generator::Spikes, (128, 128), 30.0, 0.1),
        case("step cliff", Generator::Step, (128, 128), 30.0, 0.1),
        case("white noise", Generator::Noise, (128, 128), 30.0, 0.1),
    ];
    let mut r32 = case("R32F storage", fbm, (128, 128), 30.0, 0.1);
    r32.format = HeightFormat::R32Float;
    let mut clamp = case("clamp addressing", fbm, (128, 128), 30.0, 0.1);
    clamp.address = Address::Clamp;
    cases.extend([r32, clamp]);
    let keep = if quick { 1 } else { SPIKE_ANGLES.len() };
    for angle in SPIKE_ANGLES.into_iter().take(keep) {
        for depth in SPIKE_DEPTHS.into_iter().take(keep) {
            let name = format!("sparse spikes 256^2, {angle} deg, depth {depth}");
            let mut spikes = case(&name, Generator::Spikes, (256, 256), angle, depth);
            spikes.azimuth = 71.0;
            cases.push(spikes);
        }
    }
    cases
}

/// Traces `method` on `case` and summarises what went wrong, if anything.
pub fn run_stiff_case(ctx: &Arc<Context>, case: &StiffCase, method: Method) -> StabilityCell {
    let cell = |failed: Option<String>| StabilityCell {
        method: method.id().to_owned(),
        case: case.name.clone(),
        nan_pixels: 0,
        capped_rate: 0.0,
        gross_rate: 0.0,
        max_error_texels: 0.0,
        gpu_ms: None,
        failed,
    };
    let (w, h) = case.size;
    if let Some(kind) = method.info().method_map() {
        let cpu_only = u64::from(w) * u64::from(h) > CPU_MAP_TEXELS;
        if cpu_only && !gpu_builds(ctx, kind, w, h) {
            return cell(Some(format!(
                "its map at {w}x{h} exceeds what this device's GPU builder takes (largest storage buffer {} MiB), and the CPU builder is not run above {}^2 texels (minutes to hours on 2 cores; see the map build times)",
                ctx.info().max_storage_buffer_range >> 20,
                (CPU_MAP_TEXELS as f64).sqrt()
            )));
        }
    }
    let raw = case.field.generate(w, h, 1);
    let hf = match case.format {
        HeightFormat::R16Unorm => raw.quantized_unorm16(),
        HeightFormat::R32Float => raw,
    };
    let map = match build_method_map_with(method, &hf, case.address, MapBuilder::Gpu(ctx)) {
        Ok(map) => map,
        Err(e) => return cell(Some(format!("building its map: {e}"))),
    };
    let req = TraceRequest {
        method,
        dir: ray_direction(case.angle, case.azimuth).map(|x| x as f32),
        depth_scale: case.depth_scale as f32,
        grid: RAYS,
        budget: method.info().default_budget,
        address: case.address,
        format: case.format,
        map: map.as_ref().map(|m| &m.data),
        shadow: None,
    };
    match trace_on_gpu(ctx, &hf, &req) {
        Err(e) => cell(Some(e.to_string())),
        Ok(out) => {
            let s = trace_stats(
                &hf,
                &out.hits,
                &out.steps,
                f64::from(req.depth_scale),
                case.address,
            );
            StabilityCell {
                nan_pixels: s.nan_pixels,
                capped_rate: s.capped_rate,
                gross_rate: s.gross_rate,
                max_error_texels: s.error_texels.max,
                gpu_ms: out.frame_ms.iter().copied().reduce(f64::min),
                ..cell(None)
            }
        }
    }
}
