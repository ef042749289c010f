//! `relief bench --shard K/N` and `relief bench merge`: three shards of a small sweep, run at once as
//! separate processes, merge into the very cells of one unsharded run (every error, step count and
//! rate equal; only times differ), and merge refuses a shard of another sweep and names a missing
//! or a conflicting repeated shard.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};

use common::cli::{assert_clean_failure, relief};
use serde_json::Value;

/// A small sweep with every kind of step: jobs of every section (the depth-scale one with both
/// baselines), stability cells, shadows and AO, and blending as a section run whole.
const SWEEP: &[&str] = &[
    "bench",
    "--quick",
    "--methods",
    "pom,qdm",
    "--sizes",
    "64,32",
    "--angles",
    "30,60",
    "--depth-scales",
    "0.1,0.5",
    "--sections",
    "main,stability,shading,blending",
    "--no-lod",
    "--no-edits",
    "--no-scene-shadows",
];

fn start(args: &[&str], out: &Path) -> Child {
    Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .arg("--out")
        .arg(out)
        .stdout(Stdio::null())
        .stderr(Stdio::piped())
        .spawn()
        .expect("relief starts")
}

fn finish(child: Child, what: &str) {
    let out = child.wait_with_output().expect("relief runs");
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{what} failed:\n{err}");
}

fn results(dir: &Path) -> Value {
    let text = std::fs::read_to_string(dir.join("results.json")).expect("results.json");
    serde_json::from_str(&text).expect("JSON")
}

/// `v` without what a run's timing decides: every `*_ms` and `samples` field.
fn untimed(v: &Value) -> Value {
    match v {
        Value::Object(map) => Value::Object(
            map.iter()
                .filter(|(k, _)| !(k.ends_with("_ms") || *k == "ms" || *k == "samples"))
                .map(|(k, x)| (k.clone(), untimed(x)))
                .collect(),
        ),
        Value::Array(items) => Value::Array(items.iter().map(untimed).collect()),
        other => other.clone(),
    }
}

fn path(p: &Path) -> &str {
    p.to_str().expect("utf-8 path")
}

/// `relief bench merge DIRS... --out OUT`.
fn merge(dirs: &[&Path], out: &Path) -> std::process::Output {
    let mut args = vec!["bench", "merge"];
    args.extend(dirs.iter().map(|d| path(d)));
    args.extend(["--out", path(out)]);
    relief(&args)
}

#[test]
fn shards_run_at_once_merge_into_the_unsharded_runs_cells() {
    if common::device("bench_shards").is_none() {
        return;
    }
    let dir = common::scratch_dir("bench-shards");
    let shard_dirs: Vec<PathBuf> = (1..=3).map(|k| dir.join(format!("shard{k}"))).collect();
    let other = dir.join("other-sweep");
    // All five processes at once: three shards, the unsharded run, and a shard of another sweep
    // (one more timed frame per configuration).
    let mut children = Vec::new();
    for (k, out) in shard_dirs.iter().enumerate() {
        let shard = format!("{}/3", k + 1);
        let args = [SWEEP, &["--shard", &shard]].concat();
        children.push((start(&args, out), format!("shard {shard}")));
    }
    children.push((start(SWEEP, &dir.join("whole")), "the unsharded run".into()));
    let mixed = [SWEEP, &["--frames", "4", "--no-stability", "--no-shading"]].concat();
    let mixed = [&mixed[..], &["--no-blending", "--shard", "2/3"]].concat();
    children.push((start(&mixed, &other), "the other sweep's shard".into()));
    for (child, what) in children {
        finish(child, &what);
    }

    let whole = results(&dir.join("whole"));
    assert!(
        whole.get("shard").is_none(),
        "an unsharded run has no shard"
    );
    let mut runs_per_shard = Vec::new();
    for (k, d) in shard_dirs.iter().enumerate() {
        let r = results(d);
        assert_eq!(r["shard"]["index"], k + 1);
        assert_eq!(r["shard"]["count"], 3);
        assert_eq!(
            r["shard"]["fingerprint"],
            results(&shard_dirs[0])["shard"]["fingerprint"]
        );
        runs_per_shard.push(r["runs"].as_array().expect("runs").len());
    }
    let total = whole["runs"].as_array().expect("runs").len();
    assert_eq!(runs_per_shard.iter().sum::<usize>(), total);
    assert!(
        runs_per_shard.iter().filter(|&&n| n > 0).count() >= 2,
        "the runs were split: {runs_per_shard:?}"
    );

    // Merged in a scrambled order.
    let merged_dir = dir.join("merged");
    let [s1, s2, s3] = [&shard_dirs[0], &shard_dirs[1], &shard_dirs[2]].map(PathBuf::as_path);
    let run = merge(&[s3, s1, s2], &merged_dir);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "merge failed:\n{err}");
    assert!(merged_dir.join("report.md").exists());
    let merged = results(&merged_dir);
    assert!(merged.get("shard").is_none(), "a merged file is whole");
    assert!(!merged["command"].as_str().unwrap().contains("--shard"));
    for key in [
        "runs",
        "maps",
        "stability",
        "shadows",
        "ao",
        "shadow_stability",
        "blending",
        "options",
        "device",
    ] {
        assert!(
            untimed(&whole[key]) == untimed(&merged[key]),
            "{key} differs between the merged shards and the unsharded run"
        );
    }
    assert!(total > 10 && !whole["stability"].as_array().unwrap().is_empty());

    // A shard of another sweep.
    let refused = dir.join("refused");
    let run = merge(&[s1, &other, s3], &refused);
    assert_clean_failure(&run, &["other-sweep", "different sweeps", "frames"]);
    // A missing shard.
    let run = merge(&[s1, s3], &refused);
    assert_clean_failure(&run, &["shard(s) 2 of 3 missing"]);
    // Shard 2 twice: the same file is merged once; a different run of it is refused.
    let again = dir.join("shard2-again");
    std::fs::create_dir_all(&again).unwrap();
    let mut changed = results(s2);
    changed["date"] = "2026-01-01T00:00:00Z".into();
    std::fs::write(again.join("results.json"), changed.to_string()).unwrap();
    let run = merge(&[s1, s2, s3, s2], &dir.join("twice"));
    assert!(
        run.status.success(),
        "{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let run = merge(&[s1, s2, s3, &again], &refused);
    assert_clean_failure(&run, &["shard 2/3", "given twice", "shard2-again"]);
}

#[test]
fn bad_shards_are_bad_usage() {
    for bad in ["0/2", "3/2", "garbage"] {
        let run = relief(&["bench", "--quick", "--out", "unused", "--shard", bad]);
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(2), "{bad}:\n{err}");
        assert!(err.contains("--shard"), "{bad}: {err}");
    }
    let run = relief(&["bench", "merge", "--out", "unused"]);
    assert_eq!(run.status.code(), Some(2), "merge needs shard folders");
}
