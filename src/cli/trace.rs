//! `relief trace`: parallel rays over a grid traced on the GPU by one method, the hits dumped to
//! `.npy`, and one JSON line of error statistics against the exact reference.

use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use relief::bench::{ray_direction, shadow_stats, trace_stats, write_npy_f32};
use relief::heightfield::visibility::{LightDir, MAX_SAMPLES_PER_SIDE};
use relief::heightfield::{build_method_map, Address};
use relief::method::{Budget, Leaf, Method};
use relief::render::{trace_on_gpu, HeightFormat, ShadowTrace, TraceRequest};
use relief::scene::ShadowMode;
use serde_json::json;

use super::heightmap_args::HeightmapArgs;
use super::scene_args::FormatArg;

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
    /// Iteration cap, fixed (when left out, the method's default: for the accurate methods 256
    /// plus one step per texel the ray crosses, up to 8192).
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
    /// Write the traced rays to this .npy file, shape (rows, cols, 8); with --shadows
    /// (rows, cols, 9), the light's visible fraction at the hit last.
    #[arg(long)]
    dump: Option<PathBuf>,
    #[command(flatten)]
    light: ShadowArgs,
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
}

/// A directional light to shadow every hit toward (docs/conventions.md).
#[derive(Args)]
struct ShadowArgs {
    /// Shade each hit's visibility of the light: none, hard, pom-soft, horizon or cone.
    #[arg(long, value_name = "MODE")]
    shadows: Option<ShadowMode>,
    /// Light elevation in degrees (90: overhead, below 0: under the horizon).
    #[arg(long, default_value_t = 30.0, allow_negative_numbers = true)]
    light_elevation: f64,
    /// Light azimuth in degrees from +u toward +v.
    #[arg(long, default_value_t = 0.0, allow_negative_numbers = true)]
    light_azimuth: f64,
    /// Angular radius of the light's disk in degrees (0: a hard light; the sun: 0.27).
    #[arg(long, default_value_t = 0.0)]
    light_radius: f64,
    /// Samples (pom-soft, horizon) or the pyramid walk's cap (cone); the mode's default when
    /// left out.
    #[arg(long)]
    shadow_steps: Option<u32>,
    /// Horizon mode's reach, as a multiple of the distance at which the light's lowest
    /// direction clears the top plane.
    #[arg(long, default_value_t = 1.0)]
    horizon_reach: f32,
    /// Exact reference rays per point: this number squared, over the light's disk.
    #[arg(long, default_value_t = 16)]
    reference_samples: u32,
}

impl ShadowArgs {
    fn light(&self) -> anyhow::Result<Option<(ShadowTrace, LightDir)>> {
        let Some(mode) = self.shadows else {
            return Ok(None);
        };
        let light = LightDir {
            elevation_deg: self.light_elevation,
            azimuth_deg: self.light_azimuth,
            radius_deg: self.light_radius,
        };
        if !(-90.0..=90.0).contains(&light.elevation_deg) {
            anyhow::bail!(
                "--light-elevation must be in [-90, 90] degrees, got {}",
                light.elevation_deg
            );
        }
        if !light.azimuth_deg.is_finite() {
            anyhow::bail!("--light-azimuth must be finite");
        }
        if !(0.0..=90.0).contains(&light.radius_deg) {
            anyhow::bail!(
                "--light-radius must be in [0, 90] degrees, got {}",
                light.radius_deg
            );
        }
        if !(1..=MAX_SAMPLES_PER_SIDE).contains(&self.reference_samples) {
            anyhow::bail!("--reference-samples must be in 1..={MAX_SAMPLES_PER_SIDE}");
        }
        let mut trace = ShadowTrace::directional(
            mode,
            light.elevation_deg,
            light.azimuth_deg,
            light.radius_deg,
        );
        if let Some(steps) = self.shadow_steps {
            if steps == 0 {
                anyhow::bail!("--shadow-steps must be at least 1");
            }
            trace.steps = steps;
        }
        if !(self.horizon_reach.is_finite() && self.horizon_reach > 0.0) {
            anyhow::bail!("--horizon-reach must be a finite number above 0");
        }
        trace.horizon_reach = self.horizon_reach;
        Ok(Some((trace, light)))
    }
}

fn parse_grid(text: &str) -> anyhow::Result<(u32, u32)> {
    match super::parse_wxh(text) {
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
    let (hf, source, ctx) = args.heights.load_on_device(args.device.as_deref(), true)?;
    let defaults = method.info().default_budget;
    let budget = Budget {
        max_steps: args.budget.unwrap_or(defaults.max_steps),
        refine_steps: args.refine.unwrap_or(defaults.refine_steps),
        leaf: args.leaf.unwrap_or(defaults.leaf),
        // --budget is a fixed cap; the default grows with the ray.
        extent_limit: args.budget.map_or(defaults.extent_limit, |_| 0),
    };
    let (format, stored) = match args.height_format {
        FormatArg::R16 => (HeightFormat::R16Unorm, hf.quantized_unorm16()),
        FormatArg::R32f => (HeightFormat::R32Float, hf.clone()),
    };
    let address = args.address;
    let d = ray_direction(args.angle, args.azimuth);
    let map = build_method_map(method, &stored, address);
    let light = args.light.light()?;
    let req = TraceRequest {
        method,
        dir: d.map(|x| x as f32),
        depth_scale: args.depth_scale as f32,
        grid,
        budget,
        address,
        format,
        map: map.as_ref().map(|(data, _)| data),
        shadow: light.map(|(trace, _)| trace),
    };
    let out = trace_on_gpu(&ctx, &stored, &req).context("tracing on the GPU")?;
    super::check_validation(&ctx)?;
    if let Some(path) = &args.dump {
        let columns = if light.is_some() { 9 } else { 8 };
        let flat: Vec<f32> = out
            .hits
            .iter()
            .zip(&out.visible)
            .flat_map(|(hit, &vis)| hit.iter().copied().chain((columns == 9).then_some(vis)))
            .collect();
        write_npy_f32(path, &[grid.1 as usize, grid.0 as usize, columns], &flat)
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
    let mut line = json!({
        "method": method.id(), "heightmap": source, "size": [hf.width(), hf.height()],
        "angle_deg": args.angle, "azimuth_deg": args.azimuth, "depth_scale": args.depth_scale,
        "address": address.to_string(), "grid": [grid.0, grid.1], "budget": budget,
        "gpu_ms": out.frame_ms[0], "device": ctx.info().name,
        "error_texels": stats.error_texels, "depth_error_texels": stats.depth_error_texels,
        "gross_rate": stats.gross_rate, "capped_rate": stats.capped_rate,
        "nan_pixels": stats.nan_pixels, "steps": stats.steps,
    });
    if let Some((trace, dir)) = light {
        let shadow = shadow_stats(
            &stored,
            &out.hits,
            &out.visible,
            f64::from(req.depth_scale),
            address,
            dir,
            args.light.reference_samples,
        )?;
        line["shadow"] = json!({
            "mode": trace.mode.id(), "steps": trace.steps,
            "light_elevation_deg": dir.elevation_deg, "light_azimuth_deg": dir.azimuth_deg,
            "light_radius_deg": dir.radius_deg, "reference_rays_per_point": args.light.reference_samples.pow(2),
            "stats": shadow,
        });
    }
    println!("{line}");
    Ok(())
}
