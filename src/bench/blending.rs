//! The bench's terrain-blending section (Drobot section 1.7, Table 1.7): what tracing a
//! height-blended terrain costs against a single field of the same shape, and how far its hits
//! are from the exact reference of the blended surface.
//!
//! A few procedural layers are weighed by a coarse splat map. For each blend mode, method and
//! view angle, the same rays are traced twice: through the blended surface as a terrain supplies
//! it (pyramid methods through the conservative pyramid `terrain::blended_pyramid` builds from the
//! layers' and weights' own pyramids; other methods read the stored blended field, which is all
//! they read) and through the exact pyramid of the blended field, which is what a single-layer
//! field of that shape costs. Methods that read no pyramid get one trace, since both sides are
//! the same dispatch for them. A `one-hot` row, the first layer weighing 1 alone, is the
//! baseline of a true single layer (its bound is that layer's own pyramid).
//!
//! Every trace is one submission of `warmup + frames` dispatches (`render::trace_repeated`,
//! `render::time_through_pyramid`); the last dispatch's hits and iterations give the error and
//! the steps, its timestamps the median GPU time.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::results::GpuMs;
use super::trace_stats::{ray_direction, trace_stats, Spread, StepStats};
use crate::heightfield::rng::SplitMix64;
use crate::heightfield::{Address, Generator, Heightfield, MaxPyramid};
use crate::method::Method;
use crate::render::{
    time_through_pyramid, trace_repeated, HeightFormat, TraceOutput, TraceRequest,
};
use crate::terrain::{blended_field, blended_pyramid, BlendMode, LayerStack, SplatMap};
use crate::vk::Context;

/// What the section measures.
#[derive(Debug, Clone)]
pub struct BlendingConfig {
    /// Methods to trace; those reading a precomputed method map (cone, quadric) are left out,
    /// since that map would have to be built per blend mode from the blended field.
    pub methods: Vec<Method>,
    /// One layer per generator (at most four), each with its own seed.
    pub layers: Vec<Generator>,
    /// Side of every layer's height field, in texels.
    pub size: u32,
    /// Side of the square splat map weighing the layers.
    pub splat_side: u32,
    /// View elevations in degrees.
    pub angles: Vec<f64>,
    /// View azimuth from +u toward +v, in degrees.
    pub azimuth_deg: f64,
    /// Depth of height 0 below the top plane, in uv units.
    pub depth_scale: f32,
    /// Rays per trace, one per texel centre of this grid over the map.
    pub grid: (u32, u32),
    /// Untimed traces before the timed ones.
    pub warmup: u32,
    /// Timed traces per cell.
    pub frames: u32,
    /// Seed of the first layer's generator and of the splat map; each further layer adds one.
    pub seed: u64,
}

impl BlendingConfig {
    /// Four layers at 512^2 under a 16^2 splat map (the paper's 32^2 splat for 1024^2 fields, at
    /// the same texels per splat texel), the methods of Table 1.7 and the pyramid ones.
    pub fn full() -> BlendingConfig {
        let ids = ["relief", "pom", "qdm", "maxmip", "pdm"];
        BlendingConfig {
            methods: ids.iter().filter_map(|id| id.parse().ok()).collect(),
            layers: vec![
                Generator::Fbm,
                Generator::Bricks,
                Generator::Fbm,
                Generator::Bricks,
            ],
            size: 512,
            splat_side: 16,
            angles: vec![30.0, 60.0],
            azimuth_deg: 30.0,
            depth_scale: 0.05,
            grid: (256, 256),
            warmup: 2,
            frames: 9,
            seed: 1,
        }
    }

    /// Smaller layers and fewer rays, for `--quick`.
    pub fn quick() -> BlendingConfig {
        BlendingConfig {
            size: 256,
            splat_side: 8,
            grid: (128, 128),
            warmup: 1,
            frames: 3,
            ..BlendingConfig::full()
        }
    }
}

/// One trace's outcome against the exact reference of the blended surface.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BlendTrace {
    /// GPU time of the trace dispatch over the timed frames.
    pub gpu_ms: GpuMs,
    /// Iterations per ray.
    pub steps: StepStats,
    /// Hit distance from the exact hit of the blended surface, in texels (as [`crate::bench::TraceStats`]).
    pub error_texels: Spread,
    /// Fraction of rays more than one texel from the exact hit.
    pub gross_rate: f64,
    /// Fraction of rays that ran out of iterations.
    pub capped_rate: f64,
    /// Rays whose hit was not finite.
    pub nan_pixels: usize,
}

/// One (method, blend, angle) cell.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BlendCost {
    /// The method's name.
    pub method: String,
    /// A blend mode's id, or `one-hot` for the first layer alone.
    pub blend: String,
    /// View elevation above the surface plane, in degrees.
    pub angle_deg: f64,
    /// Whether `blended` went through the conservative blended pyramid; when false the method
    /// reads no pyramid and `single` is the same trace as `blended`.
    pub through_bound: bool,
    /// Through the blended surface as a terrain supplies it.
    pub blended: BlendTrace,
    /// The same rays through the exact pyramid of the blended field.
    pub single: BlendTrace,
}

impl BlendCost {
    /// Blended over single median GPU time.
    pub fn ms_ratio(&self) -> f64 {
        self.blended.gpu_ms.median / self.single.gpu_ms.median.max(1e-9)
    }

    /// Blended over single mean iterations per ray.
    pub fn steps_ratio(&self) -> f64 {
        self.blended.steps.mean / self.single.steps.mean.max(1e-9)
    }
}

/// The blend of the one-hot baseline row.
pub const ONE_HOT: &str = "one-hot";

/// The section's settings as run, and its cells.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BlendingSection {
    /// The layers' generator names, in stack order.
    pub layers: Vec<String>,
    /// Side of every layer, in texels.
    pub size: u32,
    /// Side of the splat map, in texels.
    pub splat_side: u32,
    /// Depth of height 0 below the top plane, in uv units.
    pub depth_scale: f32,
    /// View azimuth, in degrees.
    pub azimuth_deg: f64,
    /// The ray grid per trace, `[width, height]`.
    pub rays: [u32; 2],
    /// Untimed traces per cell.
    pub warmup: u32,
    /// Timed traces per cell.
    pub frames: u32,
    /// Texel format the blended heights were traced in.
    pub format: HeightFormat,
    /// Methods asked for but not traced (they read a method map).
    pub left_out: Vec<String>,
    /// One row per (method, blend, angle).
    pub rows: Vec<BlendCost>,
}

/// The layers' heights: 32-bit floats, so that the exact reference traces the very surface the
/// GPU reads (a 16-bit blended field is not the blend of 16-bit layers).
const FORMAT: HeightFormat = HeightFormat::R32Float;
const ADDRESS: Address = Address::Repeat;

/// Runs the section.
pub fn run_blending_section(
    ctx: &Arc<Context>,
    cfg: &BlendingConfig,
) -> anyhow::Result<BlendingSection> {
    let heights: Vec<Heightfield> = cfg
        .layers
        .iter()
        .enumerate()
        .map(|(k, g)| g.generate(cfg.size, cfg.size, cfg.seed + k as u64))
        .collect();
    let splat = painted_splat(cfg.splat_side, heights.len(), cfg.seed)?;
    let (traced, left_out): (Vec<Method>, Vec<Method>) = cfg
        .methods
        .iter()
        .partition(|m| m.info().method_map().is_none());
    let mut blends: Vec<(String, LayerStack, BlendMode)> = BlendMode::ALL
        .iter()
        .map(|&mode| {
            let stack = LayerStack::from_splat(heights.clone(), &splat)?;
            Ok((mode.id().to_owned(), stack, mode))
        })
        .collect::<anyhow::Result<_>>()?;
    // Any mode gives a one-hot stack's single layer back bit for bit, its bound that layer's own
    // pyramid.
    blends.push((
        ONE_HOT.to_owned(),
        LayerStack::one_hot(heights.clone(), 0)?,
        BlendMode::HeightIntersect,
    ));
    let mut rows = Vec::new();
    for (blend, stack, mode) in &blends {
        let field = blended_field(stack, *mode);
        let bound = blended_pyramid(stack, *mode, |hf| {
            MaxPyramid::build_bilinear_bound(hf, ADDRESS == Address::Repeat)
        });
        for &method in &traced {
            for &angle in &cfg.angles {
                let req = TraceRequest {
                    method,
                    dir: ray_direction(angle, cfg.azimuth_deg).map(|x| x as f32),
                    depth_scale: cfg.depth_scale,
                    grid: cfg.grid,
                    budget: method.info().default_budget,
                    address: ADDRESS,
                    format: FORMAT,
                    map: None,
                    shadow: None,
                };
                let exact = trace_repeated(ctx, &field, &req, cfg.warmup, cfg.frames)?;
                let single = measured(&field, &exact, cfg.depth_scale);
                let through_bound = method.info().reads_pyramid();
                let blended = if through_bound {
                    let out = time_through_pyramid(ctx, &bound, &req, cfg.warmup, cfg.frames)?;
                    measured(&field, &out, cfg.depth_scale)
                } else {
                    single.clone()
                };
                rows.push(BlendCost {
                    method: method.id().to_owned(),
                    blend: blend.clone(),
                    angle_deg: angle,
                    through_bound,
                    blended,
                    single,
                });
            }
        }
    }
    Ok(BlendingSection {
        layers: cfg.layers.iter().map(|g| g.name().to_owned()).collect(),
        size: cfg.size,
        splat_side: cfg.splat_side,
        depth_scale: cfg.depth_scale,
        azimuth_deg: cfg.azimuth_deg,
        rays: [cfg.grid.0, cfg.grid.1],
        warmup: cfg.warmup,
        frames: cfg.frames,
        format: FORMAT,
        left_out: left_out.iter().map(|m| m.id().to_owned()).collect(),
        rows,
    })
}

/// A splat map as a painter leaves one: each texel mostly one layer, with traces of the others,
/// so that the bilinear weights between texels make blend zones of every mix.
fn painted_splat(side: u32, layers: usize, seed: u64) -> anyhow::Result<SplatMap> {
    let mut rng = SplitMix64::new(seed);
    let texels = (0..side * side)
        .map(|_| {
            let main = rng.below(layers as u32) as usize;
            std::array::from_fn(|k| match k {
                _ if k == main => 1.0,
                _ if k < layers && rng.next_f32() < 0.3 => 0.5 * rng.next_f32(),
                _ => 0.0,
            })
        })
        .collect();
    Ok(SplatMap::new(side, side, texels)?)
}

fn measured(field: &Heightfield, out: &TraceOutput, depth_scale: f32) -> BlendTrace {
    let stats = trace_stats(
        field,
        &out.hits,
        &out.steps,
        f64::from(depth_scale),
        ADDRESS,
    );
    BlendTrace {
        gpu_ms: GpuMs::of(&out.frame_ms),
        steps: stats.steps,
        error_texels: stats.error_texels,
        gross_rate: stats.gross_rate,
        capped_rate: stats.capped_rate,
        nan_pixels: stats.nan_pixels,
    }
}
