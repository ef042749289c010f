//! Meshes drawn through their cubic cell complexes: the plan, the pass and the GPU march.

pub(in crate::render) mod cells_pass;
pub(in crate::render) mod cells_plan;
pub(in crate::render) mod cells_trace_pass;
