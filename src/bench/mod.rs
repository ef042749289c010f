//! Measuring methods: rays from view angles, error against the exact reference, statistics,
//! and the files the tools write (`.npy` dumps).

mod npy;
mod trace_stats;

pub use npy::write_npy_f32;
pub use trace_stats::{ray_direction, trace_stats, Spread, TraceStats};
