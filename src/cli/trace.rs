//! `relief trace`: parallel rays over a grid traced on the GPU by one method, the hits dumped to
//! `.npy`, and one JSON line of error statistics against the exact reference.

use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use relief::bench::{ray_direction, trace_stats, write_npy_f32};
use relief::heightfield::{build_method_map, Address};
use relief::method::{Budget, Leaf, Method};
use relief::render::{trace_on_gpu, HeightFormat, TraceRequest};
use serde_json::json;

use super::heightmap_args::HeightmapArgs;
use super::render::FormatArg;

#[derive(Args)]
pub struct TraceArgs {
    #[command(flatten)]
    heights: HeightmapArgs,
    /// Method id (see `relief methods`).
    #[arg(long, default_value_t = Method::POM.id().to_owned())]
    method: String,
    /// View elevation in degrees: 90 looks straight down, 0 grazes.
    #[arg(long, default_value_t = 30.0)]
    angle: f64,
    /// Azimuth in degrees from +u toward +v.
    #[arg(long, default_value_t = 0.0)]
    azimuth: f64,
    /// Depth of height 0 below the top plane, in uv units.
    #[arg(long, default_value_t = 0.1)]
    depth_scale: f64,
    #[arg(long, value_name = "repeat|clamp", default_value_t = Address::Repeat)]
    address: Address,
    /// Ray grid, COLSxROWS; ray (c, r) enters at the cell centre.
    #[arg(long, default_value = "64x64")]
    grid: String,
    /// Iteration cap (the method's default when left out).
    #[arg(long)]
    budget: Option<u32>,
    /// Refinement steps (the method's default when left out).
    #[arg(long)]
    refine: Option<u32>,
    /// How methods with a leaf choice finish: the paper's refinement or the exact bilinear
    /// intersection (the method's default when left out; the others ignore it).
    #[arg(long, value_name = "paper|exact")]
    leaf: Option<Leaf>,
    #[arg(long, value_enum, default_value = "r16")]
    height_format: FormatArg,
    /// Write the traced rays to this .npy file, shape (rows, cols, 8).
    #[arg(long)]
    dump: Option<PathBuf>,
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
}

fn parse_grid(text: &str) -> anyhow::Result<(u32, u32)> {
    let parsed = text
        .split_once('x')
        .and_then(|(c, r)| Some((c.parse::<u32>().ok()?, r.parse::<u32>().ok()?)));
    match parsed {
        Some((c, r)) if c > 0 && r > 0 && u64::from(c) * u64::from(r) <= 1 << 24 => Ok((c, r)),
        _ => anyhow::bail!("--grid must be COLSxROWS with 1..=16M rays, got {text:?}"),
    }
}

fn check(args: &TraceArgs) -> anyhow::Result<()> {
    if !(args.angle > 0.0 && args.angle <= 90.0) {
        anyhow::bail!("--angle must be in (0, 90] degrees, got {}", args.angle);
    }
    if !(args.depth_scale.is_finite() && args.depth_scale > 0.0) {
        anyhow::bail!(
            "--depth-scale must be a finite number above 0, got {}",
            args.depth_scale
        );
    }
    if !args.azimuth.is_finite() {
        anyhow::bail!("--azimuth must be finite");
    }
    Ok(())
}

pub fn run(args: &TraceArgs) -> anyhow::Result<()> {
    check(args)?;
    let grid = parse_grid(&args.grid)?;
    let method: Method = args.method.parse()?;
    let (hf, source) = args
        .heights
        .load()?
        .ok_or_else(|| anyhow::anyhow!("give a height map: --heightmap FILE or --field NAME"))?;
    let ctx = super::open_device(args.device.as_deref(), true)?;
    hf.check_max_dimension(ctx.info().max_image_dimension_2d, &source)?;
    let defaults = method.info().default_budget;
    let budget = Budget {
        max_steps: args.budget.unwrap_or(defaults.max_steps),
        refine_steps: args.refine.unwrap_or(defaults.refine_steps),
        leaf: args.leaf.unwrap_or(defaults.leaf),
    };
    let (format, stored) = match args.height_format {
        FormatArg::R16 => (HeightFormat::R16Unorm, hf.quantized_unorm16()),
        FormatArg::R32f => (HeightFormat::R32Float, hf.clone()),
    };
    let address = args.address;
    let d = ray_direction(args.angle, args.azimuth);
    let map = build_method_map(method, &stored, address);
    let req = TraceRequest {
        method,
        dir: d.map(|x| x as f32),
        depth_scale: args.depth_scale as f32,
        grid,
        budget,
        address,
        format,
        map: map.as_ref().map(|(data, _)| data),
    };
    let out = trace_on_gpu(&ctx, &stored, &req).context("tracing on the GPU")?;
    super::check_validation(&ctx)?;
    if let Some(path) = &args.dump {
        let flat: Vec<f32> = out.hits.iter().flatten().copied().collect();
        write_npy_f32(path, &[grid.1 as usize, grid.0 as usize, 8], &flat)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    // The reference sees the depth scale as the GPU did: rounded to f32.
    let stats = trace_stats(
        &stored,
        &out.hits,
        &out.steps,
        f64::from(req.depth_scale),
        address,
    );
    let line = json!({
        "method": method.id(), "heightmap": source, "size": [hf.width(), hf.height()],
        "angle_deg": args.angle, "azimuth_deg": args.azimuth, "depth_scale": args.depth_scale,
        "address": address.to_string(), "grid": [grid.0, grid.1], "budget": budget,
        "gpu_ms": out.frame_ms[0], "device": ctx.info().name,
        "error_texels": stats.error_texels, "depth_error_texels": stats.depth_error_texels,
        "gross_rate": stats.gross_rate, "capped_rate": stats.capped_rate,
        "nan_pixels": stats.nan_pixels, "steps": stats.steps,
    });
    println!("{line}");
    Ok(())
}
