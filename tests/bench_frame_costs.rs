//! `relief bench --frame-costs-only`: the default look against the plain frame as a chain whose
//! steps multiply out to the whole, every row and stack timed, and a still view whose steady
//! frames render no shadow map.

mod common;

use std::process::Command;

#[test]
fn frame_costs_chain_multiplies_out_and_a_still_view_keeps_its_maps() {
    if common::device("frame_costs_chain_multiplies_out").is_none() {
        return;
    }
    let out = common::scratch_dir("bench-frame-costs");
    let run = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["bench", "--quick", "--frame-costs-only", "--out"])
        .arg(&out)
        .output()
        .expect("binary runs");
    assert!(
        run.status.success(),
        "bench failed: {}",
        String::from_utf8_lossy(&run.stderr)
    );
    let text = std::fs::read_to_string(out.join("results.json")).expect("results.json");
    let results: serde_json::Value = serde_json::from_str(&text).expect("JSON");
    assert!(
        results["runs"].as_array().is_some_and(Vec::is_empty),
        "--frame-costs-only ran the method sweep"
    );
    let s = &results["frame_costs"];
    let number = |v: &serde_json::Value| v.as_f64().expect("a number");
    for row in s["rows"].as_array().expect("rows") {
        let ms = number(&row["gpu_ms"]);
        assert!(ms > 0.0 && ms.is_finite(), "implausible time in {row}");
    }
    let chain: f64 = s["chain"]
        .as_array()
        .expect("chain")
        .iter()
        .map(|c| number(&c["ratio"]))
        .product();
    let whole = number(&s["look_over_plain"]);
    assert!(
        (chain / whole - 1.0).abs() < 1e-9,
        "the chain's steps multiply to {chain}, the look over plain is {whole}"
    );
    // Deferred lighting frame for frame against forward, at one sample; where the device has
    // ray queries (CI's lavapipe does), traced shadows against the deferred look's maps too.
    let deferred = s["deferred"].as_array().expect("deferred");
    let rays = results["device"]["ray_query"].as_bool().unwrap_or(false);
    assert_eq!(deferred.len(), if rays { 4 } else { 3 }, "{deferred:?}");
    for step in deferred {
        let ratio = number(&step["ratio"]);
        assert!(ratio > 0.0 && ratio.is_finite(), "{step}");
        assert!(
            step["to"]
                .as_str()
                .is_some_and(|t| t.ends_with(", deferred") || t.ends_with("traced shadows")),
            "{step}"
        );
    }
    let stacks = s["stacks"].as_array().expect("stacks");
    assert_eq!(stacks.len(), 2, "the 0.25 and the 1-unit stacks");
    for stack in stacks {
        for key in ["one_ms", "nearest_first_ms", "farthest_first_ms"] {
            let ms = number(&stack[key]);
            assert!(ms > 0.0 && ms.is_finite(), "{key} in {stack}");
        }
    }
    assert_eq!(
        number(&s["still_shadow_share"]),
        0.0,
        "a still view's steady frames rendered shadow maps"
    );
    let report = std::fs::read_to_string(out.join("report.md")).expect("report.md");
    assert!(
        report.contains("## Frame costs") && report.contains("Deferred lighting"),
        "report lacks the section or its deferred table"
    );
}
