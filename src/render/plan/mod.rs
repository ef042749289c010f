//! The plan of a frame: what a scene needs (pipelines, height maps, maps, passes, MSAA) and what
//! it leaves out, decided before any Vulkan object is made.

pub(in crate::render) mod frame_plan;
pub(in crate::render) mod lod_note;
pub(in crate::render) mod msaa;
mod plan_sources;
