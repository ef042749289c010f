//! Narrowing `relief bench` narrows the run: flags that narrow the sweep run only the sections
//! they apply to, `--sections` names sections outright, and `results.json` and the report say
//! which sections ran and why the others did not.

mod common;

use serde_json::Value;

fn bench(extra: &[&str], name: &str) -> Value {
    let out = common::scratch_dir(name);
    let mut args = vec![
        "bench",
        "--fields",
        "fbm",
        "--sizes",
        "64",
        "--angles",
        "30",
        "--resolution",
        "32x32",
        "--frames",
        "1",
        "--passes",
        "1",
        "--out",
        out.to_str().expect("UTF-8 path"),
    ];
    args.extend_from_slice(extra);
    let run = common::cli::relief(&args);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "bench failed:\n{err}");
    let report = std::fs::read_to_string(out.join("report.md")).expect("report.md");
    assert!(report.contains("Sections: "), "the report says which ran");
    serde_json::from_slice(&std::fs::read(out.join("results.json")).expect("json")).expect("JSON")
}

fn names(list: &Value) -> Vec<&str> {
    list.as_array()
        .expect("a list")
        .iter()
        .map(|v| {
            v.as_str()
                .or_else(|| v["section"].as_str())
                .expect("a name")
        })
        .collect()
}

#[test]
fn narrowing_flags_run_only_the_sections_they_narrow() {
    if common::device("bench_sections_narrowed").is_none() {
        return;
    }
    let results = bench(
        &["--methods", "qdm", "--no-stability", "--no-blending"],
        "bench-narrowed",
    );
    let sections = &results["sections"];
    assert_eq!(names(&sections["ran"]), ["main"]);
    let skipped = sections["skipped"].as_array().expect("skipped");
    let why = |name: &str| {
        skipped
            .iter()
            .find(|s| s["section"] == name)
            .and_then(|s| s["why"].as_str())
            .unwrap_or_default()
            .to_owned()
    };
    assert!(why("frame-costs").contains("--methods, --fields, --sizes, --angles"));
    assert!(why("stability").contains("--no-"), "{}", why("stability"));
    assert!(results["frame_costs"].is_null() && results["lod"].is_null());
    assert!(!results["runs"].as_array().expect("runs").is_empty());
}

#[test]
fn sections_named_outright_run_beside_a_narrowed_sweep() {
    if common::device("bench_sections_named").is_none() {
        return;
    }
    let results = bench(
        &["--methods", "qdm", "--sections", "main,lod", "--quick"],
        "bench-named",
    );
    assert_eq!(names(&results["sections"]["ran"]), ["main", "lod"]);
    assert!(
        results["lod"].is_object(),
        "the level-of-detail section ran"
    );
    assert!(results["stability"]
        .as_array()
        .expect("stability")
        .is_empty());
}
