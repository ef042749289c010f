//! The renderer: joins height fields and scenes with the Vulkan layer. A [`Renderer`] made once
//! per scene owns the uploads, maps and pipelines and draws frames from cameras; typed passes are
//! timed by timestamp scopes and read a frame later.
//!
//! - `frame`: the frame renderer and its passes (the plan of what a scene needs, uploads, the
//!   surface pass, targets, uniforms, timers, `--explain`);
//! - `maps`: map builders run once per height field (max and mean pyramids, cone, relaxed cone
//!   and quadric maps, the texture-space AO map);
//! - `terrain`: layered materials' blended pyramid and live edits (elevation brushes, painting);
//! - `shadows`: the lights' shadow maps, displaced casters included;
//! - `cells`: meshes drawn through their cubic cell complexes;
//! - `environment`: image-based ambient light (irradiance, prefiltered specular, BRDF table);
//! - `measure`: traces and timings for the bench and `relief trace` (feature `bench`, as are the
//!   other measuring hooks re-exported here: `time_on_gpu`, `time_occlusion`,
//!   `march_cells_on_gpu`);
//! - `traced`: the scene in acceleration structures, and rays traced through it by ray query.

mod cells;
mod compute_pass;
mod environment;
mod frame;
mod heights;
mod kit;
mod lighting;
mod maps;
#[cfg(feature = "bench")]
mod measure;
mod plan;
pub(crate) mod shader_interface;
mod shadows;
mod shells;
mod terrain;
mod traced;

pub use cells::cells_pass::{BuiltComplex, CellsOptions};
pub use cells::cells_plan::CellsPlan;
#[cfg(feature = "bench")]
pub use cells::cells_trace_pass::{march_cells_on_gpu, CellsTrace};
pub use environment::{BakedEnvironment, EnvironmentLight, EnvironmentPlan};
pub use frame::explain::explain;
pub use frame::frame_stats::{sequence_stats, PassStats, SequenceStats};
pub use frame::gbuffer::GBufferChannels;
pub use frame::mesh_pipeline::describe as describe_pipeline;
pub use frame::renderer::{FrameOutput, FrameRequest, Renderer, FRAMES_IN_FLIGHT};
pub use frame::shadow_probe::{probe_shadows, ShadowProbe};
pub use frame::single_frame::{render, BuiltMap, Frame, RenderOptions, MAX_SUPERSAMPLE};
pub use frame::work_counters::{WorkCounts, WorkSummary};
pub use heights::height_resources::{HeightResources, HeightUpload};
pub use heights::method_map::GpuMethodMap;
pub use kit::formats::{COLOR_FORMAT, DEPTH_FORMAT, GBUFFER_FORMATS, HDR_FORMAT};
pub use kit::frame_timeline::{ClockAlignment, FrameTimeline, GpuSpan, HostSpan, HostWork};
pub use kit::frame_uniforms::{
    frame_camera, FrameUniforms, LightUniform, ShadowTileUniform, MAX_LIGHTS, MAX_SHADOW_TILES,
};
pub use kit::gpu_heightfield::{GpuHeightfield, HeightFormat};
pub use kit::graph::{DroppedPass, FrameGraph, FrameResource, GraphError, GraphNode, PassRate};
pub use kit::pass::Pass;
pub use kit::pass_timer::{PassTiming, Scope, TimedScope};
pub use kit::render_error::RenderError;
pub use kit::tone_curves::{ToneMap, ToneMapping};
pub use lighting::Lighting;
pub use maps::ao_map_pass::{AoJob, AoMap, AoMapPass, AO_MAP_FORMAT, SWEEP_DIRECTIONS};
pub use maps::cone_map_pass::{
    build_cone_map_on_gpu, ConeMapPass, MAX_SIDE as CONE_MAP_GPU_MAX_SIDE, RATIO_TOLERANCE,
};
pub use maps::map_builder::{build_method_map_with, gpu_builds, BuiltMethodMap, MapBuilder};
pub use maps::mean_pyramid_pass::{build_mean_pyramid_on_gpu, MeanPyramid};
pub use maps::pyramid_pass::{build_pyramid_on_gpu, PyramidJob, PyramidPass};
pub use maps::quadric_map_pass::{build_quadric_map_on_gpu, QuadricMapPass};
pub use maps::relaxed_cone_map_pass::{build_relaxed_cone_map_on_gpu, RelaxedConeMapPass};
#[cfg(feature = "bench")]
pub use measure::bench_pass::{time_method, BenchRequest, BenchTiming};
#[cfg(feature = "bench")]
pub use measure::timeline_trace::{timeline_trace, TraceHeader, TracedFrame};
#[cfg(feature = "bench")]
pub use measure::trace_pass::{
    time_through_pyramid, trace_counting_fetches, trace_on_gpu, trace_repeated,
    trace_through_pyramid, ShadowTrace, TraceOutput, TraceRequest, TRACE_GROUP_SIDE,
};
pub use plan::frame_plan::{
    DrawPlan, DrawRole, HeightKey, HeightPlan, PassPlan, PipelineKey, Plan, PlanError, Skipped,
};
pub use plan::msaa::{MsaaPlan, SAMPLE_COUNTS};
pub use shadows::light_views::{cascade_splits, LightView};
pub use shadows::shadow_plan::{
    ShadowFilter, ShadowMapKind, ShadowMapPlan, ShadowOptions, DEFAULT_SHADOW_CASCADES,
    DEFAULT_SHADOW_MAP_SIZE,
};
pub use shells::shell_upload::BuiltShell;
#[cfg(feature = "bench")]
pub use terrain::blended_pyramid_pass::time_on_gpu;
pub use terrain::blended_pyramid_pass::{build_blended_pyramid_on_gpu, BlendedPyramid};
pub use terrain::elevation_editor::{EditError, EditReport, ElevationEditor};
pub use terrain::layer_paint::{LayerPainter, PaintError, PaintReport, StagedPaint};
#[cfg(feature = "bench")]
pub use traced::occlusion_pass::time_occlusion;
pub use traced::occlusion_pass::{trace_occlusion, Occlusion, OcclusionRay};
pub use traced::prism_records::PrismRecord;
pub use traced::traced_scene::{TracedScene, TracedSceneStats};
