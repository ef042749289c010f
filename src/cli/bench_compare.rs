//! `relief bench compare BASE NEW`: two results files cell by cell, printed as a table, and
//! optionally written as Markdown and an SVG plot; `--fail-above` turns a regression into an
//! exit code for CI.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use clap::Args;
use relief::bench::compare::{
    compare, markdown_report, ratio_plot, terminal_report, CellComparison, DEFAULT_MIN_EFFECT,
};
use relief::bench::load_results;

/// Exit code when `--fail-above` finds a cell slower than allowed.
pub const EXIT_SLOWER: u8 = 3;

#[derive(Args)]
pub struct CompareArgs {
    /// The baseline: a results.json, or the folder `relief bench --out` wrote.
    base: PathBuf,
    /// The run judged against it (file or folder).
    new: PathBuf,
    /// The band of no practical change: ratios within 1 +- this (0.05: 5%) are within noise
    /// however many frames say otherwise.
    #[arg(long, value_name = "FRACTION", default_value_t = DEFAULT_MIN_EFFECT)]
    min_effect: f64,
    /// Exit with code 3 when any cell is slower beyond noise with its whole interval above
    /// RATIO (e.g. 1.10), for CI.
    #[arg(long, value_name = "RATIO")]
    fail_above: Option<f64>,
    /// Also write the comparison as Markdown to this file.
    #[arg(long, value_name = "FILE")]
    markdown: Option<PathBuf>,
    /// Also plot each cell's ratio with its interval to this SVG file.
    #[arg(long, value_name = "FILE")]
    svg: Option<PathBuf>,
}

/// `--fail-above` found cells slower than allowed: the CLI exits with [`EXIT_SLOWER`].
#[derive(Debug, thiserror::Error)]
#[error("{count} cell(s) slower than {limit}x beyond noise; the worst: {worst}")]
pub struct SlowerThanAllowed {
    count: usize,
    limit: f64,
    worst: String,
}

#[cfg(test)]
impl SlowerThanAllowed {
    /// One, for the exit-code test.
    pub fn example() -> SlowerThanAllowed {
        SlowerThanAllowed {
            count: 1,
            limit: 1.1,
            worst: "a cell".into(),
        }
    }
}

pub fn run(args: &CompareArgs) -> anyhow::Result<()> {
    if !(args.min_effect.is_finite() && args.min_effect >= 0.0) {
        anyhow::bail!(
            "--min-effect must be a fraction of 0 or more, got {}",
            args.min_effect
        );
    }
    if let Some(r) = args.fail_above.filter(|r| !(r.is_finite() && *r > 0.0)) {
        anyhow::bail!("--fail-above must be a ratio above 0 (e.g. 1.1), got {r}");
    }
    let base = load_results(&args.base).context("reading BASE")?;
    let new = load_results(&args.new).context("reading NEW")?;
    let comparison = compare(&base, &new, args.min_effect);
    print!("{}", terminal_report(&comparison));
    if let Some(path) = &args.markdown {
        write(path, &markdown_report(&comparison))?;
    }
    if let Some(path) = &args.svg {
        write(path, &ratio_plot(&comparison))?;
    }
    let Some(limit) = args.fail_above else {
        return Ok(());
    };
    if !comparison.same_device {
        anyhow::bail!(
            "--fail-above judges runs of one device, but BASE was measured on {} and NEW on {}",
            comparison.base.device.name,
            comparison.new.device.name
        );
    }
    let slower = comparison.slower_above(limit);
    let worst = slower
        .iter()
        .max_by(|a, b| low_end(a).total_cmp(&low_end(b)));
    match worst {
        None => Ok(()),
        Some(w) => Err(SlowerThanAllowed {
            count: slower.len(),
            limit,
            worst: format!(
                "{} at {:.3}x, interval from {:.3}x",
                w.key,
                w.interval.map_or(f64::NAN, |i| i.ratio),
                low_end(w)
            ),
        }
        .into()),
    }
}

fn low_end(c: &CellComparison) -> f64 {
    c.interval.map_or(f64::NAN, |i| i.low)
}

fn write(path: &Path, text: &str) -> anyhow::Result<()> {
    std::fs::write(path, text).with_context(|| format!("writing {}", path.display()))
}
