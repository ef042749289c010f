//! `relief bench --quick` (the CI sweep) covers every method, writes the report and plots, and
//! no run anywhere, the stability matrix included, produces a NaN hit; its cost curves over depth
//! scale and relief objects on screen keep their points and fit their exponents.

mod common;

use std::process::Command;

use relief::method::Method;

#[test]
fn quick_bench_covers_every_method_without_nan() {
    if common::device("quick_bench_covers_every_method_without_nan").is_none() {
        return;
    }
    let out = common::scratch_dir("bench-quick");
    let run = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["bench", "--quick", "--out", out.to_str().expect("utf-8")])
        .output()
        .expect("binary runs");
    assert!(
        run.status.success(),
        "bench failed:\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let results: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("results.json")).expect("results.json"))
            .expect("JSON");
    let runs = results["runs"].as_array().expect("runs");
    for m in Method::all() {
        assert!(
            runs.iter().any(|r| r["method"] == m.id()),
            "{m} missing from results.json"
        );
    }
    for r in runs {
        assert_eq!(r["nan_pixels"], 0, "NaN in {r}");
        let ms = r["gpu_ms"]["median"].as_f64().expect("gpu ms");
        assert!(ms > 0.0 && ms.is_finite(), "implausible GPU time in {r}");
        // Every timed ray iterates at least once, and a subgroup pays at least its mean ray.
        let timed = &r["timed_steps"];
        let (mean, paid) = (
            timed["mean"].as_f64().expect("timed mean steps"),
            timed["subgroup_mean_max"].as_f64().expect("subgroup steps"),
        );
        assert!(
            timed["subgroup_size"].as_u64().is_some_and(|n| n >= 1),
            "{r}"
        );
        assert!(mean >= 1.0 && paid >= mean - 1e-9, "timed steps in {r}");
        // Where the device counts invocations (lavapipe does), one per ray of the timed grid.
        if let Some(n) = r["compute_invocations"].as_u64() {
            let grid = &r["resolution"];
            let rays = grid[0].as_u64().unwrap() * grid[1].as_u64().unwrap();
            assert!(
                n >= rays
                    && n < rays + 64 * (grid[0].as_u64().unwrap() + grid[1].as_u64().unwrap()),
                "{r}"
            );
        }
        for key in [
            "method",
            "heightfield",
            "size",
            "depth_scale",
            "angle_deg",
            "azimuth_deg",
            "address",
            "budget",
            "frames",
            "error_texels",
            "gross_rate",
            "capped_rate",
            "steps",
        ] {
            assert!(!r[key].is_null(), "run lacks {key}: {r}");
        }
    }
    cost_curves(
        &results,
        &std::fs::read_to_string(out.join("report.md")).expect("report"),
    );
    let stability = results["stability"].as_array().expect("stability");
    assert!(
        stability.len() >= 20 * Method::all().count(),
        "every stiff case for every method"
    );
    for cell in stability {
        assert_eq!(cell["nan_pixels"], 0, "NaN in stability cell {cell}");
        assert!(cell["failed"].is_null(), "stiff case failed: {cell}");
    }
    assert!(results["device"]["name"]
        .as_str()
        .is_some_and(|n| !n.is_empty()));
    // Provenance: which device and driver build exactly, and the machine and its load.
    for uuid in ["device_uuid", "driver_uuid"] {
        let hex = results["device"][uuid].as_str().expect(uuid);
        assert!(
            hex.len() == 32 && hex.chars().all(|c| c.is_ascii_hexdigit()),
            "{uuid}: {hex}"
        );
    }
    let machine = &results["machine"];
    assert!(
        machine["cpus"].as_u64().is_some_and(|n| n >= 1),
        "{machine}"
    );
    assert!(machine["cpu_model"].as_str().is_some_and(|m| !m.is_empty()));
    if std::path::Path::new("/proc/loadavg").exists() {
        assert_eq!(machine["load_before"].as_array().map(Vec::len), Some(3));
        assert_eq!(machine["load_after"].as_array().map(Vec::len), Some(3));
    }
    let report = std::fs::read_to_string(out.join("report.md")).expect("report.md");
    assert!(report.contains("Machine: "), "the report names the machine");
    // Where each method's steps go, drawn beside the error figures.
    assert!(report.contains("### Where the steps go"));
    let grid: Vec<u32> = results["options"]["error_grid"]
        .as_array()
        .expect("error_grid")
        .iter()
        .map(|v| v.as_u64().expect("a side") as u32)
        .collect();
    for m in Method::all() {
        let file = format!("steps-{}.png", m.id());
        assert!(
            report.contains(&format!("]({file})")),
            "{file} in the report"
        );
        let map = image::open(out.join(&file)).expect("a steps map").to_rgb8();
        assert_eq!(
            map.dimensions(),
            (grid[0] + 12, grid[1]),
            "{file}: the grid and its bar"
        );
    }
    // The scene-shadow section traces its light by ray query beside the maps, where it can.
    let shadows = &results["scene_shadows"];
    match shadows["traced"].as_array().map(Vec::as_slice) {
        Some([_, _, ..]) => {
            for cell in shadows["traced"].as_array().expect("traced") {
                assert!(cell["hard_agreement"].as_f64() >= Some(0.999), "{cell}");
                assert!(cell["rays"].as_u64() > Some(0) && cell["trace_ms"].as_f64() > Some(0.0));
            }
            assert_eq!(shadows["traced"][0]["caster"], "displaced");
            assert!(shadows["traced"][0]["prisms_tested"].as_u64() > Some(0));
            assert!(report.contains("The same light traced by ray query"));
        }
        _ => {
            let why = shadows["traced_skipped"].as_str().expect("a reason");
            assert!(!common::under_ci(), "CI's lavapipe has ray queries: {why}");
            assert!(report.contains("No shadows traced by ray query"));
        }
    }
    for heading in [
        "## 1. Error against run time",
        "## 2. Scaling with map size",
        "Iterations of the timed rays",
        "## 3. Depth scale",
        "## 5. Stability matrix",
    ] {
        assert!(report.contains(heading), "report lacks {heading:?}");
    }
    for plot in ["error_vs_ms.svg", "ms_vs_size.svg", "steps_vs_angle.svg"] {
        let svg = std::fs::read_to_string(out.join(plot)).expect("plot written");
        assert!(
            svg.starts_with("<svg") && svg.contains("<polyline"),
            "{plot} has data"
        );
    }
}

/// The depth-scale curve: every method at every depth scale of the sweep, with its texel fetches
/// counted, and a fitted exponent per method in the report; the objects-on-screen curve: 1, 4 and
/// 16 quads, whose traced work grows with them, and its exponent.
fn cost_curves(results: &serde_json::Value, report: &str) {
    let runs = results["runs"].as_array().expect("runs");
    let depths = results["options"]["depth_scales"]
        .as_array()
        .expect("depth scales")
        .len();
    assert!(depths >= 2, "a curve needs two depths");
    for m in Method::all() {
        let points: Vec<&serde_json::Value> = runs
            .iter()
            .filter(|r| r["section"] == "depth_curve" && r["method"] == m.id())
            .collect();
        assert_eq!(points.len(), depths, "{m}'s depth curve");
        for p in points {
            let fetches = p["fetches"]["mean"].as_f64().expect("fetches counted");
            assert!(fetches >= 1.0, "every ray fetches: {p}");
        }
        let section = report
            .split("## Cost against depth scale")
            .nth(1)
            .expect("the depth-curve section");
        let row = section
            .lines()
            .find(|l| l.starts_with(&format!("| {} | ", m.id())))
            .unwrap_or_else(|| panic!("{m}'s depth-curve row in the report"));
        assert_eq!(row.matches(" | ").count(), depths + 3, "{row}");
        let exponents: Vec<&str> = row.trim_end_matches(" |").rsplit(" | ").take(3).collect();
        for k in exponents {
            assert!(k.parse::<f64>().is_ok_and(f64::is_finite), "{m}: {row}");
        }
    }
    let objects = results["frame_costs"]["objects"]
        .as_array()
        .expect("objects curve");
    let quads: Vec<u64> = objects
        .iter()
        .map(|o| o["quads"].as_u64().unwrap())
        .collect();
    assert_eq!(quads, [1, 4, 16]);
    let traced: Vec<u64> = objects
        .iter()
        .map(|o| o["work"]["traced_pixels"].as_u64().unwrap())
        .collect();
    assert!(
        traced[0] > 0 && traced[1] > 3 * traced[0] && traced[2] > 3 * traced[1],
        "{traced:?}"
    );
    assert!(objects
        .iter()
        .all(|o| o["work"]["fetches"].as_u64() > o["work"]["steps"].as_u64()));
    assert!(report.contains("Relief objects on screen"));
    assert!(
        report.contains("Time ~ quads^k: **k = "),
        "the exponent is fitted"
    );
}
