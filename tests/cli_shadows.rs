//! `relief shadows` and the shadow-map flags through the binary: the dumps it writes, the
//! agreement it prints, and one clear error line for bad values.

mod common;

use common::cli::relief;

#[test]
fn shadows_writes_both_dumps_and_reports_agreement() {
    let dir = common::scratch_dir("cli-shadows");
    let out = relief(&[
        "shadows",
        "--scene",
        "box-over-plane",
        "--size",
        "64x36",
        "--dump",
        dir.to_str().expect("utf-8"),
        "--json",
    ]);
    let stderr = String::from_utf8_lossy(&out.stderr);
    if out.status.code() == Some(77) {
        eprintln!("SKIPPED: no Vulkan device: {stderr}");
        return;
    }
    assert!(out.status.success(), "{stderr}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let agreement = json["agreement"]["hard_agreement"]
        .as_f64()
        .expect("agreement");
    assert!(agreement >= 0.99, "{json}");
    for name in [
        "exact.npy",
        "relief.npy",
        "relief_maps.npy",
        "relief_own.npy",
    ] {
        let bytes = std::fs::read(dir.join(name)).expect(name);
        assert!(bytes.starts_with(b"\x93NUMPY"), "{name}");
        // 64 x 36 f32 after the header.
        assert!(bytes.len() > 64 * 36 * 4, "{name}: {} bytes", bytes.len());
    }
}

#[test]
fn bad_shadow_flags_name_the_flag() {
    for (args, needle) in [
        (
            &["render", "--shadow-map-size", "8", "--out", "/dev/null"][..],
            "--shadow-map-size must be in 16..=8192, got 8",
        ),
        (
            &["render", "--shadow-cascades", "9", "--out", "/dev/null"][..],
            "--shadow-cascades must be in 1..=4, got 9",
        ),
    ] {
        let out = relief(args);
        common::cli::assert_usage_failure(&out, &[needle]);
    }
    let out = relief(&["shadows", "--scene", "teapot"]);
    common::cli::assert_clean_failure(&out, &["unknown shadow scene `teapot`"]);
    let out = relief(&["render", "--shadow-filter", "blur", "--out", "/dev/null"]);
    assert_eq!(out.status.code(), Some(2));
}

#[test]
fn traced_shadows_report_their_agreement_and_say_when_the_device_cannot() {
    let dir = common::scratch_dir("cli-traced-shadows");
    let args = [
        "shadows",
        "--scene",
        "slab-over-plane",
        "--size",
        "64x36",
        "--traced",
        "--dump",
        dir.to_str().expect("utf-8"),
        "--json",
    ];
    let Some(out) = common::cli::relief_with_ray_queries(&args) else {
        return;
    };
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stderr}");
    let json: serde_json::Value = serde_json::from_slice(&out.stdout).expect("json");
    let traced = &json["traced"];
    assert!(
        traced["everywhere"]["hard_agreement"].as_f64() >= Some(0.999),
        "{json}"
    );
    assert_eq!(traced["everywhere"]["excluded_band"], 0, "{json}");
    assert_eq!(
        traced["structures"]["prisms"], 2,
        "the slab's two relief triangles"
    );
    assert!(traced["prisms_tested"].as_u64() > Some(0), "{json}");
    let bytes = std::fs::read(dir.join("traced.npy")).expect("traced.npy");
    assert!(bytes.len() > 64 * 36 * 4);
    let off = std::process::Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .env(relief::vk::RAY_QUERIES_ENV, "0")
        .output()
        .expect("binary runs");
    common::cli::assert_clean_failure(&off, &["has no ray queries", "VK_KHR_ray_query"]);
}
