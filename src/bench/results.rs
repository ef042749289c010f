//! What `relief bench` records (docs/results-schema.md): where and how it was measured, one
//! object per measured configuration with its frame samples, the map build times, the stability
//! matrix and the other sections, written as `results.json` and read back by
//! [`crate::bench::load_results`].

use serde::{Deserialize, Serialize};

use super::ao::AoRun;
use super::provenance::{BenchDevice, ReliefBuild, SweepOptions};
use super::shading::ShadowRun;
use super::shadow_stability::ShadowStabilityCell;
use super::subgroup_steps::TimedSteps;
use super::trace_stats::{Spread, StepStats};
use crate::method::Budget;

/// The version of the `results.json` layout this relief writes and reads. Version 1 (no
/// `schema_version` field) had only the summaries, no frame samples; version 2 adds the samples
/// and the provenance (build, date, argv, options, device ids). Any change that renames, removes
/// or reinterprets a field raises it (docs/results-schema.md).
pub const SCHEMA_VERSION: u32 = 2;

/// Median, minimum and maximum of the timed frames, and every frame's time.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct GpuMs {
    /// Median frame time in ms (mean of the middle two for an even count).
    pub median: f64,
    /// Fastest frame, in ms.
    pub min: f64,
    /// Slowest frame, in ms.
    pub max: f64,
    /// Every timed frame's time in ms, in the order they ran: what `relief bench compare` draws
    /// its intervals from.
    pub samples: Vec<f64>,
}

impl GpuMs {
    /// Summarises frame times and keeps them; empty input gives zeros.
    pub fn of(frames: &[f64]) -> GpuMs {
        let sorted = super::median::sorted(frames.iter().copied());
        let (Some(&min), Some(&max)) = (sorted.first(), sorted.last()) else {
            return GpuMs {
                median: 0.0,
                min: 0.0,
                max: 0.0,
                samples: Vec::new(),
            };
        };
        GpuMs {
            median: super::median::median_of_sorted_frames(&sorted),
            min,
            max,
            samples: frames.to_vec(),
        }
    }
}

/// One measured configuration: a method on a height field at one view, scale and budget.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct Run {
    /// The report section the run belongs to.
    pub section: super::runner::Section,
    /// The method's name, as `--methods` spells it.
    pub method: String,
    /// The height field's name: a generator's name or the file name.
    pub heightfield: String,
    /// Map width and height, in texels.
    pub size: [u32; 2],
    /// Depth of the height field's 0 below its 1, in uv units.
    pub depth_scale: f64,
    /// View ray elevation above the surface plane, in degrees (90 = straight down).
    pub angle_deg: f64,
    /// View ray azimuth from +u toward +v, in degrees.
    pub azimuth_deg: f64,
    /// Addressing mode, `"repeat"` or `"clamp"`.
    pub address: String,
    /// The method's iteration budget for this run.
    pub budget: Budget,
    /// GPU time of the trace dispatch over the timed frames (timestamp queries), with every
    /// frame's sample.
    pub gpu_ms: GpuMs,
    /// Timed frames (after warm-up).
    pub frames: u32,
    /// Rays per frame as a `[width, height]` grid.
    pub resolution: [u32; 2],
    /// CPU wall time of the whole timed submission, for context.
    pub cpu_ms: f64,
    /// Distance in uv between the method's hit and the exact bilinear hit ([`crate::heightfield::reference::trace`]),
    /// in texels of the map (u scaled by the width, v by the height); NaN hits excluded.
    pub error_texels: Spread,
    /// `|z - z_exact|` of the hit's depth below the top plane, in texels (depth in uv times the map width).
    pub depth_error_texels: Spread,
    /// Fraction of error rays whose hit is more than one texel from the exact hit.
    pub gross_rate: f64,
    /// Fraction of error rays that ran out of iterations.
    pub capped_rate: f64,
    /// Error rays whose hit was not finite.
    pub nan_pixels: usize,
    /// Iterations of the error trace's rays.
    pub steps: StepStats,
    /// Texel fetches of the error trace's rays (the method's trace: height map, pyramid and
    /// method map; a gather is one), counted by the shader in an untimed trace. Absent
    /// (zeros) in files from before fetches were counted.
    #[serde(default)]
    pub fetches: StepStats,
    /// Compute shader invocations of one timed frame (every frame's dispatches), as the device
    /// counts them (pipeline statistics); absent where it cannot, and in older files.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub compute_invocations: Option<u64>,
    /// Iterations of the timed rays, and what their subgroups paid.
    pub timed_steps: TimedSteps,
}

/// Time to build one precomputed map.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct MapBuild {
    /// Which map: the [`crate::method::MapKind`]'s name.
    pub kind: String,
    /// The height field's name.
    pub heightfield: String,
    /// Map width and height, in texels.
    pub size: [u32; 2],
    /// GPU ms for maps built on the GPU, CPU wall ms for those built on the CPU.
    pub ms: f64,
    /// Which builder built it: "gpu" or "cpu".
    pub on: String,
}

/// One cell of the stability matrix: a method on a named stiff case.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StabilityCell {
    /// The method's name.
    pub method: String,
    /// The stiff case's name.
    pub case: String,
    /// Rays whose hit was not finite.
    pub nan_pixels: usize,
    /// Fraction of rays that ran out of iterations.
    pub capped_rate: f64,
    /// Fraction of rays more than one texel from the exact hit.
    pub gross_rate: f64,
    /// Largest hit error, in texels (see [`Run::error_texels`]).
    #[serde(deserialize_with = "super::nan_null::f64_or_nan")]
    pub max_error_texels: f64,
    /// The trace's GPU time (the fastest timed dispatch), in ms.
    pub gpu_ms: Option<f64>,
    /// Why the case could not run for this method (an error), if it could not.
    pub failed: Option<String>,
}

/// The whole of `results.json`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct BenchResults {
    /// [`SCHEMA_VERSION`] when written by this relief.
    pub schema_version: u32,
    /// The relief that measured: its version and commit.
    pub relief: ReliefBuild,
    /// When the run finished, UTC, RFC 3339 (`2026-12-04T17:42:41Z`).
    pub date: String,
    /// The GPU everything was measured on.
    pub device: BenchDevice,
    /// The command line that produced the file, its words joined by spaces (for reading).
    pub command: String,
    /// The same command line word by word, exactly as the process received it.
    pub argv: Vec<String>,
    /// The sweep's effective options, after defaults and flags.
    pub options: SweepOptions,
    /// Every measured configuration of the sweep.
    pub runs: Vec<Run>,
    /// Build time of every precomputed map the runs used.
    pub maps: Vec<MapBuild>,
    /// The stability matrix (empty when not run).
    pub stability: Vec<StabilityCell>,
    /// The shading section: shadow modes against the exact visible fraction.
    pub shadows: Vec<ShadowRun>,
    /// Shadow modes under extreme lights on degenerate fields.
    pub shadow_stability: Vec<ShadowStabilityCell>,
    /// The AO modes' maps against the exact AO, with their build times.
    pub ao: Vec<AoRun>,
    /// The level-of-detail section (`None` when skipped, e.g. `--no-lod`).
    pub lod: Option<super::lod::LodSection>,
    /// The terrain-edit section (empty when skipped, e.g. `--no-edits`).
    pub edits: Vec<super::edits::EditCost>,
    /// The weight-painting costs beside it (empty when skipped, e.g. `--no-edits`).
    pub paint_edits: Vec<super::paint_edits::PaintCost>,
    /// The terrain-blending section (`None` when skipped, e.g. `--no-blending`).
    pub blending: Option<super::blending::BlendingSection>,
    /// The scene-shadow section (`None` when skipped, e.g. `--no-scene-shadows`).
    pub scene_shadows: Option<super::scene_shadow_section::SceneShadowSection>,
    /// The frame-feature section (`None` when skipped, e.g. `--no-frame-features`; files
    /// written before it have none).
    #[serde(default)]
    pub frame_features: Option<super::frame_features::FrameFeatureSection>,
    /// The silhouette section (`None` when skipped, e.g. `--no-silhouettes`; files written
    /// before it have none).
    #[serde(default)]
    pub silhouettes: Option<super::silhouettes::SilhouetteSection>,
    /// The frame-cost section (`None` when skipped, e.g. `--no-frame-costs`; files written
    /// before it have none).
    #[serde(default)]
    pub frame_costs: Option<super::frame_costs::FrameCostSection>,
    /// Which shard of a split sweep this file holds (`relief bench --shard K/N`); absent for a
    /// whole sweep and for `relief bench merge`'s output.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub shard: Option<super::shard_info::ShardInfo>,
    /// The machine and its load while measuring; absent in files written before relief
    /// recorded it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub machine: Option<super::machine::BenchMachine>,
    /// The sections measured and why the others were left out; absent in files written before
    /// relief recorded it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sections: Option<super::sections_run::SectionsRun>,
    /// Each method's steps per ray at its first error-against-time configuration, drawn as
    /// `steps-<method>.png` beside the report; not kept in results.json (the run's `steps`
    /// summarise them).
    #[serde(skip)]
    pub steps_maps: Vec<super::steps_map::StepsMap>,
}

#[cfg(test)]
mod tests {
    use super::GpuMs;

    #[test]
    fn median_of_odd_and_even_counts() {
        assert_eq!(
            GpuMs::of(&[3.0, 1.0, 2.0]),
            GpuMs {
                median: 2.0,
                min: 1.0,
                max: 3.0,
                samples: vec![3.0, 1.0, 2.0],
            }
        );
        assert_eq!(GpuMs::of(&[4.0, 1.0, 2.0, 3.0]).median, 2.5);
        assert_eq!(GpuMs::of(&[]).max, 0.0);
    }
}
