//! `relief render --environment sky|none|FILE.hdr` and `--background`: what `--explain` lists for
//! each, and one clear error line for a missing, truncated or malformed environment file.

mod common;

use std::path::Path;

use common::cli::{assert_clean_failure, relief};
use relief::environment::Environment;

fn explain(name: &str, flags: &[&str]) -> serde_json::Value {
    let out = common::scratch_dir(name).join("frame.png");
    let mut args = vec![
        "render",
        "--explain",
        "--width",
        "48",
        "--height",
        "32",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend_from_slice(flags);
    let run = relief(&args);
    assert!(
        run.status.success(),
        "render {flags:?} failed:\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    serde_json::from_slice(&run.stdout).expect("one JSON object")
}

fn skipped(plan: &serde_json::Value, what: &str) -> Option<String> {
    plan["skipped"]
        .as_array()
        .expect("skipped")
        .iter()
        .find(|s| s["what"] == what)
        .map(|s| s["why"].as_str().unwrap_or_default().to_owned())
}

#[test]
fn explain_lists_the_environment_maps_or_why_none_were_built() {
    if common::device("explain_lists_the_environment_maps").is_none() {
        return;
    }
    let sky = explain("env-sky", &[]);
    assert_eq!(sky["environment"]["name"], "built-in sky", "{sky}");
    assert_eq!(sky["environment"]["background"], true);
    assert!(skipped(&sky, "environment maps").is_none());

    let dir = common::scratch_dir("env-file");
    let path = dir.join("studio.hdr");
    Environment::from_fn("studio", 64, 32, |d| glam::Vec3::splat(1.0 + d.y))
        .save(&path)
        .expect("writes the environment");
    let file = explain(
        "env-file-render",
        &[
            "--environment",
            path.to_str().expect("utf-8"),
            "--background",
            "colour",
        ],
    );
    assert_eq!(file["environment"]["name"], "studio.hdr", "{file}");
    assert_eq!(
        file["environment"]["source_size"],
        serde_json::json!([64, 32])
    );
    assert_eq!(file["environment"]["background"], false);

    let flat = explain("env-none", &["--environment", "none"]);
    assert!(flat["environment"].is_null(), "{flat}");
    let why = skipped(&flat, "environment maps").expect("says why no maps were built");
    assert!(why.contains("flat ambient"), "{why}");
    let why = skipped(&flat, "background: environment").expect("says why no background");
    assert!(why.contains("no environment"), "{why}");
    // No environment kernels: the pyramid and the AO map are the compute pipelines.
    assert_eq!(flat["created"]["compute_pipelines"], 2, "{flat}");
    assert_eq!(sky["created"]["compute_pipelines"], 5, "{sky}");
}

fn render_with(environment: &Path) -> std::process::Output {
    let out = common::scratch_dir("env-bad").join("frame.png");
    relief(&[
        "render",
        "--width",
        "32",
        "--height",
        "32",
        "--environment",
        environment.to_str().expect("utf-8"),
        "--out",
        out.to_str().expect("utf-8"),
    ])
}

#[test]
fn a_missing_truncated_or_malformed_environment_is_one_clear_error() {
    if common::device("a_missing_truncated_or_malformed_environment").is_none() {
        return;
    }
    let dir = common::scratch_dir("env-errors");
    assert_clean_failure(&render_with(&dir.join("absent.hdr")), &["absent.hdr"]);

    let whole = dir.join("whole.hdr");
    Environment::uniform([1.0, 0.5, 0.25])
        .save(&whole)
        .expect("writes");
    let bytes = std::fs::read(&whole).expect("reads");
    let cut = dir.join("cut.hdr");
    std::fs::write(&cut, &bytes[..bytes.len() - 30]).expect("writes");
    assert_clean_failure(&render_with(&cut), &["cut.hdr", "truncated"]);

    let junk = dir.join("junk.hdr");
    std::fs::write(&junk, b"P6\n2 2\n255\nnot radiance at all").expect("writes");
    assert_clean_failure(&render_with(&junk), &["junk.hdr", "not a readable"]);

    let png = dir.join("sky.png");
    std::fs::write(&png, b"whatever").expect("writes");
    assert_clean_failure(&render_with(&png), &["sky.png", ".hdr"]);
}
