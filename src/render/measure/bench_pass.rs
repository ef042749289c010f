//! The timed pass of `relief bench`: one ray per pixel of a `resolution`-sized grid traced by one
//! method, `warmup + frames` times in one submission, each timed frame between two timestamps
//! with a full barrier between frames.
//!
//! It is the trace compute pass, not a full-screen fragment pass: llvmpipe (lavapipe) bins draws
//! and rasterizes them after the closing timestamp, so fragment work reads as ~0 ms there, while
//! its compute dispatches run inside the timed interval on every driver. The per-ray work and the
//! bindings are the surface pass's own.

use std::sync::Arc;

use super::trace_pass::{trace_timed, TraceRequest};
use crate::heightfield::Heightfield;
use crate::vk::{Context, VkError, VkResult};

/// One timed configuration: the rays (`trace.grid` is the resolution) and how often to run them.
#[derive(Debug, Clone, Copy)]
pub struct BenchRequest<'a> {
    /// The rays and the method tracing them; its `shadow` is traced too when set.
    pub trace: TraceRequest<'a>,
    /// Untimed frames run first in the same submission (caches, clocks).
    pub warmup: u32,
    /// Timed frames; at least 1.
    pub frames: u32,
    /// Dispatches of the trace per frame, timed together; 1 to measure the method. More slow
    /// the method down on the GPU by that factor on purpose, so that `relief bench compare` can
    /// be shown to catch it (`relief bench --slow-down`).
    pub dispatches: u32,
}

/// GPU milliseconds of each timed frame, in order, and the iterations of the timed rays.
#[derive(Debug, Clone)]
pub struct BenchTiming {
    /// GPU ms of each timed frame, in order (`frames` of them).
    pub frame_ms: Vec<f64>,
    /// `(steps, capped)` per ray of the last frame, row by row over `trace.grid`.
    pub steps: Vec<[u32; 2]>,
    /// Compute shader invocations of each timed frame, as the device counts them; empty where
    /// it cannot.
    pub compute_invocations: Vec<u64>,
}

/// Times `req.frames` frames of `req.trace` over `hf`.
pub fn time_method(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    req: &BenchRequest<'_>,
) -> VkResult<BenchTiming> {
    let (w, h) = req.trace.grid;
    if req.frames == 0 || w == 0 || h == 0 {
        return Err(VkError::Invalid(format!(
            "bench of {} frames at {w}x{h}",
            req.frames
        )));
    }
    let out = trace_timed(ctx, hf, &req.trace, req.warmup, req.frames, req.dispatches)?;
    Ok(BenchTiming {
        frame_ms: out.frame_ms,
        steps: out.steps,
        compute_invocations: out.compute_invocations,
    })
}
