//! `relief occlusion`: ambient occlusion from the whole scene (objects and relief solids alike)
//! traced by ray query from each pixel of a G-buffer frame, against the brute-force CPU reference
//! on the very same rays; prints the comparison and writes both as `.npy` dumps.

use std::path::PathBuf;

use clap::Args;
use relief::bench::{measure_traced_ao, write_npy_f32, TracedAoConfig};
use relief::scene::ShadowScene;

use super::{check_validation, open_device, parse_size};

#[derive(Args)]
pub struct OcclusionArgs {
    /// The scene: box-over-plane, slab-over-plane, box-over-relief, sphere-over-plane (generated), or default (the
    /// built-in default scene).
    #[arg(long, default_value = "box-over-relief")]
    scene: String,
    /// Image size.
    #[arg(long, value_name = "WxH", default_value = "240x135")]
    size: String,
    /// How far the occlusion rays reach, in world units.
    #[arg(long, value_name = "UNITS", default_value_t = 1.0)]
    radius: f32,
    /// Rays per pixel per side (N x N, stratified and cosine-weighted).
    #[arg(long, value_name = "N", default_value_t = 4)]
    samples: u32,
    /// Write exact.npy and traced.npy here: rows x cols of unblocked shares, -1 where no
    /// surface was drawn.
    #[arg(long, value_name = "DIR")]
    dump: Option<PathBuf>,
    /// Print the result as JSON.
    #[arg(long)]
    json: bool,
    /// Pick the Vulkan device whose name contains this text.
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
}

pub fn run(args: &OcclusionArgs) -> anyhow::Result<()> {
    let (width, height) = parse_size("--size", &args.size)?;
    if !(args.radius.is_finite() && args.radius > 0.0 && args.radius <= 1e6) {
        anyhow::bail!(
            "--radius must be a positive number of world units, got {}",
            args.radius
        );
    }
    if !(1..=16).contains(&args.samples) {
        anyhow::bail!("--samples must be in 1..=16, got {}", args.samples);
    }
    let scene = match args.scene.as_str() {
        "default" => None,
        other => Some(other.parse::<ShadowScene>().map_err(anyhow::Error::msg)?),
    };
    let config = TracedAoConfig {
        scene,
        width,
        height,
        radius: args.radius,
        samples_per_side: args.samples,
    };
    let ctx = open_device(args.device.as_deref(), args.json)?;
    eprintln!("tracing {width}x{height} pixels' occlusion rays on the GPU and the CPU ...");
    let run = measure_traced_ao(&ctx, &config)?;
    check_validation(&ctx)?;
    if let Some(dir) = &args.dump {
        std::fs::create_dir_all(dir)?;
        let shape = [height as usize, width as usize];
        write_npy_f32(&dir.join("exact.npy"), &shape, &run.exact)?;
        write_npy_f32(&dir.join("traced.npy"), &shape, &run.traced)?;
    }
    if args.json {
        println!("{}", serde_json::to_string_pretty(&run)?);
        return Ok(());
    }
    println!(
        "scene {}: {} receiver pixels, {} rays each reaching {} units",
        run.scene, run.pixels, run.rays, args.radius
    );
    println!(
        "reference: mean unblocked share {:.4}, {} pixels partly occluded",
        run.mean_visibility, run.occluded_pixels
    );
    println!(
        "ray-traced vs reference: mean |difference| {:.5}, max {:.4}, {} pixels differ",
        run.mean_abs_error, run.max_abs_error, run.differing_pixels
    );
    let s = &run.structures;
    println!(
        "ray queries: {} prism tests ({} capped), {:.3} gpu ms; structures: {} triangles, {} prisms, {:.1} KiB, built in {:.3} gpu ms",
        run.prisms_tested,
        run.capped,
        run.trace_ms,
        s.triangles,
        s.prisms,
        s.structure_bytes as f64 / 1024.0,
        s.build_ms
    );
    if let Some(dir) = &args.dump {
        println!("wrote {}/exact.npy and traced.npy", dir.display());
    }
    Ok(())
}
