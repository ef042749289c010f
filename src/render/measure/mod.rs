//! Measuring passes: tracing rays through a height field on the GPU and timing methods for the
//! bench; frames' timelines written as trace events.

pub(in crate::render) mod bench_pass;
pub(in crate::render) mod timeline_trace;
pub(in crate::render) mod trace_pass;
mod trace_sweeps;
