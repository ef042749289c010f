//! `relief render`: a glTF scene or the built-in default scene to a PNG, with per-pass GPU times.

use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use relief::render::Renderer;

use super::exr_out::is_exr;
use super::pipeline_cache::{self, CacheArgs};
use super::render_frames::{run_frames, CacheReport, FrameArgs};
use super::scene_args::SceneArgs;
use super::terrain_edits::TerrainEdits;

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Output PNG, or OpenEXR (FILE.exr: the channels --exr-out writes); with --frames N > 1,
    /// frame k is written as STEM_000k.png (.exr) beside it.
    #[arg(long, default_value = "frame.png")]
    pub(super) out: PathBuf,
    /// Also write each frame's linear radiance (before exposure and tone mapping) as a
    /// Radiance .hdr file, named like the PNGs.
    #[arg(long, value_name = "FILE.hdr")]
    pub(super) hdr_out: Option<PathBuf>,
    /// Also write each frame as an OpenEXR file, named like the PNGs: the linear radiance (R, G,
    /// B, A) and the surface pass's G-buffer: Z (linear view depth of the displaced hit, along the
    /// camera's axis; infinite where nothing was drawn), P.X, P.Y, P.Z (world position,
    /// unprojected from Z), N.X, N.Y, N.Z (world shading normal), coverage, uv.U, uv.V (texture
    /// coordinates at the hit), id (scene mesh index + 1, 0 for none) and steps (the view ray's
    /// steps through its height field). The header holds the camera.
    #[arg(long, value_name = "FILE.exr")]
    pub(super) exr_out: Option<PathBuf>,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub(super) json: bool,
    /// Print the plan (pipelines, maps, passes, what was skipped and why) as one JSON object.
    #[arg(long)]
    pub(super) explain: bool,
    #[command(flatten)]
    pub(super) frames: FrameArgs,
    #[command(flatten)]
    cache: CacheArgs,
}

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    check_hdr_out(args)?;
    check_exr_out(args)?;
    let mut loaded = args.scene.load()?;
    let ctx = super::open_device(args.scene.device.as_deref(), args.json)?;
    loaded.check_device(&ctx)?;
    if let (true, Some(why)) = (args.frames.frames > 1, &ctx.info().known_frame_leak) {
        eprintln!(
            "relief: warning: {why}; {} frames will grow this process's memory accordingly \
             (scripts/setup.sh upgrades lavapipe)",
            args.frames.frames
        );
    }
    let mut opts = args
        .scene
        .render_options(args.scene.width, args.scene.height);
    let exr = args.exr_out.is_some() || is_exr(&args.out);
    opts.keep_radiance = args.hdr_out.is_some() || exr;
    opts.gbuffer = exr;
    opts.paintable_layers = loaded
        .edits
        .as_ref()
        .is_some_and(TerrainEdits::needs_painter);
    let cache = args.cache.file(&ctx);
    let seeded = pipeline_cache::seed(&ctx, cache.as_deref());
    let before = ctx.created();
    let mut renderer = Renderer::new(&ctx, &loaded.scene, loaded.heights.as_ref(), &opts)
        .context("preparing the scene for rendering")?;
    let msaa = &renderer.plan().msaa;
    if let Some(why) = &msaa.reduced {
        eprintln!(
            "relief: --msaa {}: {why}; drawing {} sample(s) per pixel",
            msaa.asked, msaa.samples
        );
    }
    if let Some(edits) = &mut loaded.edits {
        edits.check_renderer(&renderer)?;
    }
    let cache_report = CacheReport {
        path: cache.clone(),
        seeded,
        pipelines: ctx.created() - before,
    };
    run_frames(
        args,
        &ctx,
        &mut renderer,
        &mut loaded,
        before,
        &cache_report,
    )?;
    super::check_validation(&ctx)?;
    if let Some(path) = &cache {
        pipeline_cache::persist(&ctx, path);
    }
    Ok(())
}

fn check_exr_out(args: &RenderArgs) -> anyhow::Result<()> {
    if is_exr(&args.out) && args.scene.supersampled() {
        return Err(super::usage(format!(
            "--out {} reads the G-buffer at the frame's size, one entry per pixel; leave out --supersample",
            args.out.display()
        )));
    }
    let Some(path) = &args.exr_out else {
        return Ok(());
    };
    if !is_exr(path) {
        return Err(super::usage(format!(
            "--exr-out writes OpenEXR files; {} does not end in .exr",
            path.display()
        )));
    }
    if args.frames.no_write {
        return Err(super::usage(
            "--exr-out writes the frames' channels; leave out --no-write",
        ));
    }
    if args.scene.supersampled() {
        return Err(super::usage(
            "--exr-out reads the G-buffer at the frame's size, one entry per pixel; leave out --supersample",
        ));
    }
    Ok(())
}

fn check_hdr_out(args: &RenderArgs) -> anyhow::Result<()> {
    let Some(path) = &args.hdr_out else {
        return Ok(());
    };
    let hdr = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("hdr"));
    if !hdr {
        return Err(super::usage(format!(
            "--hdr-out writes Radiance .hdr files; {} does not end in .hdr",
            path.display()
        )));
    }
    if args.frames.no_write {
        return Err(super::usage(
            "--hdr-out writes the frames' radiance; leave out --no-write",
        ));
    }
    Ok(())
}
