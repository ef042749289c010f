//! Measuring methods: rays from view angles, error against the exact reference, statistics,
//! and the files the tools write (`.npy` dumps).
//!
//! This is what `relief bench` and `relief trace` run: a sweep of displacement methods over height
//! fields, view angles, depth scales and iteration budgets, each timed on the GPU and compared ray by
//! ray with [`crate::heightfield::reference::trace`], written as `results.json` and a report.
//! Units throughout: times in ms, hit errors in texels of the map, angles in degrees (elevation above
//! the surface plane, azimuth from +u toward +v), depth scales in uv units.
//!
//! # Main types
//! - [`SweepConfig`] (what to measure) and [`plan_jobs`], which expands it into [`Job`]s by [`Section`].
//! - [`Runner`]: measures jobs on one device, caching fields and method maps; each gives a [`Run`].
//! - [`TraceStats`], [`Spread`], [`StepStats`] and [`GpuMs`]: the statistics every section records.
//! - [`BenchResults`]: the whole `results.json`, with the extra sections (shading, AO, LOD, edits,
//!   blending) as their own result types; [`load_results`] reads one back, checking its
//!   [`SCHEMA_VERSION`].
//! - [`work_units`], [`partition`] and [`Shard`]: a sweep cut into units with expected costs and
//!   split between shards; [`ShardInfo`] in a shard's results, and [`merge_shards`] joining them.
//!
//! # How they fit together
//! A bench builds a [`SweepConfig`], turns it into jobs with [`plan_jobs`], hands each to a [`Runner`]
//! created on a Vulkan context, and collects the [`Run`]s, the [`Runner::map_builds`] and the other
//! sections into a [`BenchResults`], which is serialized and passed to [`render_report`]. A single
//! trace outside the sweep uses [`ray_direction`] for the view and [`trace_stats`] on the GPU's hits.

mod ao;
mod blending;
mod blending_report;
pub mod compare;
mod cost_curve;
mod cost_gate;
mod depth_curve;
mod depth_match;
mod edits;
mod frame_costs;
mod frame_costs_report;
mod frame_costs_timing;
mod frame_features;
mod frame_timing;
mod lod;
mod machine;
mod median;
mod merge;
mod nan_null;
mod npy;
mod objects_curve;
mod paint_edits;
mod provenance;
mod report;
mod results;
mod results_file;
#[cfg(test)]
mod results_file_fuzz;
#[cfg(test)]
mod results_fixture;
mod runner;
mod scene_shadow_section;
mod scene_shadows;
mod sections_run;
mod shading;
mod shading_report;
mod shadow_stability;
mod shadow_stats;
mod shard;
mod shard_info;
mod silhouettes;
mod slow_down;
pub mod soak;
mod stability;
mod steps_map;
mod subgroup_steps;
mod svg;
mod sweep;
mod trace_stats;
mod traced_ao;
mod traced_shadows;
mod work_units;

pub use ao::{measure_ao, AoConfig, AoRun};
pub use blending::{
    run_blending_section, BlendCost, BlendTrace, BlendingConfig, BlendingSection, ONE_HOT,
};
pub use blending_report::{notes as blending_notes, STEPS_RATIO_NOTED};
pub use cost_curve::fitted_exponent;
pub use cost_gate::{
    check_gate, gate_setup, measure_gate, GateCell, GateCounts, GateFinding, GATE_DEPTH_SCALE,
    GATE_ELEVATIONS, GATE_FIELDS, GATE_RAYS, GATE_SIZE, MAX_GROWTH, MEAN_GROWTH,
};
pub use depth_match::{settled as depth_match_settled, MAX_COST_RATIO, MAX_STEP_BUDGET};
pub use edits::{run_edit_section, EditCost};
pub use frame_costs::{
    run_frame_cost_section, ChainStep, FrameCostRow, FrameCostSection, StackRow,
};
pub use frame_features::{run_frame_feature_section, FrameFeatureRow, FrameFeatureSection};
pub use frame_timing::{
    time_interleaved, time_setups_interleaved, time_steady_frames, FrameSetup, MapRate,
    SteadyFrames,
};
pub use lod::{
    downsample, image_error, receding_plane, render_interleaved, render_timed, run_lod_section,
    ImageError, LodConfig, LodRun, LodScaling, LodSection,
};
pub use machine::{BenchMachine, MachineAtStart};
pub use median::median;
pub use merge::{merge_shards, MergeError, ShardFile};
pub use npy::write_npy_f32;
pub use paint_edits::{run_paint_section, PaintCost};
pub use provenance::{utc_now_rfc3339, BenchDevice, ReliefBuild, SweepOptions};
pub use report::render_report;
pub use results::{BenchResults, GpuMs, MapBuild, Run, StabilityCell, SCHEMA_VERSION};
pub use results_file::{load_results, parse_results, results_path, ResultsFileError};
pub use runner::{plan_jobs, Job, Runner, Section};
pub use scene_shadow_section::{
    run_scene_shadow_section, DefaultFrameCost, SceneShadowCell, SceneShadowSection,
};
pub use scene_shadows::{
    measure_scene_shadows, CasterDifference, SceneShadowConfig, SceneShadowError, SceneShadowRun,
    TURNED_AWAY,
};
pub use sections_run::{SectionsRun, SkippedSection};
pub use shading::{measure_shadows, ShadingConfig, ShadowRun};
pub use shadow_stability::{shadow_stability, ShadowStabilityCell};
pub use shadow_stats::{
    compare_fractions, reference_fractions, shadow_stats, ShadowStats, LEAK_DARK, LEAK_LIT,
};
pub use shard::{partition, Shard, UnitCost};
pub use shard_info::{ShardInfo, StepOrigins};
pub use silhouettes::{
    run_silhouette_section, SilhouetteCell, SilhouetteError, SilhouetteSection, SilhouetteStrip,
    SILHOUETTE_OPTIONS,
};
pub use slow_down::{SlowDown, MAX_SLOW_DOWN};
pub use stability::{run_stiff_case, stiff_cases, StiffCase};
pub use steps_map::StepsMap;
pub use subgroup_steps::{subgroup_steps, TimedSteps};
pub use sweep::{FieldSource, SweepConfig};
pub use trace_stats::{ray_direction, trace_stats, Spread, StepStats, TraceStats};
pub use traced_ao::{measure_traced_ao, TracedAoConfig, TracedAoRun};
pub use traced_shadows::{traced_shadows, TracedShadows};
pub use work_units::{work_units, StepLayout, SweepSections, WholeSection, WorkUnit};
