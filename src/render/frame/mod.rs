//! The frame's orchestrator: the `Renderer`, which records the frame's graph of passes (`frame_graph`),
//! with the uploads it keeps, the surface pass, targets, the G-buffer and tone mapping; what the
//! passes share is in the kit (`render::kit`), what a scene needs in its plan (`render::plan`).

mod draw_bounds;
pub(in crate::render) mod explain;
mod frame_environment;
pub(in crate::render) mod frame_graph;
pub(in crate::render) mod frame_request;
mod frame_setup;
mod frame_slot;
pub(in crate::render) mod frame_stats;
pub(in crate::render) mod gbuffer;
mod height_upload;
pub(in crate::render) mod material_set;
mod mesh_draws;
pub(in crate::render) mod mesh_pipeline;
pub(in crate::render) mod occluders;
mod record_graph;
pub(in crate::render) mod renderer;
pub(in crate::render) mod scene_ao;
pub(in crate::render) mod scene_textures;
pub(in crate::render) mod shadow_probe;
pub(in crate::render) mod single_frame;
pub(in crate::render) mod surface_pass;
mod surface_pipelines;
mod target_images;
pub(in crate::render) mod targets;
mod terrain_paint;
pub(in crate::render) mod tonemap;
pub(in crate::render) mod work_counters;
