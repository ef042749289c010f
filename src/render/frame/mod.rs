//! The frame renderer and its passes: the plan of what a scene needs, the uploads it keeps, the surface pass, targets, uniforms and timers.

mod draw_bounds;
pub(in crate::render) mod explain;
pub(in crate::render) mod frame_stats;
pub(in crate::render) mod frame_uniforms;
pub(in crate::render) mod gbuffer;
pub(in crate::render) mod gpu_heightfield;
pub(in crate::render) mod height_resources;
mod height_upload;
pub(in crate::render) mod lod_note;
pub(in crate::render) mod material_set;
pub(in crate::render) mod mesh_pipeline;
pub(in crate::render) mod method_map;
pub(in crate::render) mod msaa;
pub(in crate::render) mod occluders;
pub(in crate::render) mod pass;
pub(in crate::render) mod pass_timer;
pub(in crate::render) mod plan;
mod plan_sources;
pub(in crate::render) mod renderer;
pub(in crate::render) mod scene_ao;
pub(in crate::render) mod scene_textures;
pub(in crate::render) mod shell_draw;
pub(in crate::render) mod single_frame;
pub(in crate::render) mod surface_pass;
pub(in crate::render) mod targets;
pub(in crate::render) mod texture_mips;
pub(in crate::render) mod tonemap;
