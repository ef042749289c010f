//! `relief render`: a glTF scene or the built-in default scene to a PNG, with per-pass GPU times.

use std::path::PathBuf;

use anyhow::Context as _;
use clap::{Args, ValueEnum};
use relief::heightfield::Heightfield;
use relief::method::Method;
use relief::render::{render, Addressing, Frame, HeightFormat, RenderOptions};
use relief::scene::{default_heightfield, default_scene, load_gltf, Scene};
use serde_json::json;

use super::heightmap_args::HeightmapArgs;

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FormatArg {
    R16,
    R32f,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum AddressArg {
    Repeat,
    Clamp,
}

#[derive(Args)]
pub struct RenderArgs {
    /// glTF scene (.gltf or .glb); the built-in default scene when left out.
    scene: Option<PathBuf>,
    /// Output PNG.
    #[arg(long, default_value = "frame.png")]
    out: PathBuf,
    #[arg(long, default_value_t = 960)]
    width: u32,
    #[arg(long, default_value_t = 540)]
    height: u32,
    #[command(flatten)]
    heights: HeightmapArgs,
    /// Depth of height 0 below the surface, in uv units (0.05 = a twentieth of the texture).
    #[arg(long, value_name = "S")]
    depth_scale: Option<f32>,
    /// Displacement method id (see `relief methods`).
    #[arg(long, default_value = "pom")]
    method: String,
    /// Storage of heights on the GPU.
    #[arg(long, value_enum, default_value = "r16")]
    height_format: FormatArg,
    /// Height map addressing.
    #[arg(long, value_enum, default_value = "repeat")]
    address: AddressArg,
    /// Pick the Vulkan device whose name contains this text.
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
    /// Print one JSON object instead of the table.
    #[arg(long)]
    json: bool,
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
    let mut scene = load_gltf(path)?;
    if heights {
        scene.apply_relief(args.depth_scale.unwrap_or(DEFAULT_GLTF_DEPTH_SCALE), method);
    }
    Ok(scene)
}

pub fn run(args: &RenderArgs) -> anyhow::Result<()> {
    check_inputs(args)?;
    let method: Method = args.method.parse()?;
    let loaded = args.heights.load()?;
    let scene = build_scene(args, method, loaded.is_some())?;
    let ctx = super::open_device(args.device.as_deref(), args.json)?;
    let (heights, source) = match loaded {
        Some(pair) => pair,
        None if args.scene.is_none() => {
            (default_heightfield(), "built-in bricks 256x256".to_owned())
        }
        None => (Heightfield::new(1, 1, vec![1.0])?, "none (flat)".to_owned()),
    };
    heights.check_max_dimension(ctx.info().max_image_dimension_2d, &source)?;
    let opts = RenderOptions {
        width: args.width,
        height: args.height,
        height_format: match args.height_format {
            FormatArg::R16 => HeightFormat::R16Unorm,
            FormatArg::R32f => HeightFormat::R32Float,
        },
        address: match args.address {
            AddressArg::Repeat => Addressing::Repeat,
            AddressArg::Clamp => Addressing::Clamp,
        },
    };
    let frame = render(&ctx, &scene, &heights, &opts).context("rendering the frame")?;
    write_png(&frame, &args.out)?;
    super::check_validation(&ctx)?;
    report(args, &ctx, &frame, &source);
    Ok(())
}

fn write_png(frame: &Frame, out: &std::path::Path) -> anyhow::Result<()> {
    if let Some(dir) = out.parent().filter(|d| !d.as_os_str().is_empty()) {
        std::fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    }
    image::save_buffer(
        out,
        &frame.rgba,
        frame.width,
        frame.height,
        image::ColorType::Rgba8,
    )
    .with_context(|| format!("writing {}", out.display()))
}

fn report(args: &RenderArgs, ctx: &relief::vk::Context, frame: &Frame, source: &str) {
    if args.json {
        let value = json!({
            "device": ctx.info(),
            "out": args.out,
            "width": frame.width,
            "height": frame.height,
            "method": args.method,
            "heightmap": source,
            "upload_ms": frame.upload_ms,
            "passes": frame.timings,
        });
        println!("{value}");
        return;
    }
    println!("{:<10} {:>9}", "pass", "gpu_ms");
    for t in &frame.timings {
        println!("{:<10} {:>9.3}", t.pass, t.gpu_ms);
    }
    eprintln!(
        "wrote {} ({}x{}, method {}, heights: {source})",
        args.out.display(),
        frame.width,
        frame.height,
        args.method
    );
}
