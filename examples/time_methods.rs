//! Times two displacement methods on a height field made here, and measures how far each one's
//! hits land from the exact intersection: the trade a method makes, in one line each.
//!
//! ```sh
//! cargo run --release --example time_methods -- [--size N]
//! ```

use anyhow::Context as _;
use relief::bench::{ray_direction, trace_stats, GpuMs};
use relief::heightfield::{build_method_map, Address, Heightfield};
use relief::method::Method;
use relief::render::{time_method, trace_on_gpu, BenchRequest, HeightFormat, TraceRequest};
use relief::vk::{Context, ContextOptions};

fn main() -> anyhow::Result<()> {
    let size = parse_size()?;
    let hf = ripples(size)?;
    let ctx = Context::new(&ContextOptions::default())?;
    // A grazing ray (30 degrees above the plane) is where cheap methods skip over crests.
    let dir = ray_direction(30.0, 20.0).map(|x| x as f32);

    println!(
        "{:<6} {:>14} {:>10} {:>12}",
        "method", "error (texels)", "gross", "GPU ms"
    );
    for method in [Method::POM, Method::QDM] {
        // Methods that read a precomputed map (cone maps, ...) get it built on the CPU here;
        // POM and QDM need none (QDM's pyramid is built on the GPU with the heights).
        let map = build_method_map(method, &hf, Address::Repeat).map(|(data, _)| data);
        let trace = TraceRequest {
            method,
            dir,
            depth_scale: 0.1,
            grid: (size, size),
            budget: method.info().default_budget,
            address: Address::Repeat,
            format: HeightFormat::R32Float,
            map: map.as_ref(),
            shadow: None,
        };
        // Timing: a few warm-up dispatches, then GPU timestamps around each timed one.
        let timing = time_method(
            &ctx,
            &hf,
            &BenchRequest {
                trace,
                warmup: 2,
                frames: 5,
                dispatches: 1,
            },
        )?;
        // Error: one more trace whose hits come back, each compared with the exact hit that
        // `heightfield::reference` finds on the heights as the GPU stored them.
        let traced = trace_on_gpu(&ctx, &hf, &trace)?;
        let stats = trace_stats(&hf, &traced.hits, &traced.steps, 0.1, Address::Repeat);
        println!(
            "{:<6} {:>14.4} {:>9.2}% {:>12.4}",
            method.id(),
            stats.error_texels.mean,
            stats.gross_rate * 100.0,
            GpuMs::of(&timing.frame_ms).median
        );
    }
    // Debug builds load the Khronos validation layer (RELIEF_VALIDATION=0 turns it off): what it
    // finds is a bug, so it fails the run.
    ctx.messages().ensure_none()?;
    Ok(())
}

/// Concentric ripples with sharp crests: smooth enough for POM's linear search to find, with
/// crests thin enough that its fixed steps sometimes miss them.
fn ripples(size: u32) -> anyhow::Result<Heightfield> {
    let n = size as usize;
    let data = (0..n * n)
        .map(|k| {
            let (x, y) = ((k % n) as f32 + 0.5, (k / n) as f32 + 0.5);
            let r = (x / n as f32 - 0.5).hypot(y / n as f32 - 0.5);
            (0.5 + 0.5 * (r * 60.0).cos()).powi(4)
        })
        .collect();
    Ok(Heightfield::new(size, size, data)?)
}

/// `--size N`: the field's side and the ray grid's, 128 by default.
fn parse_size() -> anyhow::Result<u32> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    match args.as_slice() {
        [] => Ok(128),
        [flag, n] if flag == "--size" => n.parse().context("--size takes a number"),
        _ => anyhow::bail!("usage: time_methods [--size N]"),
    }
}
