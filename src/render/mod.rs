//! The renderer: joins height fields and scenes with the Vulkan layer. A [`Renderer`] made once
//! per scene owns the uploads, maps and pipelines and draws frames from cameras; typed passes
//! (the pyramid, the surface) are timed by timestamp scopes and read a frame later. Also where a
//! method's map is built (`map_builder`: on the GPU where a builder exists, else `heightfield`'s
//! CPU build) and where the height field's `Address` becomes a sampler address mode
//! (`gpu_heightfield`). The texture-space AO map is built here too (`ao_map_pass`), as are the
//! cells pass that draws meshes through their cell complexes (`cells_pass`), a terrain's blended
//! pyramid (`blended_pyramid_pass`) and its elevation's brush edits (`elevation_editor`).

mod ao_influence;
mod ao_map_pass;
mod ao_sweep;
mod bench_pass;
mod blended_pyramid_pass;
mod cells_pass;
mod cells_plan;
mod cells_trace_pass;
mod cone_map_pass;
mod elevation_editor;
mod explain;
mod frame;
mod frame_stats;
mod frame_uniforms;
mod gpu_heightfield;
mod height_resources;
mod layer_paint;
mod layer_set;
mod layered_heights;
mod lod_note;
mod map_builder;
mod map_search;
mod material_set;
mod mean_pyramid_pass;
mod method_map;
mod pass;
mod pass_timer;
mod plan;
mod pyramid_pass;
mod quadric_map_pass;
mod relaxed_cone_map_pass;
mod renderer;
mod scene_ao;
mod scene_textures;
mod surface_pass;
mod targets;
mod texture_mips;
mod trace_pass;

pub use ao_map_pass::{AoJob, AoMap, AoMapPass, AO_MAP_FORMAT, SWEEP_DIRECTIONS};
pub use bench_pass::{time_method, BenchRequest, BenchTiming};
pub use blended_pyramid_pass::{build_blended_pyramid_on_gpu, time_on_gpu, BlendedPyramid};
pub use cells_pass::{BuiltComplex, CellsOptions};
pub use cells_plan::CellsPlan;
pub use cells_trace_pass::{march_cells_on_gpu, CellsTrace};
pub use cone_map_pass::{
    build_cone_map_on_gpu, ConeMapPass, MAX_SIDE as CONE_MAP_GPU_MAX_SIDE, RATIO_TOLERANCE,
};
pub use elevation_editor::{EditError, EditReport, ElevationEditor};
pub use explain::explain;
pub use frame::{render, BuiltMap, Frame, RenderError, RenderOptions};
pub use frame_stats::{sequence_stats, PassStats, SequenceStats};
pub use frame_uniforms::{frame_camera, FrameUniforms, LightUniform, MAX_LIGHTS};
pub use gpu_heightfield::{GpuHeightfield, HeightFormat};
pub use height_resources::{HeightResources, HeightUpload};
pub use layer_paint::{LayerPainter, PaintError, PaintReport, StagedPaint};
pub use map_builder::{build_method_map_with, gpu_builds, BuiltMethodMap, MapBuilder};
pub use mean_pyramid_pass::{build_mean_pyramid_on_gpu, MeanPyramid};
pub use method_map::GpuMethodMap;
pub use pass::Pass;
pub use pass_timer::{PassTiming, Scope};
pub use plan::{DrawPlan, HeightKey, HeightPlan, PassPlan, PipelineKey, Plan, PlanError, Skipped};
pub use pyramid_pass::{build_pyramid_on_gpu, PyramidJob, PyramidPass};
pub use quadric_map_pass::{build_quadric_map_on_gpu, QuadricMapPass};
pub use relaxed_cone_map_pass::{build_relaxed_cone_map_on_gpu, RelaxedConeMapPass};
pub use renderer::{FrameOutput, FrameRequest, Renderer, FRAMES_IN_FLIGHT};
pub use surface_pass::{describe as describe_pipeline, COLOR_FORMAT, DEPTH_FORMAT};
pub use trace_pass::{
    time_through_pyramid, trace_on_gpu, trace_repeated, trace_through_pyramid, ShadowTrace,
    TraceOutput, TraceRequest, TRACE_GROUP_SIDE,
};
