//! `relief ao`: the texture-space AO map of a height field built on the GPU in one mode, dumped to
//! `.npy` as (H, W) float32, and one JSON line of its error against the exact CPU reference
//! (`heightfield::ambient_occlusion`) on stdout.
//!
//! The reference costs about 25 ms per texel at 256 azimuths on these machines, so maps above
//! [`FULL_REFERENCE_TEXELS`] texels are compared on a seeded random subset (`--reference-texels`),
//! which the JSON reports; progress goes to stderr.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use anyhow::Context as _;
use clap::Args;
use indicatif::ProgressBar;
use relief::bench::write_npy_f32;
use relief::heightfield::ambient_occlusion::{ao_at_texel, ao_reference};
use relief::heightfield::{Address, Heightfield};
use relief::render::AoMapPass;
use relief::scene::AoMode;
use serde_json::json;

use super::heightmap_args::HeightmapArgs;

/// Maps with at most this many texels are compared at every texel by default.
const FULL_REFERENCE_TEXELS: usize = 64 * 64;
/// The subset's size by default for larger maps.
const DEFAULT_SUBSET: usize = 1024;
/// Exact-horizon builds above this many texels get a note on stderr before they start.
const LONG_SWEEP_TEXELS: usize = 128 * 128;
/// The subset's seed (fixed, so runs are comparable).
const SUBSET_SEED: u64 = 0x5eed_00a0;

#[derive(Args)]
pub struct AoArgs {
    #[command(flatten)]
    heights: HeightmapArgs,
    /// Depth of height 0 below the top plane, in uv units.
    #[arg(long, default_value_t = 0.1)]
    depth_scale: f64,
    #[arg(long, value_name = "repeat|clamp", default_value_t = Address::Repeat)]
    address: Address,
    /// AO mode: horizon-4, horizon-8, horizon-16 (optionally -rotated), exact-horizon.
    #[arg(long, value_name = "MODE", default_value = "horizon-8")]
    ao: String,
    /// Write the GPU's AO map to this .npy file, shape (H, W) float32.
    #[arg(long)]
    dump: Option<PathBuf>,
    /// Texels the exact reference is computed at (a seeded random subset; all when at least the
    /// map's size). Default: every texel up to 64x64, else 1024. 0 skips the comparison.
    #[arg(long, value_name = "N")]
    reference_texels: Option<usize>,
    /// Azimuth slices of the exact reference.
    #[arg(long, default_value_t = 256, value_name = "N")]
    reference_azimuths: u32,
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
}

/// Which texels the reference visits: all, or `n` distinct ones drawn by a seeded SplitMix64.
fn subset(total: usize, n: usize) -> Vec<usize> {
    if n >= total {
        return (0..total).collect();
    }
    let mut state = SUBSET_SEED;
    let mut picked = vec![false; total];
    let mut out = Vec::with_capacity(n);
    while out.len() < n {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        let k = ((z ^ (z >> 31)) % total as u64) as usize;
        if !picked[k] {
            picked[k] = true;
            out.push(k);
        }
    }
    out.sort_unstable();
    out
}

/// The reference at `texels` (row-major indices), on two threads, with a progress bar on a terminal.
fn reference_at(hf: &Heightfield, args: &AoArgs, texels: &[usize]) -> anyhow::Result<Vec<f32>> {
    let (w, s, azimuths) = (
        hf.width() as usize,
        args.depth_scale,
        args.reference_azimuths,
    );
    if texels.len() == hf.texel_count() {
        return Ok(ao_reference(hf, s, args.address, azimuths)?);
    }
    let bar = if std::io::stderr().is_terminal() {
        ProgressBar::new(texels.len() as u64)
    } else {
        ProgressBar::hidden()
    };
    let done = AtomicUsize::new(0);
    let half = texels.len().div_ceil(2).max(1);
    let parts: Vec<anyhow::Result<Vec<f32>>> = std::thread::scope(|scope| {
        let handles: Vec<_> = texels
            .chunks(half)
            .map(|part| {
                let (bar, done) = (&bar, &done);
                scope.spawn(move || {
                    let mut out = Vec::with_capacity(part.len());
                    for &k in part {
                        let at = ((k % w) as u32, (k / w) as u32);
                        out.push(ao_at_texel(hf, s, args.address, at, azimuths)?.value as f32);
                        bar.set_position(done.fetch_add(1, Ordering::Relaxed) as u64 + 1);
                    }
                    Ok(out)
                })
            })
            .collect();
        handles
            .into_iter()
            .map(|h| {
                h.join()
                    .unwrap_or_else(|_| Err(anyhow::anyhow!("reference thread panicked")))
            })
            .collect()
    });
    bar.finish_and_clear();
    let mut all = Vec::with_capacity(texels.len());
    for part in parts {
        all.extend(part?);
    }
    Ok(all)
}

/// Mean, 99th percentile and max of the absolute differences.
fn error_stats(mut diffs: Vec<f64>) -> serde_json::Value {
    if diffs.is_empty() {
        return json!(null);
    }
    diffs.sort_by(f64::total_cmp);
    let mean = diffs.iter().sum::<f64>() / diffs.len() as f64;
    let p99 = diffs[((diffs.len() - 1) as f64 * 0.99).round() as usize];
    json!({"mean": mean, "p99": p99, "max": diffs[diffs.len() - 1]})
}

fn check(args: &AoArgs) -> anyhow::Result<AoMode> {
    if !(args.depth_scale.is_finite() && args.depth_scale > 0.0) {
        anyhow::bail!(
            "--depth-scale must be a finite number above 0, got {}",
            args.depth_scale
        );
    }
    let mode: AoMode = args
        .ao
        .parse()
        .map_err(|e: String| anyhow::anyhow!("--ao: {e}"))?;
    if !mode.is_some() {
        anyhow::bail!("--ao none builds no AO map; pick a mode that does");
    }
    Ok(mode)
}

/// The error statistics of `ao` against the reference, and what the reference cost.
fn compare(
    hf: &Heightfield,
    args: &AoArgs,
    ao: &[f32],
) -> anyhow::Result<(serde_json::Value, serde_json::Value)> {
    let all = hf.texel_count();
    let default = if all <= FULL_REFERENCE_TEXELS {
        all
    } else {
        DEFAULT_SUBSET
    };
    let texels = subset(all, args.reference_texels.unwrap_or(default));
    if texels.len() > 256 {
        eprintln!(
            "reference: {} texels x {} azimuths on the CPU ...",
            texels.len(),
            args.reference_azimuths
        );
    }
    let started = Instant::now();
    let reference = reference_at(hf, args, &texels)?;
    let cpu_ms = started.elapsed().as_secs_f64() * 1e3;
    let diffs = texels
        .iter()
        .zip(&reference)
        .map(|(&k, &r)| f64::from((ao[k] - r).abs()))
        .collect();
    let cost = json!({
        "texels": texels.len(), "of": all, "azimuths": args.reference_azimuths,
        "seed": SUBSET_SEED, "cpu_ms": cpu_ms,
    });
    Ok((error_stats(diffs), cost))
}

pub fn run(args: &AoArgs) -> anyhow::Result<()> {
    let mode = check(args)?;
    let (hf, source, ctx) = args.heights.load_on_device(args.device.as_deref(), true)?;
    let pass = AoMapPass::new(&ctx, mode).context("creating the AO pipeline")?;
    if mode == AoMode::ExactHorizon && hf.texel_count() > LONG_SWEEP_TEXELS {
        // One submission with no progress of its own: say that it may take a while.
        eprintln!(
            "building the exact-horizon AO map of {}x{} on the GPU (on lavapipe this takes seconds to minutes) ...",
            hf.width(),
            hf.height()
        );
    }
    let (ao, gpu_ms) = pass
        .build(&hf, args.depth_scale, args.address)
        .context("building the AO map on the GPU")?;
    super::check_validation(&ctx)?;
    let (w, h) = (hf.width() as usize, hf.height() as usize);
    if let Some(path) = &args.dump {
        write_npy_f32(path, &[h, w], &ao).with_context(|| format!("writing {}", path.display()))?;
    }
    let comparison = compare(&hf, args, &ao)?;
    let gpu_nan = ao.iter().filter(|v| !v.is_finite()).count();
    let line = json!({
        "ao": mode.to_string(), "heightmap": source, "size": [w, h],
        "depth_scale": args.depth_scale, "address": args.address.to_string(),
        "gpu_ms": gpu_ms, "device": ctx.info().name,
        "error": comparison.0, "nan_texels": gpu_nan, "reference": comparison.1,
        "mean_ao": ao.iter().map(|&v| f64::from(v)).sum::<f64>() / ao.len() as f64,
    });
    println!("{line}");
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn subsets_are_distinct_sorted_and_seeded() {
        let a = subset(10_000, 100);
        assert_eq!(a.len(), 100);
        assert!(a.windows(2).all(|p| p[0] < p[1]));
        assert_eq!(a, subset(10_000, 100));
        assert_eq!(subset(5, 9), vec![0, 1, 2, 3, 4]);
    }

    #[test]
    fn error_stats_of_known_differences() {
        let s = error_stats((0..100).map(f64::from).collect());
        assert_eq!(s["max"], 99.0);
        assert_eq!(s["mean"], 49.5);
        assert_eq!(error_stats(vec![]), json!(null));
    }
}
