//! `relief render`: a glTF scene or the built-in default scene to a PNG, with per-pass GPU times;
//! several scenes, or every camera of one, as a batch (`render_batch`).

use std::sync::Arc;

use anyhow::Context as _;
use clap::Args;
use relief::render::Renderer;
use relief::vk::Context;

use super::frame_files::FileArgs;
use super::pipeline_cache::{self, CacheArgs};
use super::render_batch;
use super::render_frames::{run_frames, CacheReport, FrameArgs, SceneSummary};
use super::scene_args::{LoadedScene, SceneArgs};
use super::terrain_edits::TerrainEdits;

#[derive(Args)]
pub struct RenderArgs {
    #[command(flatten)]
    pub(super) scene: SceneArgs,
    #[command(flatten)]
    pub(super) files: FileArgs,
    /// Print one JSON object instead of the table (a batch: one per scene, then its summary).
    #[arg(long)]
    pub(super) json: bool,
    /// Print the plan (pipelines, maps, passes, what was skipped and why) as one JSON object.
    #[arg(long)]
    pub(super) explain: bool,
    #[command(flatten)]
    pub(super) frames: FrameArgs,
    /// In a batch (several scenes, or --camera all), stop at the first scene that fails; by
    /// default every scene is drawn and the run exits 1 at the end if any failed.
    #[arg(long, conflicts_with = "keep_going")]
    fail_fast: bool,
    /// In a batch, draw every scene even when one fails (the default; for scripts that say so).
    #[arg(long)]
    keep_going: bool,
    #[command(flatten)]
    cache: CacheArgs,
}

impl RenderArgs {
    /// Whether a batch stops at its first failing scene.
    pub fn fail_fast(&self) -> bool {
        self.fail_fast && !self.keep_going
    }
}

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    args.files
        .check(args.frames.no_write, args.scene.supersampled())?;
    args.scene.check()?;
    render_batch::run(args)
}

/// Opens the device `--device` names, with the warnings a sequence of frames needs.
pub fn open_device(args: &RenderArgs) -> anyhow::Result<Arc<Context>> {
    let ctx = super::open_device(args.scene.device.as_deref(), args.json)?;
    if let (true, Some(why)) = (args.frames.frames > 1, &ctx.info().known_frame_leak) {
        eprintln!(
            "relief: warning: {why}; {} frames will grow this process's memory accordingly \
             (scripts/setup.sh upgrades lavapipe)",
            args.frames.frames
        );
    }
    Ok(ctx)
}

/// Draws one loaded scene's frames into `files`.
pub fn render_scene(
    args: &RenderArgs,
    ctx: &Arc<Context>,
    loaded: &mut LoadedScene,
    files: &FileArgs,
) -> anyhow::Result<SceneSummary> {
    loaded.check_device(ctx)?;
    let mut opts = args
        .scene
        .render_options(args.scene.width, args.scene.height);
    opts.keep_radiance = files.needs_radiance();
    opts.gbuffer = files.needs_gbuffer();
    opts.count_work = args.frames.count_work || !files.cost_map.is_empty();
    opts.paintable_layers = loaded
        .edits
        .as_ref()
        .is_some_and(TerrainEdits::needs_painter);
    let errors_before = ctx.messages().errors();
    let cache = args.cache.file(ctx);
    let seeded = pipeline_cache::seed(ctx, cache.as_deref());
    let before = ctx.created();
    let mut renderer = Renderer::new(ctx, &loaded.scene, loaded.heights.as_ref(), &opts)
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
    let summary = run_frames(
        args,
        files,
        ctx,
        &mut renderer,
        loaded,
        before,
        &cache_report,
    )?;
    let errors = ctx.messages().errors() - errors_before;
    if errors > 0 {
        anyhow::bail!("the Vulkan validation layer reported {errors} error(s); see the log above");
    }
    if let Some(path) = &cache {
        pipeline_cache::persist(ctx, path);
    }
    Ok(summary)
}
