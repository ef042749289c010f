//! `relief bench gate`: the cost gate. Measures the fixed sweep's counts of work (steps per ray,
//! the slowest ray, capped rays) and compares them with the baseline in the repository; a count
//! grown beyond its tolerance fails the run, naming the method, field and view. `--update`
//! writes the run as the new baseline, one cell per line so that its diff reads as what changed.

use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use relief::bench::{check_gate, gate_setup, measure_gate, GateCell, GateCounts};
use relief::method::Method;

use super::frame_files::write_whole;

#[derive(Args)]
pub struct GateArgs {
    /// The baseline counts (the repository keeps assets/cost-gate.json).
    #[arg(
        long,
        value_name = "FILE.json",
        default_value = "assets/cost-gate.json"
    )]
    baseline: PathBuf,
    /// Write this run's counts as the baseline instead of comparing with it.
    #[arg(long)]
    update: bool,
    /// Method ids, comma-separated (default: all); only their cells are compared.
    #[arg(long, value_delimiter = ',', value_parser = method_id)]
    methods: Vec<Method>,
    /// Test-only: double METHOD's iteration cap, so that a fixed-step method takes twice the
    /// steps and the gate must fail. Refused with --update.
    #[arg(long, value_name = "METHOD", value_parser = method_id, conflicts_with = "update")]
    waste: Option<Method>,
    /// Print the run's counts and the findings as one JSON object.
    #[arg(long)]
    json: bool,
    /// Device name substring, as for `relief bench`.
    #[arg(long)]
    device: Option<String>,
}

fn method_id(text: &str) -> Result<Method, String> {
    text.parse::<Method>().map_err(|e| e.to_string())
}

/// The gate found counts grown beyond their tolerance.
#[derive(Debug, thiserror::Error)]
#[error("the cost gate failed: {count} cell(s) take more work than {baseline} allows; the first: {first}")]
pub struct CostGrew {
    count: usize,
    baseline: String,
    first: String,
}

pub fn run(args: &GateArgs) -> anyhow::Result<()> {
    let baseline = if args.update {
        None
    } else {
        let text = std::fs::read_to_string(&args.baseline).with_context(|| {
            format!(
                "reading the cost gate's baseline {} (write one with --update)",
                args.baseline.display()
            )
        })?;
        let counts: GateCounts = serde_json::from_str(&text)
            .with_context(|| format!("{} is not a cost gate baseline", args.baseline.display()))?;
        Some(counts)
    };
    let methods: Vec<Method> = if args.methods.is_empty() {
        Method::all().collect()
    } else {
        args.methods.clone()
    };
    let ctx = super::open_device(args.device.as_deref(), args.json)?;
    if !args.json {
        eprintln!("cost gate: {} methods, {}", methods.len(), gate_setup());
    }
    let show = |c: &GateCell| {
        if !args.json {
            eprintln!(
                "  {:<14} {:<8} {:<14} mean {:>8.3}  max {:>5}  capped {:>3}  fetches {:>8.3}  max {:>5}",
                c.method, c.field, c.view, c.mean_steps, c.max_steps, c.capped, c.mean_fetches, c.max_fetches
            );
        }
    };
    let run = measure_gate(&ctx, &methods, args.waste, show)?;
    super::check_validation(&ctx)?;
    let Some(baseline) = baseline else {
        write_whole(&args.baseline, baseline_text(&run).as_bytes())?;
        eprintln!(
            "wrote {} cells to {}",
            run.cells.len(),
            args.baseline.display()
        );
        return Ok(());
    };
    let findings = check_gate(&baseline, &run);
    if args.json {
        let listed: Vec<_> = findings
            .iter()
            .map(|f| serde_json::json!({ "cell": f.cell, "what": f.what }))
            .collect();
        println!(
            "{}",
            serde_json::json!({ "counts": run, "findings": listed })
        );
    }
    for f in &findings {
        eprintln!("relief: cost gate: {}: {}", f.cell, f.what);
    }
    match findings.first() {
        None => {
            if !args.json {
                eprintln!(
                    "cost gate passed: {} cells within the tolerances of {}",
                    run.cells.len(),
                    args.baseline.display()
                );
            }
            Ok(())
        }
        Some(first) => Err(CostGrew {
            count: findings.len(),
            baseline: args.baseline.display().to_string(),
            first: format!("{}: {}", first.cell, first.what),
        }
        .into()),
    }
}

/// The baseline as JSON with one cell per line, so that a diff shows the cells that moved.
fn baseline_text(counts: &GateCounts) -> String {
    let cells: Vec<String> = counts
        .cells
        .iter()
        .map(|c| format!("    {}", serde_json::to_string(c).expect("cells encode")))
        .collect();
    format!(
        "{{\n  \"device\": {},\n  \"setup\": {},\n  \"cells\": [\n{}\n  ]\n}}\n",
        serde_json::to_string(&counts.device).expect("strings encode"),
        serde_json::to_string(&counts.setup).expect("strings encode"),
        cells.join(",\n")
    )
}
