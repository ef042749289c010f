//! `relief render`: a glTF scene or the built-in default scene to a PNG, with per-pass GPU times.

use std::path::PathBuf;

use anyhow::Context as _;
use clap::{Args, ValueEnum};
use relief::heightfield::Address;
use relief::method::Method;
use relief::render::{HeightFormat, RenderOptions, Renderer};
use relief::scene::{
    default_heightfield, default_scene, load_gltf, Scene, SceneOptions, DEFAULT_SCENE_METHOD,
};

use super::heightmap_args::HeightmapArgs;
use super::lod_args::LodArgs;
use super::pipeline_cache;
use super::render_frames::{run_frames, CacheReport, FrameArgs};
use super::shading_args::ShadingArgs;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FormatArg {
    R16,
    R32f,
}

#[derive(Args)]
pub struct RenderArgs {
    /// glTF scene (.gltf or .glb); the built-in default scene when left out.
    scene: Option<PathBuf>,
    /// Output PNG; with --frames N > 1, frame k is written as STEM_000k.png beside it.
    #[arg(long, default_value = "frame.png")]
    pub(super) out: PathBuf,
    #[arg(long, default_value_t = 960)]
    width: u32,
    #[arg(long, default_value_t = 540)]
    height: u32,
    #[command(flatten)]
    heights: HeightmapArgs,
    #[command(flatten)]
    shading: ShadingArgs,
    /// Depth of height 0 below the surface, in uv units (0.05 = a twentieth of the texture).
    #[arg(long, value_name = "S")]
    depth_scale: Option<f32>,
    /// Displacement method id (see `relief methods`) for the default scene (default qdm) and for
    /// materials given relief by --heightmap (default pom).
    #[arg(long)]
    method: Option<String>,
    /// Which materials --heightmap displaces: a material name, or `all`.
    #[arg(long, value_name = "NAME|all", default_value = "all")]
    material: String,
    /// Which scene of the glTF file (default: the file's default scene).
    #[arg(long = "scene", value_name = "N")]
    scene_index: Option<usize>,
    /// Which camera of the scene, in node order (default: the first; none frames the scene).
    #[arg(long, value_name = "N")]
    camera: Option<usize>,
    /// Storage of heights on the GPU.
    #[arg(long, value_enum, default_value = "r16")]
    height_format: FormatArg,
    /// Height map addressing.
    #[arg(long, value_name = "repeat|clamp", default_value_t = Address::Repeat)]
    address: Address,
    /// Pick the Vulkan device whose name contains this text.
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    pub(super) json: bool,
    /// Print the plan (pipelines, maps, passes, what was skipped and why) as one JSON object.
    #[arg(long)]
    pub(super) explain: bool,
    #[command(flatten)]
    pub(super) frames: FrameArgs,
    #[command(flatten)]
    lod: LodArgs,
    /// Where compiled pipelines are kept between runs (default: relief/pipelines-VENDOR-DEVICE.bin
    /// under $XDG_CACHE_HOME or ~/.cache).
    #[arg(long, value_name = "PATH")]
    pipeline_cache: Option<PathBuf>,
    /// Neither read nor write a pipeline cache file.
    #[arg(long, conflicts_with = "pipeline_cache")]
    no_pipeline_cache: bool,
}

const DEFAULT_GLTF_DEPTH_SCALE: f32 = 0.05;
const MAX_SIDE: u32 = 16384;

fn check_inputs(args: &RenderArgs) -> anyhow::Result<()> {
    if args.width == 0 || args.height == 0 || args.width > MAX_SIDE || args.height > MAX_SIDE {
        anyhow::bail!(
            "--width and --height must be within 1..={MAX_SIDE}, got {}x{}",
            args.width,
            args.height
        );
    }
    if let Some(s) = args.depth_scale {
        if !(s.is_finite() && s > 0.0) {
            anyhow::bail!("--depth-scale must be a finite number above 0, got {s}");
        }
    }
    Ok(())
}

fn build_scene(args: &RenderArgs, method: Method, heights: bool) -> anyhow::Result<Scene> {
    let Some(path) = &args.scene else {
        let mut scene = default_scene(method);
        if let Some(s) = args.depth_scale {
            scene
                .materials
                .iter_mut()
                .filter_map(|m| m.relief.as_mut())
                .for_each(|r| r.depth_scale = s);
        }
        return Ok(scene);
    };
    let options = SceneOptions {
        scene: args.scene_index,
        camera: args.camera,
    };
    let mut scene = load_gltf(path, &options)?;
    let filter = (args.material != "all").then_some(args.material.as_str());
    if heights {
        let depth = args.depth_scale.unwrap_or(DEFAULT_GLTF_DEPTH_SCALE);
        if scene.apply_relief(depth, method, filter) == 0 {
            let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
            anyhow::bail!(
                "--material {:?} names no material of {}; its materials: {}",
                args.material,
                path.display(),
                names.join(", ")
            );
        }
    } else if filter.is_some() {
        anyhow::bail!(
            "--material chooses which materials --heightmap displaces; give --heightmap FILE"
        );
    }
    Ok(scene)
}

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    check_inputs(args)?;
    let method: Method = match &args.method {
        Some(id) => id.parse()?,
        None if args.scene.is_none() => DEFAULT_SCENE_METHOD,
        None => Method::POM,
    };
    let loaded = args.heights.load()?;
    let mut scene = build_scene(args, method, loaded.is_some())?;
    args.shading.apply(&mut scene)?;
    args.lod.apply(&mut scene)?;
    let ctx = super::open_device(args.device.as_deref(), args.json)?;
    let (heights, source) = match loaded {
        Some((hf, source)) => (Some(hf), source),
        None if args.scene.is_none() => (
            Some(default_heightfield()),
            "built-in bricks 256x256".to_owned(),
        ),
        None => (None, "the scene's own".to_owned()),
    };
    if let Some(hf) = &heights {
        hf.check_max_dimension(ctx.info().max_image_dimension_2d, &source)?;
    }
    let opts = RenderOptions {
        width: args.width,
        height: args.height,
        height_format: match args.height_format {
            FormatArg::R16 => HeightFormat::R16Unorm,
            FormatArg::R32f => HeightFormat::R32Float,
        },
        address: args.address,
    };
    let cache = cache_file(args, &ctx);
    let seeded = seed_pipeline_cache(&ctx, cache.as_deref());
    let before = ctx.created();
    let mut renderer = Renderer::new(&ctx, &scene, heights.as_ref(), &opts)
        .context("preparing the scene for rendering")?;
    let cache_report = CacheReport {
        path: cache.clone(),
        seeded,
        pipelines: ctx.created() - before,
    };
    run_frames(
        args,
        &ctx,
        &mut renderer,
        &scene,
        before,
        &source,
        &cache_report,
    )?;
    super::check_validation(&ctx)?;
    if let Some(path) = &cache {
        persist_pipeline_cache(&ctx, path);
    }
    Ok(())
}

/// The pipeline cache file this run reads and writes, if any.
fn cache_file(args: &RenderArgs, ctx: &relief::vk::Context) -> Option<PathBuf> {
    if args.no_pipeline_cache {
        return None;
    }
    args.pipeline_cache
        .clone()
        .or_else(|| pipeline_cache::default_path(ctx.info()))
}

/// Merges the cache file into the context's pipeline cache; whether it was used. A missing file
/// is a first run; an unreadable, corrupt or foreign one is ignored with a warning.
fn seed_pipeline_cache(ctx: &relief::vk::Context, path: Option<&std::path::Path>) -> bool {
    let Some(bytes) = path.and_then(pipeline_cache::load) else {
        return false;
    };
    match ctx.merge_pipeline_cache(&bytes) {
        Ok(seeded) => seeded,
        Err(e) => {
            log::warn!("ignoring the pipeline cache: {e}");
            false
        }
    }
}

/// Writes the pipeline cache back; a failure costs the next run its head start, not this one.
fn persist_pipeline_cache(ctx: &relief::vk::Context, path: &std::path::Path) {
    let saved = ctx
        .pipeline_cache_data()
        .map_err(anyhow::Error::from)
        .and_then(|bytes| pipeline_cache::save(path, &bytes));
    if let Err(e) = saved {
        log::warn!(
            "could not save the pipeline cache to {}: {e:#}",
            path.display()
        );
    }
}
