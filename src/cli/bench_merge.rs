//! `relief bench merge DIR... --out DIR`: the folders of `relief bench --shard K/N` runs joined
//! into the results.json, report and plots one unsharded run writes (times aside, which each shard
//! measured on its own).

use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use relief::bench::{load_results, merge_shards, results_path, ShardFile};

#[derive(Args)]
pub struct MergeArgs {
    /// The shards' folders (or their results.json files), one per shard, in any order.
    #[arg(required = true, value_name = "DIR")]
    shards: Vec<PathBuf>,
    /// Folder for the merged results.json, report.md and the SVG plots.
    #[arg(long)]
    out: PathBuf,
    /// Print the merged results.json to stdout.
    #[arg(long)]
    json: bool,
}

pub fn run(args: &MergeArgs) -> anyhow::Result<()> {
    let mut files = Vec::with_capacity(args.shards.len());
    for dir in &args.shards {
        let path = results_path(dir);
        let results = load_results(dir)?;
        let text = std::fs::read_to_string(&path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        files.push(ShardFile {
            path,
            text,
            results,
        });
    }
    let count = files.len();
    let (mut merged, notes) = merge_shards(files)?;
    // The command an unsharded run would have had: the shards' (less --shard), writing here.
    merged.argv = with_out(&merged.argv, &args.out);
    merged.command = merged.argv.join(" ");
    for line in notes {
        eprintln!("merge: {line}");
    }
    if !args.json {
        eprintln!("merged {count} shard file(s) of one sweep");
    }
    super::bench::write_outputs(&args.out, &merged, args.json)
}

/// `argv` with its `--out` folder replaced by `out`.
fn with_out(argv: &[String], out: &std::path::Path) -> Vec<String> {
    let out = out.display().to_string();
    let mut words = Vec::with_capacity(argv.len());
    let mut next_is_out = false;
    for word in argv {
        if std::mem::take(&mut next_is_out) {
            words.push(out.clone());
        } else if word.starts_with("--out=") {
            words.push(format!("--out={out}"));
        } else {
            next_is_out = word == "--out";
            words.push(word.clone());
        }
    }
    words
}
