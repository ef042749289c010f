//! Argument parsing (clap), logging, and the mapping of failures to exit codes: 0 success,
//! 1 failure (a batch of `relief render` with any failed scene too), 2 bad usage (clap), 3 `bench compare --fail-above` found a slower cell, 77 no
//! Vulkan device (with the install line).

mod ao;
mod aov;
mod bench;
mod bench_args;
mod bench_compare;
mod bench_gate;
mod bench_merge;
mod bench_runs;
mod bench_sections;
mod bench_shard;
mod camera_sidecar;
mod cells;
mod cells_compare;
mod cells_lookup;
mod cells_render_args;
mod cost_map;
mod devices;
mod exr_out;
mod frame_encoders;
mod frame_files;
mod frame_progress;
mod frame_range;
mod heightmap_args;
mod lod_args;
mod logger;
mod maps;
mod methods;
mod occlusion;
mod pipeline_cache;
mod reference_args;
mod render;
mod render_batch;
mod render_frames;
mod scene_args;
mod shading_args;
mod shadow_map_args;
mod shadows;
mod soak;
mod terrain_args;
mod terrain_edits;
mod trace;
#[cfg(feature = "window")]
mod view;

use std::process::ExitCode;

use clap::{Parser, Subcommand};
use relief::heightfield::MAX_SIDE;
use relief::vk::{Context, ContextOptions, VkError};

/// Exit code when no Vulkan device (or loader) exists, as automake's "skipped".
pub const EXIT_NO_DEVICE: u8 = 77;

#[derive(Parser)]
#[command(
    name = "relief",
    version,
    about = "Per-pixel displacement mapping on Vulkan: render, measure, compare"
)]
struct Cli {
    /// More log output (-v info, -vv debug).
    #[arg(short, long, action = clap::ArgAction::Count, global = true)]
    verbose: u8,
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Build a height field's ambient-occlusion map on the GPU and measure it against the exact reference.
    Ao(ao::AoArgs),
    /// Time every method and measure its error against the exact reference; write a report.
    Bench(bench_args::BenchArgs),
    /// Replace a closed mesh by a cubic cell complex with distance maps (Apaza and Andujar) and measure its hits.
    Cells(cells::CellsArgs),
    /// List the Vulkan devices relief can use, best first.
    Devices(devices::DevicesArgs),
    /// Render a glTF scene (or the built-in default scene) to a PNG, offscreen.
    Render(render::RenderArgs),
    /// Build a height map's max pyramid on the GPU and write every level as a PNG.
    Maps(maps::MapsArgs),
    /// List the displacement methods (ids are stable).
    Methods(methods::MethodsArgs),
    /// Check scene shadows: a frame's visible fraction of the light per pixel against the exact scene reference.
    Shadows(shadows::ShadowsArgs),
    /// Draw a scene's frames for a long time and fail if memory or live Vulkan objects grow.
    Soak(soak::SoakArgs),
    /// Ambient occlusion from the whole scene by ray query, against a brute-force CPU reference
    /// on the same rays (needs ray queries).
    Occlusion(occlusion::OcclusionArgs),
    /// Trace parallel rays on the GPU with one method and measure them against the exact reference.
    Trace(trace::TraceArgs),
    /// Show a scene in a window: orbit or fly, switch methods, shadows, AO and LOD, read GPU times.
    #[cfg(feature = "window")]
    View(view::ViewArgs),
}

/// A bad value or a bad combination of flags, found before any device is made: it exits 2, as
/// the argument parser's own refusals do.
#[derive(Debug, thiserror::Error)]
#[error("{0}")]
pub struct UsageError(pub String);

/// A [`UsageError`] saying `message`.
pub fn usage(message: impl Into<String>) -> anyhow::Error {
    UsageError(message.into()).into()
}

/// The exit code of bad usage, as clap's.
const EXIT_USAGE: u8 = 2;

/// Runs the tool and turns any error into one line on stderr and an exit code.
pub fn run() -> ExitCode {
    let cli = Cli::parse();
    logger::init(cli.verbose);
    let result = match cli.command {
        Command::Ao(args) => ao::run(&args),
        Command::Bench(args) => bench::run(&args),
        Command::Cells(args) => cells::run(&args),
        Command::Devices(args) => devices::run(&args),
        Command::Render(args) => render::run(&args),
        Command::Maps(args) => maps::run(&args),
        Command::Methods(args) => methods::run(&args),
        Command::Shadows(args) => shadows::run(&args),
        Command::Soak(args) => soak::run(&args),
        Command::Occlusion(args) => occlusion::run(&args),
        Command::Trace(args) => trace::run(&args),
        #[cfg(feature = "window")]
        Command::View(args) => view::run(&args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(err) => {
            eprintln!("relief: error: {}", error_message(&err));
            ExitCode::from(exit_code(&err))
        }
    }
}

/// The error and its causes joined by ": ", each cause said once: a cause whose text the
/// message already holds (an error that prints its source as part of its own text) is left
/// out.
fn error_message(err: &anyhow::Error) -> String {
    let mut message = String::new();
    for cause in err.chain() {
        let text = cause.to_string();
        if message.is_empty() {
            message = text;
        } else if !message.contains(&text) {
            message.push_str(": ");
            message.push_str(&text);
        }
    }
    message
}

/// The exit code for a failure: 77 when there is no Vulkan device at all, 3 when `bench compare
/// --fail-above` found a cell slower than allowed, 2 for bad usage found after parsing, else 1 (a lost or hung device and exhausted
/// memory included: the device exists, the run failed).
fn exit_code(err: &anyhow::Error) -> u8 {
    if err.is::<bench_compare::SlowerThanAllowed>() {
        return bench_compare::EXIT_SLOWER;
    }
    if err.chain().any(|e| e.is::<UsageError>()) {
        return EXIT_USAGE;
    }
    let no_device = err.chain().any(|e| {
        matches!(
            e.downcast_ref::<VkError>(),
            Some(VkError::NoDevice | VkError::Loader(_))
        )
    });
    if no_device {
        EXIT_NO_DEVICE
    } else {
        1
    }
}

/// Creates the device context for `--device`, printing which device was chosen to stderr.
pub fn open_device(filter: Option<&str>, quiet: bool) -> anyhow::Result<std::sync::Arc<Context>> {
    let options = ContextOptions::default().with_device_filter(filter.map(str::to_owned));
    let ctx = Context::new(&options)?;
    if !quiet {
        eprintln!("device: {}", ctx.describe());
    }
    Ok(ctx)
}

/// An image size `WxH` given to `flag`, each side within 1..=[`MAX_SIDE`].
pub fn parse_size(flag: &str, text: &str) -> anyhow::Result<(u32, u32)> {
    match parse_wxh(text) {
        Some((w, h)) if within_max_side(w, h) => Ok((w, h)),
        _ => anyhow::bail!("{flag} must be WxH within 1..={MAX_SIDE}, got {text:?}"),
    }
}

/// The two numbers of `WxH` (an image size, a grid of rays), whatever their range; `None` unless
/// both parse.
pub fn parse_wxh(text: &str) -> Option<(u32, u32)> {
    let (w, h) = text.split_once('x')?;
    Some((w.parse().ok()?, h.parse().ok()?))
}

/// Whether a `w` x `h` image has both sides within 1..=[`MAX_SIDE`].
pub fn within_max_side(w: u32, h: u32) -> bool {
    (1..=MAX_SIDE).contains(&w) && (1..=MAX_SIDE).contains(&h)
}

/// Fails if the validation layer reported errors while the command ran.
pub fn check_validation(ctx: &Context) -> anyhow::Result<()> {
    let errors = ctx.messages().errors();
    if errors > 0 {
        anyhow::bail!("the Vulkan validation layer reported {errors} error(s); see the log above");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief::vk::raw;

    #[test]
    fn gpu_failures_exit_with_1_and_a_missing_device_with_77() {
        let failures = [
            VkError::Hang {
                what: "the frame".into(),
                seconds: 600.0,
            },
            VkError::DeviceLost {
                call: "vkQueueSubmit",
            },
            VkError::from_call("vkAllocateMemory", raw::Result::ERROR_OUT_OF_DEVICE_MEMORY),
            VkError::from_call("vkCreateFence", raw::Result::ERROR_OUT_OF_HOST_MEMORY),
        ];
        for e in failures {
            let err = anyhow::Error::from(e).context("rendering");
            assert_eq!(exit_code(&err), 1, "{err:#}");
        }
        let err = anyhow::Error::from(VkError::NoDevice).context("opening the device");
        assert_eq!(exit_code(&err), EXIT_NO_DEVICE);
    }

    #[test]
    fn each_cause_is_said_once() {
        let io = std::io::Error::new(std::io::ErrorKind::NotFound, "No such file or directory");
        // An error whose own text carries its source, as thiserror's "{0}" messages do.
        #[derive(Debug, thiserror::Error)]
        #[error("scene \"missing.gltf\": {0}")]
        struct Wrapping(#[source] std::io::Error);
        let err = anyhow::Error::from(Wrapping(io)).context("loading the scene");
        assert_eq!(
            error_message(&err),
            "loading the scene: scene \"missing.gltf\": No such file or directory"
        );
        let plain = anyhow::anyhow!("the cause").context("the step");
        assert_eq!(error_message(&plain), "the step: the cause");
    }

    #[test]
    fn a_comparison_over_its_limit_exits_with_3() {
        let err = anyhow::Error::from(bench_compare::SlowerThanAllowed::example());
        assert_eq!(exit_code(&err), bench_compare::EXIT_SLOWER);
        assert_eq!(exit_code(&anyhow::anyhow!("reading BASE")), 1);
    }
}
