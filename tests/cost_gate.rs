//! The cost gate (`relief bench gate`): this build's counts of work match the baseline kept in
//! assets/cost-gate.json within its tolerances (the suite fails, naming the method, field and
//! view, when a change makes a method take more steps or fetch more texels); a method made to
//! waste steps on purpose trips it on both; two runs count the same; a baseline that cannot be read is a clean error.

mod common;

use std::path::PathBuf;

use common::cli::{assert_clean_failure, relief};
use serde_json::Value;

fn baseline() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/cost-gate.json")
}

fn gate(extra: &[&str]) -> std::process::Output {
    let base = baseline();
    let mut args = vec!["bench", "gate", "--baseline", base.to_str().expect("UTF-8")];
    args.extend_from_slice(extra);
    relief(&args)
}

#[test]
fn this_build_does_no_more_work_than_the_baseline() {
    let out = gate(&[]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(
        out.status.success(),
        "the cost gate failed; if the change is meant, run `relief bench gate --update` and commit \
         assets/cost-gate.json with the reason:\n{err}"
    );
    assert!(err.contains("cost gate passed"), "{err}");
}

#[test]
fn a_method_wasting_steps_trips_the_gate_and_is_named() {
    let out = gate(&["--methods", "relief", "--waste", "relief"]);
    assert_clean_failure(
        &out,
        &[
            "cost gate failed",
            "relief on",
            "mean steps",
            "mean fetches",
        ],
    );
    let err = String::from_utf8_lossy(&out.stderr);
    for field in ["fbm", "bricks", "spikes"] {
        assert!(
            err.contains(&format!("relief on {field} at elevation")),
            "{field} named:\n{err}"
        );
    }
}

#[test]
fn two_runs_count_the_same() {
    let run = || -> Value {
        let out = gate(&["--methods", "pom,qdm", "--json"]);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
        serde_json::from_slice(&out.stdout).expect("--json prints JSON")
    };
    let (a, b) = (run(), run());
    assert_eq!(a["counts"]["cells"].as_array().map(Vec::len), Some(18));
    assert_eq!(a["counts"]["cells"], b["counts"]["cells"]);
    assert_eq!(a["findings"], Value::Array(Vec::new()));
    for cell in a["counts"]["cells"].as_array().unwrap() {
        let (steps, fetches) = (cell["mean_steps"].as_f64(), cell["mean_fetches"].as_f64());
        // Every step of both fetches at least one texel: the counting is on.
        assert!(fetches >= steps && steps > Some(0.0), "{cell}");
    }
}

#[test]
fn a_baseline_that_cannot_be_read_is_a_clean_error() {
    let dir = common::scratch_dir("cost-gate");
    let missing = dir.join("none.json");
    let out = relief(&["bench", "gate", "--baseline", missing.to_str().unwrap()]);
    assert_clean_failure(&out, &["none.json", "--update"]);
    let broken = dir.join("broken.json");
    std::fs::write(&broken, "{\"cells\": 3}").unwrap();
    let out = relief(&["bench", "gate", "--baseline", broken.to_str().unwrap()]);
    assert_clean_failure(&out, &["broken.json", "not a cost gate baseline"]);
}
