//! Bad input through the binary: one clear error line naming the file, a non-zero exit, no panic.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::cli::relief;

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

fn render_with(map: &Path) -> Output {
    let out = map.with_extension("out.png");
    relief(&[
        "render",
        "--heightmap",
        map.to_str().expect("utf-8 path"),
        "--out",
        out.to_str().expect("utf-8"),
    ])
}

#[test]
fn missing_height_map() {
    let dir = common::scratch_dir("missing");
    let map = dir.join("no-such-map.png");
    let out = render_with(&map);
    common::cli::assert_clean_failure(&out, &["no-such-map.png"]);
    assert!(stderr(&out).contains("cannot read"), "{}", stderr(&out));
}

#[test]
fn not_an_image() {
    let dir = common::scratch_dir("not-image");
    let map = dir.join("notes.png");
    std::fs::write(&map, "these are words, not pixels\n").expect("write");
    let out = render_with(&map);
    common::cli::assert_clean_failure(&out, &["notes.png"]);
    assert!(
        stderr(&out).contains("not a decodable image"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn empty_image() {
    let dir = common::scratch_dir("empty");
    let map = dir.join("empty.png");
    std::fs::write(&map, b"").expect("write");
    let out = render_with(&map);
    common::cli::assert_clean_failure(&out, &["empty.png"]);
    assert!(stderr(&out).contains("empty"), "{}", stderr(&out));
}

#[test]
fn zero_depth_scale() {
    let out = relief(&["render", "--depth-scale", "0", "--out", "/dev/null"]);
    common::cli::assert_usage_failure(&out, &["--depth-scale"]);
}

#[test]
fn unknown_method() {
    // Refused by the argument parser (exit 2), with the known ids.
    let out = relief(&["render", "--method", "warp", "--out", "/dev/null"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("unknown method \"warp\"; known methods: parallax"));
}

#[test]
fn map_larger_than_the_device_allows() {
    if common::device("map_larger_than_the_device_allows").is_none() {
        return;
    }
    let listed = relief(&["devices", "--json"]);
    assert!(
        listed.status.success(),
        "devices --json: {}",
        stderr(&listed)
    );
    let devices: serde_json::Value = serde_json::from_slice(&listed.stdout).expect("JSON list");
    let limit = devices[0]["max_image_dimension_2d"]
        .as_u64()
        .expect("limit") as u32;
    let dir = common::scratch_dir("too-large");
    let map = dir.join("too-wide.png");
    image::GrayImage::new(limit + 1, 1)
        .save(&map)
        .expect("write PNG");
    let out = render_with(&map);
    common::cli::assert_clean_failure(&out, &["too-wide.png"]);
    assert!(
        stderr(&out).contains(&format!("maximum image dimension {limit}")),
        "{}",
        stderr(&out)
    );
}

#[test]
fn no_vulkan_driver_exits_77_with_install_line() {
    let out = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(["devices"])
        .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
        .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
        .output()
        .expect("binary runs");
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(77), "stderr:\n{err}");
    assert!(
        err.contains("apt-get install"),
        "says how to install a device:\n{err}"
    );
    assert!(!err.contains("panicked"));
}

#[test]
fn missing_scene_file() {
    let dir = common::scratch_dir("missing_scene");
    let scene = dir.join("no-such-scene.gltf");
    let out = relief(&["render", scene.to_str().expect("utf-8")]);
    common::cli::assert_clean_failure(&out, &["no-such-scene.gltf"]);
}

#[test]
fn broken_scene_file() {
    let dir = common::scratch_dir("broken_scene");
    let scene = dir.join("broken.gltf");
    std::fs::write(
        &scene,
        "{\"asset\": {\"version\": \"2.0\"}, \"nodes\": [{\"mesh\": 7}]}",
    )
    .expect("writes");
    let out = relief(&["render", scene.to_str().expect("utf-8")]);
    common::cli::assert_clean_failure(&out, &["broken.gltf"]);
}

#[test]
fn material_flag_without_a_height_map_or_naming_nothing() {
    let Some(corpus) = common::corpus::corpus("material_flag") else {
        return;
    };
    let plane = corpus.join("gltf/sascha/plane.gltf");
    let plane = plane.to_str().expect("utf-8");
    let out = relief(&["render", plane, "--material", "Floor"]);
    common::cli::assert_usage_failure(&out, &["--heightmap"]);
    let out = relief(&[
        "render",
        plane,
        "--field",
        "bricks",
        "--size",
        "64",
        "--material",
        "NoSuch",
    ]);
    common::cli::assert_usage_failure(&out, &["plane.gltf"]);
    assert!(
        stderr(&out).contains("its materials:"),
        "lists the materials"
    );
}

#[test]
fn bad_shading_flags_name_the_flag() {
    // Unknown mode ids are usage errors, caught by the argument parser (exit 2) with the list.
    for (flag, value, needle) in [
        (
            "--shadows",
            "soft",
            "unknown shadow mode \"soft\"; known modes: none, hard",
        ),
        (
            "--ao",
            "horizon-5",
            "unknown AO mode \"horizon-5\"; known modes: none",
        ),
    ] {
        let out = relief(&["render", flag, value, "--out", "/dev/null"]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{err}");
        assert!(err.contains(needle) && !err.contains("panicked"), "{err}");
    }
    let out = relief(&["render", "--light-radius", "95", "--out", "/dev/null"]);
    common::cli::assert_clean_failure(&out, &["--light-radius 95 is above 90 degrees"]);
    let trace = [
        "trace",
        "--field",
        "fbm",
        "--size",
        "8",
        "--shadows",
        "cone",
    ];
    let out = relief(&[&trace[..], &["--light-elevation", "120"]].concat());
    common::cli::assert_clean_failure(&out, &["--light-elevation must be in [-90, 90]"]);
    let out = relief(&[&trace[..], &["--light-radius", "nan"]].concat());
    common::cli::assert_clean_failure(&out, &["--light-radius must be in [0, 90]"]);
}

#[test]
fn devices_name_ray_query_support_and_old_lavapipe() {
    if common::device("devices_name_ray_query_support").is_none() {
        return;
    }
    let listed = relief(&["devices", "--json"]);
    assert!(listed.status.success(), "{}", stderr(&listed));
    let devices: serde_json::Value = serde_json::from_slice(&listed.stdout).expect("JSON list");
    let first = &devices[0];
    let ray_query = first["ray_query"].as_bool().expect("ray_query");
    assert!(first["acceleration_structure"].is_boolean(), "{first}");
    let text = relief(&["devices"]);
    let out = String::from_utf8_lossy(&text.stdout);
    let yes_no = if ray_query { "yes" } else { "no" };
    assert!(
        out.contains(&format!("ray queries {yes_no}")),
        "the table disagrees with --json: {out}"
    );
    let leak = &first["known_frame_leak"];
    assert_eq!(
        leak.is_string(),
        out.contains("warning: lavapipe of Mesa"),
        "{out}"
    );
    if common::under_ci() && first["kind"] == "cpu" {
        // CI's machines have no GPU and take lavapipe from Debian's backports
        // (scripts/lavapipe.sh): one that holds memory flat and traces ray queries.
        assert!(leak.is_null(), "CI runs on a leaking lavapipe: {leak}");
        assert!(ray_query, "CI's lavapipe offers no ray queries: {first}");
    }
}

#[test]
fn bad_image_sizes_and_sample_counts_are_usage_errors_before_any_device() {
    // Refused by the argument parser: exit 2, one line naming the flag and what it takes, and no
    // device made (none is needed to see it, so none is asked for: this runs with no driver).
    for (flag, value, says) in [
        ("--msaa", "3", "must be 1, 2, 4 or 8 samples per pixel"),
        ("--width", "0", "an image side is 1 to 16384 pixels"),
        ("--height", "99999", "an image side is 1 to 16384 pixels"),
        ("--supersample", "5", "must be 1 to 4"),
    ] {
        let out = Command::new(env!("CARGO_BIN_EXE_relief"))
            .args(["render", flag, value, "--out", "/dev/null"])
            .env("VK_DRIVER_FILES", "/nonexistent/icd.json")
            .env("VK_ICD_FILENAMES", "/nonexistent/icd.json")
            .output()
            .expect("binary runs");
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{flag} {value}: {err}");
        assert!(
            err.contains(flag) && err.contains(says) && !err.contains("panicked"),
            "{flag} {value}: {err}"
        );
    }
}

#[test]
fn value_errors_exit_2_before_any_device() {
    // Each is refused before a device is made, so these hold on a machine without one.
    for (args, needle) in [
        (&["--depth-scale", "0"][..], "--depth-scale"),
        (&["--exposure", "nan"][..], "--exposure"),
        (&["--camera", "3"][..], "--camera 3"),
        (&["--material", "Floor"][..], "--material \"Floor\""),
        (&["--lod-fade", "1"][..], "--lod-fade"),
        (&["--shadow-map-size", "3"][..], "--shadow-map-size"),
    ] {
        let mut full = vec!["render", "--out", "/dev/null"];
        full.extend_from_slice(args);
        let out = relief(&full);
        common::cli::assert_usage_failure(&out, &[needle]);
        assert!(
            !stderr(&out).contains("device:"),
            "{args:?} opened a device first: {}",
            stderr(&out)
        );
    }
}
