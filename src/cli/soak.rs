//! `relief soak`: a long run of frames of one scene with an orbiting camera, judged by whether
//! the process's resident memory or the context's live Vulkan objects grow (a line fitted to
//! samples after a warm-up). It exits 1 naming what grew, so a driver or a change that leaks can
//! be caught on any machine, for as many frames as one cares to wait for.

use std::path::PathBuf;

use anyhow::Context as _;
use relief::bench::soak::{growth, judge, sample, samples_csv, Limits, Sample, MIN_FITTED_SAMPLES};
use relief::render::{FrameRequest, Renderer};

use super::frame_progress::FrameProgress;
use super::scene_args::SceneArgs;
use super::usage;

#[derive(clap::Args)]
pub struct SoakArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Frames to draw.
    #[arg(long, default_value_t = 2000)]
    frames: u32,
    /// Sample memory and live objects every this many retired frames.
    #[arg(long, default_value_t = 50)]
    every: u32,
    /// Frames left out of the fit while allocators and caches settle.
    #[arg(long, default_value_t = 200)]
    warm_up: u32,
    /// Resident bytes a frame may add on the fitted line before the soak fails.
    #[arg(long, default_value_t = 16384.0)]
    rss_per_frame: f64,
    /// Degrees the camera turns around the scene each frame.
    #[arg(long, default_value_t = 1.5)]
    turn: f32,
    /// Also write the samples here, as CSV.
    #[arg(long)]
    csv: Option<PathBuf>,
}

pub fn run(args: &SoakArgs) -> anyhow::Result<()> {
    check(args)?;
    let loaded = args.scene.load()?;
    let ctx = super::open_device(args.scene.device.as_deref(), false)?;
    if let Some(why) = &ctx.info().known_frame_leak {
        eprintln!(
            "relief: warning: {why}; this soak will find it (scripts/setup.sh upgrades lavapipe)"
        );
    }
    loaded.check_device(&ctx)?;
    let opts = args
        .scene
        .render_options(args.scene.width, args.scene.height);
    let mut renderer = Renderer::new(&ctx, &loaded.scene, loaded.heights.as_ref(), &opts)
        .context("preparing the scene for rendering")?;
    let centre = loaded
        .scene
        .bounds()
        .map_or(glam::Vec3::ZERO, |(lo, hi)| 0.5 * (lo + hi));
    let start = renderer.default_camera();
    let mut progress = FrameProgress::new(args.frames, false);
    let mut samples = Vec::new();
    let mut retired = 0u32;
    for k in 0..args.frames {
        let camera = start.orbited(centre, (args.turn * k as f32).to_radians());
        let frame = renderer.submit(&FrameRequest::new(camera).with_read_back(false))?;
        if frame.is_some() {
            retired += 1;
            if retired % args.every == 0 {
                samples.push(sample(&ctx, retired).context("reading /proc/self/status")?);
            }
        }
        progress.advance();
    }
    renderer.finish()?;
    progress.finish();
    report(args, &samples)?;
    let limits = Limits {
        warm_up: args.warm_up,
        rss_per_frame: args.rss_per_frame,
    };
    let errors = ctx.messages().errors();
    if errors > 0 {
        anyhow::bail!("the Vulkan validation layer reported {errors} error(s); see the log above");
    }
    judge(&samples, limits).map_err(|why| anyhow::anyhow!("the frames leak: {why}"))
}

/// Refuses a run too short to fit a line after its warm-up.
fn check(args: &SoakArgs) -> anyhow::Result<()> {
    if args.every == 0 {
        return Err(usage("--every must be at least 1"));
    }
    let fitted = args.frames.saturating_sub(args.warm_up.max(1)) / args.every;
    if (fitted as usize) < MIN_FITTED_SAMPLES {
        return Err(usage(format!(
            "--frames {} with --warm-up {} and --every {} leaves {fitted} sample(s) to fit; at \
             least {MIN_FITTED_SAMPLES} are needed",
            args.frames, args.warm_up, args.every
        )));
    }
    if !(args.rss_per_frame.is_finite() && args.rss_per_frame >= 0.0) {
        return Err(usage(
            "--rss-per-frame must be a finite number of bytes, 0 or more",
        ));
    }
    args.scene.check()
}

/// Prints the first and last samples and the fitted growth; writes the CSV when asked.
fn report(args: &SoakArgs, samples: &[Sample]) -> anyhow::Result<()> {
    for s in [samples.first(), samples.last()].into_iter().flatten() {
        println!("{s}");
    }
    let growth = growth(samples, args.warm_up).unwrap_or_default();
    let moved: Vec<String> = growth
        .iter()
        .filter(|&&(name, per_frame)| name == "rss" || per_frame != 0.0)
        .map(|(name, per_frame)| format!("{name} {per_frame:+.3}"))
        .collect();
    let nothing_else = if moved.len() == 1 {
        "; no Vulkan object or allocation"
    } else {
        ""
    };
    println!(
        "growth a frame after {} warm-up frames (fitted): {}{nothing_else}",
        args.warm_up,
        moved.join(", ")
    );
    if let Some(path) = &args.csv {
        std::fs::write(path, samples_csv(samples))
            .with_context(|| format!("writing the samples to {}", path.display()))?;
        println!("samples: {}", path.display());
    }
    Ok(())
}
