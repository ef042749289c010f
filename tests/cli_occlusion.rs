//! `relief occlusion` through the binary: traced ambient occlusion against its CPU reference,
//! the dumps, and one clear error line for bad values and for a device without ray queries.

mod common;

use common::cli::relief;

#[test]
fn occlusion_reports_the_traced_and_reference_shares() {
    let dir = common::scratch_dir("cli-occlusion");
    let args = [
        "occlusion",
        "--scene",
        "box-over-relief",
        "--size",
        "64x36",
        "--samples",
        "3",
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
    let pixels = json["pixels"].as_u64().expect("pixels");
    assert!(pixels > 1000, "{json}");
    assert_eq!(json["rays"].as_u64(), Some(9 * pixels), "{json}");
    assert!(json["mean_abs_error"].as_f64() <= Some(0.001), "{json}");
    assert!(
        json["occluded_pixels"].as_u64() > Some(pixels / 10),
        "{json}"
    );
    for name in ["exact.npy", "traced.npy"] {
        let bytes = std::fs::read(dir.join(name)).expect(name);
        assert!(
            bytes.starts_with(b"\x93NUMPY") && bytes.len() > 64 * 36 * 4,
            "{name}"
        );
    }
    let off = std::process::Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .env(relief::vk::RAY_QUERIES_ENV, "0")
        .output()
        .expect("binary runs");
    common::cli::assert_clean_failure(&off, &["has no ray queries"]);
}

#[test]
fn bad_occlusion_flags_name_the_flag() {
    for (args, needle) in [
        (
            &["occlusion", "--radius", "0"][..],
            "--radius must be a positive number",
        ),
        (
            &["occlusion", "--radius", "nan"][..],
            "--radius must be a positive number",
        ),
        (
            &["occlusion", "--samples", "40"][..],
            "--samples must be in 1..=16, got 40",
        ),
    ] {
        let out = relief(args);
        common::cli::assert_clean_failure(&out, &[needle]);
    }
    let out = relief(&["occlusion", "--scene", "teapot"]);
    common::cli::assert_clean_failure(&out, &["unknown shadow scene `teapot`"]);
}
