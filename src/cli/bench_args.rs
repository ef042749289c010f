//! `relief bench`'s flags and subcommands, parsed by clap; src/cli/bench.rs runs them.

use std::path::PathBuf;

use clap::{Args, Subcommand};
use relief::bench::{Shard, SlowDown};
use relief::heightfield::{Address, Generator};

use super::bench_merge::MergeArgs;
use super::scene_args::FormatArg;

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct BenchArgs {
    #[command(subcommand)]
    pub(super) command: Option<BenchCommand>,
    /// Folder for results.json, report.md and the SVG plots.
    #[arg(long, required = true)]
    pub(super) out: Option<PathBuf>,
    /// Small sweep for CI (a few minutes on lavapipe).
    #[arg(long)]
    pub(super) quick: bool,
    /// Sections to run, comma-separated: main, stability, shading, lod, edits, blending,
    /// scene-shadows, frame-features, silhouettes, frame-costs. Without it every section runs,
    /// or, when --methods, --fields, --heightmap, --sizes, --angles, --azimuths, --depth-scales
    /// or --budgets narrow the sweep, only those they narrow (main, stability, blending). The
    /// --no-X and --X-only flags apply on top.
    #[arg(long, value_enum, value_delimiter = ',')]
    pub(super) sections: Vec<super::bench_sections::SectionName>,
    /// Write the frame-cost section's frames as a timeline (trace-event JSON for
    /// ui.perfetto.dev and chrome://tracing): every renderer's host and GPU work on one clock,
    /// each span labelled with what its renderer drew. Needs the frame-cost section in the run.
    #[arg(long, value_name = "FILE.json")]
    pub(super) timeline: Option<PathBuf>,
    /// Method ids, comma-separated (default: all).
    #[arg(long, value_delimiter = ',')]
    pub(super) methods: Vec<String>,
    /// Synthetic fields, comma-separated (default fbm,bricks; quick: fbm).
    #[arg(long, value_delimiter = ',')]
    pub(super) fields: Vec<Generator>,
    /// A real height map to add (repeatable).
    #[arg(long)]
    pub(super) heightmap: Vec<PathBuf>,
    /// Map sides; the first is used by every section, all of them by the scaling section.
    #[arg(long, value_delimiter = ',')]
    pub(super) sizes: Vec<u32>,
    /// View elevations in degrees.
    #[arg(long, value_delimiter = ',')]
    pub(super) angles: Vec<f64>,
    /// Azimuths in degrees.
    #[arg(long, value_delimiter = ',')]
    pub(super) azimuths: Vec<f64>,
    /// Depth scales; the first is used by every section, all of them by the depth-scale one.
    #[arg(long, value_delimiter = ',')]
    pub(super) depth_scales: Vec<f64>,
    /// Iteration caps tried on fixed-step methods besides their defaults.
    #[arg(long, value_delimiter = ',')]
    pub(super) budgets: Vec<u32>,
    /// Size of the timed full-screen pass, WxH.
    #[arg(long)]
    pub(super) resolution: Option<String>,
    /// Timed frames per configuration.
    #[arg(long)]
    pub(super) frames: Option<u32>,
    /// Passes over the sweep that share each configuration's frames, so that a slow spell of
    /// the machine touches every method alike (default 3, never more than the frames).
    #[arg(long)]
    pub(super) passes: Option<u32>,
    /// Skip the stability matrix.
    #[arg(long)]
    pub(super) no_stability: bool,
    /// Run only the stability matrix (stiff and extreme cases, sparse spikes included).
    #[arg(long, conflicts_with_all = ["no_stability", "shading_only", "lod_only"])]
    pub(super) stability_only: bool,
    /// Skip the shading section (shadow modes against the exact visible fraction).
    #[arg(long)]
    pub(super) no_shading: bool,
    /// Run only the shading section.
    #[arg(long, conflicts_with = "no_shading")]
    pub(super) shading_only: bool,
    /// Run only the level-of-detail section (with --quick: its small version, seconds).
    #[arg(long, conflicts_with = "no_lod")]
    pub(super) lod_only: bool,
    /// Skip the level-of-detail section.
    #[arg(long)]
    pub(super) no_lod: bool,
    /// Skip the terrain-edit section (a brush stroke's partial rebuild against a full one, and a
    /// paint stroke's on a layered material's weights).
    #[arg(long)]
    pub(super) no_edits: bool,
    /// Field sides of the terrain-edit section (default 1024,4096; quick: 256,1024).
    #[arg(long, value_delimiter = ',', conflicts_with = "no_edits")]
    pub(super) edit_sizes: Vec<u32>,
    /// Skip the terrain-blending section (blended layers against a single field of their shape).
    #[arg(long)]
    pub(super) no_blending: bool,
    /// Skip the scene-shadow section (shadow maps: size x filter against the exact scene
    /// reference, and their cost in the default scene's frame).
    #[arg(long)]
    pub(super) no_scene_shadows: bool,
    /// Run only the scene-shadow section (with --quick: its small version).
    #[arg(long, conflicts_with = "no_scene_shadows")]
    pub(super) scene_shadows_only: bool,
    /// Skip the frame-feature section (what tone mapping, MSAA, supersampling and the sky's
    /// light add to the default scene's frame).
    #[arg(long)]
    pub(super) no_frame_features: bool,
    /// Run only the frame-feature section (with --quick: its small version).
    #[arg(long, conflicts_with = "no_frame_features")]
    pub(super) frame_features_only: bool,
    /// Skip the silhouette section (flat and curved relief on curved meshes against the
    /// displaced-geometry reference).
    #[arg(long)]
    pub(super) no_silhouettes: bool,
    /// Run only the silhouette section (with --quick: its small version).
    #[arg(long, conflicts_with = "no_silhouettes")]
    pub(super) silhouettes_only: bool,
    /// Skip the frame-cost section (the default look against the plain frame as a chain of
    /// ratios, three sizes, stacks of hidden relief quads, a still view's shadow maps).
    #[arg(long)]
    pub(super) no_frame_costs: bool,
    /// Run only the frame-cost section (with --quick: its small version).
    #[arg(long, conflicts_with = "no_frame_costs")]
    pub(super) frame_costs_only: bool,
    /// Also measure the silhouette section on the first mesh of this glTF file (its uv set 0
    /// carries the height map; seen from +z of its bounds).
    #[arg(long, value_name = "FILE.gltf", conflicts_with = "no_silhouettes")]
    pub(super) silhouette_mesh: Option<PathBuf>,
    #[arg(long, value_name = "repeat|clamp", default_value_t = Address::Repeat)]
    pub(super) address: Address,
    #[arg(long, value_enum, default_value = "r16")]
    pub(super) height_format: FormatArg,
    /// Print results.json to stdout and no progress.
    #[arg(long)]
    pub(super) json: bool,
    #[arg(long, value_name = "SUBSTRING")]
    pub(super) device: Option<String>,
    /// Measure only shard K of N (1 <= K <= N) of the sweep, split by expected cost; `relief bench
    /// merge` joins the shards' folders.
    #[arg(long, value_name = "K/N")]
    pub(super) shard: Option<Shard>,
    /// Testing only: dispatch METHOD's timed trace FACTOR times per frame, slowing it on purpose
    /// (recorded in the results' options); see docs/measuring.md.
    #[arg(long, value_name = "METHOD=FACTOR", hide = true)]
    pub(super) slow_down: Vec<SlowDown>,
}

/// What `relief bench` does besides measuring.
#[derive(Subcommand)]
pub(super) enum BenchCommand {
    /// Compare two results files cell by cell: time ratios with intervals, error changes, verdicts.
    Compare(super::bench_compare::CompareArgs),
    /// Join the folders of `relief bench --shard K/N` runs into one results.json and report.
    Merge(MergeArgs),
    /// The cost gate: count each method's steps on a fixed small sweep and fail when any grew
    /// beyond its tolerance over the baseline (assets/cost-gate.json); --update rewrites it.
    Gate(super::bench_gate::GateArgs),
}

pub(super) fn parse_resolution(text: &str) -> anyhow::Result<(u32, u32)> {
    super::parse_size("--resolution", text)
}
