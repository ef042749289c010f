//! `relief render --timeline`: a ten-frame render's trace is trace-event JSON as chrome://tracing
//! and ui.perfetto.dev read it (checked field by field here), with every pass of every frame on
//! the GPU track and the host's work on its own, no negative durations, and the passes'
//! invocation counts; two runs of one still scene count the same work; a trace file that is not
//! JSON by name is refused before any device.

mod common;

use std::collections::BTreeSet;
use std::path::Path;

use common::cli::{assert_usage_failure, relief};
use serde_json::Value;

const FRAMES: u64 = 10;

/// Renders the default scene small for `FRAMES` frames with a timeline; returns the `--json`
/// report and the trace.
fn render_with_timeline(dir: &Path) -> (Value, Value) {
    let trace = dir.join("timeline.json");
    let frames = FRAMES.to_string();
    let out = relief(&[
        "render",
        "--width",
        "160",
        "--height",
        "90",
        "--frames",
        &frames,
        "--no-write",
        "--json",
        "--timeline",
        trace.to_str().expect("UTF-8 path"),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "relief render failed:\n{err}");
    let report: Value = serde_json::from_slice(&out.stdout).expect("--json prints JSON");
    let bytes = std::fs::read(&trace).expect("the timeline is written");
    (
        report,
        serde_json::from_slice(&bytes).expect("the timeline is JSON"),
    )
}

fn names(list: &Value) -> BTreeSet<String> {
    list.as_array()
        .expect("a list of passes")
        .iter()
        .map(|p| p["pass"].as_str().expect("a pass name").to_owned())
        .collect()
}

/// Checks one event against the trace-event format's fields for its phase.
fn check_event(e: &Value) {
    let ph = e["ph"].as_str().expect("every event has a phase");
    assert!(e["name"].is_string(), "every event is named: {e}");
    assert!(e["pid"].is_u64() && e["tid"].is_u64(), "pid and tid: {e}");
    match ph {
        "M" => {
            let name = e["name"].as_str().unwrap();
            assert!(
                name == "process_name" || name == "thread_name",
                "metadata names a process or a thread: {e}"
            );
            assert!(
                e["args"]["name"].is_string(),
                "metadata carries its name: {e}"
            );
        }
        "X" => {
            let ts = e["ts"].as_f64().expect("a start in microseconds");
            let dur = e["dur"].as_f64().expect("a duration in microseconds");
            assert!(ts.is_finite() && ts >= 0.0, "start: {e}");
            assert!(dur.is_finite() && dur >= 0.0, "no negative duration: {e}");
            assert!(e["cat"].is_string(), "category: {e}");
            let frame = e["args"]["frame"].as_u64().expect("the frame number");
            assert!((1..=FRAMES).contains(&frame), "frame numbered from 1: {e}");
        }
        other => panic!("only complete and metadata events are written, got {other}: {e}"),
    }
}

#[test]
fn a_ten_frame_render_traces_every_pass_of_every_frame_on_one_clock() {
    let dir = common::scratch_dir("timeline");
    let (report, trace) = render_with_timeline(&dir);
    assert!(trace["displayTimeUnit"] == "ms" || trace["displayTimeUnit"] == "ns");
    let events = trace["traceEvents"].as_array().expect("traceEvents");
    events.iter().for_each(check_event);
    let tracks: BTreeSet<u64> = events
        .iter()
        .filter(|e| e["name"] == "thread_name")
        .map(|e| e["tid"].as_u64().unwrap())
        .collect();
    assert_eq!(tracks.len(), 2, "a host track and a GPU track");

    let first = names(&report["passes"]);
    let steady = names(&report["steady"]);
    let counted = report["device"]["pipeline_statistics"] == true;
    for frame in 1..=FRAMES {
        let of_frame = |cat: &str| -> Vec<&Value> {
            events
                .iter()
                .filter(|e| e["cat"] == cat && e["args"]["frame"] == frame)
                .collect()
        };
        let gpu: BTreeSet<String> = of_frame("gpu")
            .iter()
            .map(|e| e["name"].as_str().unwrap().to_owned())
            .collect();
        let expected = if frame == 1 { &first } else { &steady };
        assert_eq!(&gpu, expected, "frame {frame}'s passes on the GPU track");
        let host: BTreeSet<&str> = of_frame("host")
            .iter()
            .map(|e| e["name"].as_str().unwrap())
            .collect();
        assert_eq!(
            host,
            BTreeSet::from(["record", "retire", "submit"]),
            "frame {frame}'s host work"
        );
        // The GPU runs a frame's scopes in recording order.
        let starts: Vec<f64> = of_frame("gpu")
            .iter()
            .map(|e| e["ts"].as_f64().unwrap())
            .collect();
        assert!(
            starts.windows(2).all(|w| w[0] <= w[1]),
            "frame {frame}: {starts:?}"
        );
        if counted {
            let surface = of_frame("gpu")
                .into_iter()
                .find(|e| e["name"] == "surface")
                .expect("a surface pass");
            let counts = &surface["args"]["counts"];
            assert!(
                counts["vertex_invocations"].as_u64().unwrap() > 0,
                "{surface}"
            );
            assert!(
                counts["fragment_invocations"].as_u64().unwrap() > 0,
                "{surface}"
            );
        }
    }
    // A frame's passes run after its submission began, on the calibrated clock or from it: at
    // most the calibration's uncertainty early (a loaded machine can stall the thread between
    // the calibration's two host readings).
    let slack = trace["otherData"]["clock_uncertainty_us"]
        .as_f64()
        .expect("the clock's uncertainty");
    let submit_of = |frame: u64| {
        events
            .iter()
            .find(|e| e["name"] == "submit" && e["args"]["frame"] == frame)
            .and_then(|e| e["ts"].as_f64())
            .unwrap()
    };
    for e in events.iter().filter(|e| e["cat"] == "gpu") {
        let frame = e["args"]["frame"].as_u64().unwrap();
        assert!(
            e["ts"].as_f64().unwrap() + slack >= submit_of(frame),
            "{e} (calibration uncertainty {slack} us)"
        );
    }
    assert!(trace["otherData"]["clock_alignment"].is_string());
}

#[test]
fn two_runs_of_a_still_scene_count_the_same_work() {
    let dir = common::scratch_dir("timeline-counts");
    let (a, _) = render_with_timeline(&dir);
    let (b, _) = render_with_timeline(&dir);
    if a["device"]["pipeline_statistics"] != true {
        eprintln!("SKIPPED: this device has no pipeline statistics queries");
        return;
    }
    let counts = |r: &Value| -> Vec<(String, Value)> {
        r["steady"]
            .as_array()
            .unwrap()
            .iter()
            .map(|p| (p["pass"].as_str().unwrap().to_owned(), p["counts"].clone()))
            .collect()
    };
    let (ca, cb) = (counts(&a), counts(&b));
    assert!(
        ca.iter().all(|(_, c)| c.is_object()),
        "every steady pass counted: {ca:?}"
    );
    assert_eq!(ca, cb, "invocation counts of two runs");
}

#[test]
fn a_timeline_that_is_not_json_by_name_is_refused() {
    let out = relief(&["render", "--no-write", "--timeline", "trace.txt"]);
    assert_usage_failure(&out, &["--timeline", "trace.txt", ".json"]);
}

#[test]
fn the_bench_lays_its_frame_costs_on_a_timeline() {
    let dir = common::scratch_dir("bench-timeline");
    let trace = dir.join("bench-timeline.json");
    let out = relief(&[
        "bench",
        "--quick",
        "--frame-costs-only",
        "--timeline",
        trace.to_str().expect("UTF-8 path"),
        "--out",
        dir.join("out").to_str().expect("UTF-8 path"),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "relief bench failed:\n{err}");
    let trace: Value =
        serde_json::from_slice(&std::fs::read(&trace).expect("written")).expect("JSON");
    let events = trace["traceEvents"].as_array().expect("traceEvents");
    let renderers: BTreeSet<&str> = events
        .iter()
        .filter(|e| e["ph"] == "X")
        .map(|e| {
            assert!(e["dur"].as_f64().is_some_and(|d| d >= 0.0), "{e}");
            e["args"]["renderer"]
                .as_str()
                .expect("every span names its renderer")
        })
        .collect();
    for label in ["plain 320x180", "look 320x180", "plain 160x90"] {
        assert!(renderers.contains(label), "{label} in {renderers:?}");
    }
    let surfaces = events
        .iter()
        .filter(|e| e["name"] == "surface" && e["args"]["renderer"] == "look 320x180")
        .count();
    assert_eq!(
        surfaces, 4,
        "the look's untimed frame and its three timed ones"
    );
    let refused = relief(&[
        "bench",
        "--stability-only",
        "--timeline",
        "t.json",
        "--out",
        dir.join("refused").to_str().unwrap(),
    ]);
    assert_usage_failure(&refused, &["--timeline", "frame-cost"]);
}
