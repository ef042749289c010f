//! The timed pass of `relief bench`: one ray per pixel of a `resolution`-sized grid traced by one
//! method, `warmup + frames` times in one submission, each timed frame between two timestamps
//! with a full barrier between frames.
//!
//! It is the trace compute pass, not a full-screen fragment pass: llvmpipe (lavapipe) bins draws
//! and rasterizes them after the closing timestamp, so fragment work reads as ~0 ms there, while
//! its compute dispatches run inside the timed interval on every driver. The per-ray work and the
//! bindings are the surface pass's own.

use std::sync::Arc;

use super::gpu_heightfield::{Addressing, HeightFormat};
use super::method_map::MapData;
use super::trace_pass::{trace_repeated, TraceRequest};
use crate::heightfield::Heightfield;
use crate::method::{Budget, Method};
use crate::vk::{Context, VkError, VkResult};

/// One timed configuration.
#[derive(Debug, Clone, Copy)]
pub struct BenchRequest<'a> {
    pub method: Method,
    pub dir: [f32; 3],
    pub depth_scale: f32,
    pub resolution: (u32, u32),
    pub budget: Budget,
    pub address: Addressing,
    pub format: HeightFormat,
    pub map: Option<&'a MapData>,
    pub warmup: u32,
    pub frames: u32,
}

/// GPU milliseconds of each timed frame, in order.
#[derive(Debug, Clone)]
pub struct BenchTiming {
    pub frame_ms: Vec<f64>,
}

/// Times `req.frames` frames of `req.method` over `hf`.
pub fn time_method(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    req: &BenchRequest<'_>,
) -> VkResult<BenchTiming> {
    let (w, h) = req.resolution;
    if req.frames == 0 || w == 0 || h == 0 {
        return Err(VkError::Invalid(format!(
            "bench of {} frames at {w}x{h}",
            req.frames
        )));
    }
    let trace = TraceRequest {
        method: req.method,
        dir: req.dir,
        depth_scale: req.depth_scale,
        grid: req.resolution,
        budget: req.budget,
        address: req.address,
        format: req.format,
        map: req.map,
    };
    let out = trace_repeated(ctx, hf, &trace, req.warmup, req.frames)?;
    Ok(BenchTiming {
        frame_ms: out.frame_ms,
    })
}
