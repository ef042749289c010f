//! Meshes drawn through their cubic cell complexes: the plan, the pass and the GPU march.

pub(in crate::render) mod cells_pass;
pub(in crate::render) mod cells_plan;
#[cfg(feature = "bench")]
pub(in crate::render) mod cells_trace_pass;
pub(in crate::render) mod complex_buffers;
