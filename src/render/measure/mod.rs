//! Measuring passes: tracing rays through a height field on the GPU and timing methods for the bench.

pub(in crate::render) mod bench_pass;
pub(in crate::render) mod trace_pass;
