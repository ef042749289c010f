//! `relief render`'s files as a pipeline meets them: a batch over three scenes with one broken
//! writes the good two and exits 1; `--camera all` writes one image per camera; a sequence killed
//! part way leaves only whole files and `--resume` draws only what is missing; the camera
//! sidecar, 16-bit PNGs and the chosen render outputs (OpenEXR channels and 16-bit layer PNGs)
//! hold what they say; and the flags that cannot go together are refused before any device.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

use common::cli::{assert_usage_failure, relief};
use common::mesh_gltf::{write_mesh, TETRAHEDRON, TETRAHEDRON_FACES};

fn ok(out: &std::process::Output) -> String {
    let err = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(out.status.success(), "relief failed:\n{err}");
    err
}

fn path_arg(path: &Path) -> &str {
    path.to_str().expect("a UTF-8 path")
}

/// The tetrahedron's glTF with two cameras added, looking at it from the front and the side.
fn with_two_cameras(dir: &Path) -> PathBuf {
    let path = write_mesh(dir, "tetra", &TETRAHEDRON, &TETRAHEDRON_FACES);
    let mut doc: serde_json::Value =
        serde_json::from_slice(&std::fs::read(&path).expect("reads")).expect("JSON");
    let lens = serde_json::json!({"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 50.0}});
    doc["cameras"] = serde_json::json!([lens, lens]);
    let half_turn = std::f64::consts::FRAC_1_SQRT_2;
    doc["nodes"]
        .as_array_mut()
        .expect("nodes")
        .extend([
            serde_json::json!({"camera": 0, "translation": [2.3, 0.3, 4.0]}),
            // A quarter turn about y: looking down -x, from +x.
            serde_json::json!({"camera": 1, "translation": [6.0, 0.3, 0.3], "rotation": [0.0, half_turn, 0.0, half_turn]}),
        ]);
    doc["scenes"][0]["nodes"] = serde_json::json!([0, 1, 2]);
    let cameras = dir.join("cameras.gltf");
    std::fs::write(&cameras, doc.to_string()).expect("writes");
    cameras
}

#[test]
fn a_batch_writes_its_good_scenes_and_fails_for_the_broken_one() {
    if common::device("a_batch_writes_its_good_scenes").is_none() {
        return;
    }
    let dir = common::scratch_dir("batch");
    let good = write_mesh(&dir, "tetra", &TETRAHEDRON, &TETRAHEDRON_FACES);
    let broken = dir.join("broken.gltf");
    std::fs::write(&broken, "{ this is not JSON").expect("writes");
    let cameras = with_two_cameras(&dir);
    // The three scenes at a small size into `out`, with `extra` flags.
    let batch = |out: &Path, extra: &[&str]| {
        let mut args = vec![
            "render",
            path_arg(&good),
            path_arg(&broken),
            path_arg(&cameras),
        ];
        args.extend(["--width", "48", "--height", "32", "--out", path_arg(out)]);
        args.extend(extra);
        relief(&args)
    };
    let run = batch(&dir.join("shots").join("frame.png"), &[]);
    let err = String::from_utf8_lossy(&run.stderr);
    common::cli::assert_clean_failure(&run, &["1 of 3", "broken.gltf"]);
    assert!(err.contains("broken.gltf failed"), "{err}");
    assert!(err.contains("2 drawn, 1 failed"), "no summary:\n{err}");
    let mut written: Vec<String> = std::fs::read_dir(dir.join("shots"))
        .expect("shots/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    written.sort();
    assert_eq!(written, ["frame_cameras.png", "frame_tetra.png"]);
    // --fail-fast stops at the broken scene: the third is not drawn.
    let run = batch(&dir.join("fast").join("frame.png"), &["--fail-fast"]);
    common::cli::assert_clean_failure(&run, &["1 of 2", "broken.gltf"]);
    assert!(dir.join("fast").join("frame_tetra.png").is_file());
    assert!(!dir.join("fast").join("frame_cameras.png").exists());
}

#[test]
fn every_camera_of_a_scene_draws_its_own_image() {
    if common::device("every_camera_of_a_scene_draws_its_own_image").is_none() {
        return;
    }
    let dir = common::scratch_dir("all-cameras");
    let cameras = with_two_cameras(&dir);
    let out = dir.join("frame.png");
    let json = dir.join("frame.json");
    let run = relief(&[
        "render",
        path_arg(&cameras),
        "--camera",
        "all",
        "--width",
        "48",
        "--height",
        "32",
        "--out",
        path_arg(&out),
        "--camera-out",
        path_arg(&json),
    ]);
    ok(&run);
    let eye = |k: u32| -> Vec<f64> {
        let text = std::fs::read_to_string(dir.join(format!("frame_cam{k}.json"))).expect("JSON");
        let value: serde_json::Value = serde_json::from_str(&text).expect("parses");
        value["eye"]
            .as_array()
            .expect("eye")
            .iter()
            .map(|v| v.as_f64().expect("number"))
            .collect()
    };
    let (front, side) = (eye(0), eye(1));
    assert!(
        (front[2] - 4.0).abs() < 1e-4,
        "camera 0 stands at z 4: {front:?}"
    );
    assert!(
        (side[0] - 6.0).abs() < 1e-4,
        "camera 1 stands at x 6: {side:?}"
    );
    let a = std::fs::read(dir.join("frame_cam0.png")).expect("camera 0's image");
    let b = std::fs::read(dir.join("frame_cam1.png")).expect("camera 1's image");
    assert_ne!(a, b, "two cameras drew the same image");
    let built_in = relief(&["render", "--camera", "all", "--no-write"]);
    assert_usage_failure(&built_in, &["--camera all", "built-in"]);
}

/// Every `f_NNNN.png` in `dir`, each decoded whole.
fn whole_frames(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.starts_with("f_") && n.ends_with(".png"))
        .collect();
    names.sort();
    for name in &names {
        image::open(dir.join(name)).unwrap_or_else(|e| panic!("{name} is not whole: {e}"));
    }
    names
}

#[test]
fn a_killed_sequence_leaves_whole_files_and_resume_draws_the_rest() {
    if common::device("a_killed_sequence_leaves_whole_files").is_none() {
        return;
    }
    let dir = common::scratch_dir("resume");
    let out = dir.join("f.png");
    let frames = "30";
    let args = [
        "render",
        "--width",
        "96",
        "--height",
        "54",
        "--frames",
        frames,
        "--orbit",
        "90",
        "--out",
        path_arg(&out),
    ];
    let mut child = Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(args)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .expect("starts");
    let started = Instant::now();
    while !dir.join("f_0003.png").exists() {
        assert!(
            started.elapsed() < Duration::from_secs(300),
            "no third frame in 5 minutes"
        );
        if child.try_wait().expect("polls").is_some() {
            break;
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    child.kill().ok();
    child.wait().expect("ends");
    let before = whole_frames(&dir);
    assert!(before.len() >= 3, "{before:?}");
    if before.len() == 30 {
        eprintln!("the sequence finished before it was killed; resume skips every frame");
    }
    // Take one frame away from the middle too: --resume draws exactly the missing ones.
    std::fs::remove_file(dir.join("f_0002.png")).expect("removes frame 2");
    let missing = 30 - (before.len() - 1);
    let mut resumed = args.to_vec();
    resumed.extend(["--resume", "--json"]);
    let run = relief(&resumed);
    ok(&run);
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).expect("one JSON object");
    assert_eq!(report["skipped_written"], 30 - missing as u64, "{report}");
    assert_eq!(report["written"], missing as u64, "{report}");
    assert_eq!(whole_frames(&dir).len(), 30);
    let partial: Vec<_> = std::fs::read_dir(&dir)
        .expect("dir")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".partial"))
        .collect();
    assert!(partial.is_empty(), "partial files left: {partial:?}");
    // The frames drawn again equal those of a whole run.
    let whole = dir.join("whole");
    let mut again = args.to_vec();
    let whole_out = whole.join("f.png");
    *again.last_mut().expect("out") = path_arg(&whole_out);
    ok(&relief(&again));
    for k in [1, 2, 30] {
        let name = format!("f_{k:04}.png");
        let a = image::open(dir.join(&name)).expect("resumed").to_rgba8();
        let b = image::open(whole.join(&name)).expect("whole").to_rgba8();
        assert!(a == b, "{name} differs from the whole run's");
    }
}

#[test]
fn sixteen_bit_pngs_match_the_eight_bit_frame() {
    if common::device("sixteen_bit_pngs_match_the_eight_bit_frame").is_none() {
        return;
    }
    let dir = common::scratch_dir("bit-depth");
    let common_args = ["render", "--width", "96", "--height", "54", "--msaa", "1"];
    let (eight, sixteen) = (dir.join("eight.png"), dir.join("sixteen.png"));
    let mut a = common_args.to_vec();
    a.extend(["--out", path_arg(&eight)]);
    ok(&relief(&a));
    let mut b = common_args.to_vec();
    b.extend(["--out", path_arg(&sixteen), "--bit-depth", "16"]);
    ok(&relief(&b));
    let eight = image::open(&eight).expect("8-bit").to_rgba8();
    let decoded = image::open(&sixteen).expect("16-bit");
    assert!(
        matches!(decoded, image::DynamicImage::ImageRgba16(_)),
        "not a 16-bit RGBA PNG"
    );
    let sixteen = decoded.to_rgba16();
    let mut off = 0;
    let mut finer = 0;
    for (p8, p16) in eight.pixels().zip(sixteen.pixels()) {
        for c in 0..3 {
            let level = f64::from(p16.0[c]) / 257.0;
            off += usize::from((level - f64::from(p8.0[c])).abs() > 1.0);
            finer += usize::from(p16.0[c] % 257 != 0);
        }
    }
    assert_eq!(off, 0, "{off} channels more than one 8-bit level apart");
    assert!(finer > 1000, "the 16-bit frame holds only 8-bit levels");
    let exr = relief(&["render", "--out", "x.exr", "--bit-depth", "16"]);
    assert_usage_failure(&exr, &["--bit-depth 16", "x.exr"]);
}

#[test]
fn chosen_outputs_fill_the_exr_and_their_16_bit_pngs() {
    if common::device("chosen_outputs_fill_the_exr_and_their_16_bit_pngs").is_none() {
        return;
    }
    let dir = common::scratch_dir("aov");
    let out = dir.join("frame.png");
    let exr_path = dir.join("frame.exr");
    let run = relief(&[
        "render",
        "--width",
        "64",
        "--height",
        "48",
        "--out",
        path_arg(&out),
        "--exr-out",
        path_arg(&exr_path),
        "--aov",
        "depth,coverage,shadow,motion",
        "--aov-png",
    ]);
    ok(&run);
    let image = exr::prelude::read_all_flat_layers_from_file(&exr_path).expect("an EXR file");
    let layer = &image.layer_data[0];
    let mut names: Vec<String> = layer
        .channel_data
        .list
        .iter()
        .map(|c| c.name.to_string())
        .collect();
    names.sort();
    assert_eq!(
        names,
        ["A", "B", "G", "R", "Z", "coverage", "motion.X", "motion.Y", "shadow"]
    );
    assert!(
        image.attributes.chromaticities.is_some(),
        "no chromaticities"
    );
    let float = |name: &str| match &layer
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == name)
        .expect("channel")
        .sample_data
    {
        exr::prelude::FlatSamples::F32(v) => v.clone(),
        other => panic!("{name} is not 32-bit float: {other:?}"),
    };
    let coverage = float("coverage");
    let png = image::open(dir.join("frame.coverage.png"))
        .expect("the coverage PNG")
        .into_luma16();
    for (c, p) in coverage.iter().zip(png.as_raw()) {
        assert_eq!(*p, (c.clamp(0.0, 1.0) * 65535.0).round() as u16);
    }
    let depth = image::open(dir.join("frame.depth.png"))
        .expect("the depth PNG")
        .into_luma16();
    for (z, p) in float("Z").iter().zip(depth.as_raw()) {
        assert_eq!(z.is_infinite(), *p == 65535, "depth {z} as {p}");
    }
    assert!(dir.join("frame.shadow.png").is_file());
    assert!(
        !dir.join("frame.motion.png").exists(),
        "motion has two channels: EXR only"
    );
    assert!(
        float("motion.X").iter().all(|&m| m == 0.0),
        "one frame: no motion"
    );
}

#[test]
fn flags_that_cannot_be_written_are_refused_before_any_device() {
    for (args, needles) in [
        (
            &["render", "--aov", "depth"][..],
            &["--aov", "--exr-out"][..],
        ),
        (&["render", "--aov", "normal", "--aov-png"], &["--aov-png"]),
        (&["render", "--resume", "--no-write"], &["--resume"]),
        (
            &["render", "--camera-out", "cam.txt"],
            &["cam.txt", ".json"],
        ),
        (
            &["render", "--aov-png", "--supersample", "2"],
            &["--supersample"],
        ),
        (
            &["render", "--exr-beauty", "tone-mapped"],
            &["--exr-beauty"],
        ),
    ] {
        assert_usage_failure(&relief(args), needles);
    }
    let run = relief(&["render", "--aov", "colour", "--exr-out", "x.exr"]);
    assert_eq!(
        run.status.code(),
        Some(2),
        "an unknown layer is a usage error"
    );
}

#[test]
fn one_command_writes_the_same_bytes_twice_and_tone_maps_its_exr_as_its_png() {
    if common::device("one_command_writes_the_same_bytes_twice").is_none() {
        return;
    }
    let dir = common::scratch_dir("deterministic");
    let run_into = |name: &str| -> PathBuf {
        let sub = dir.join(name);
        let arg = |file: &str| sub.join(file).to_string_lossy().into_owned();
        let args = [
            "render".to_owned(),
            "--width".into(),
            "64".into(),
            "--height".into(),
            "48".into(),
            "--frames".into(),
            "2".into(),
            "--orbit".into(),
            "20".into(),
            "--out".into(),
            arg("f.png"),
            "--bit-depth".into(),
            "16".into(),
            "--exr-out".into(),
            arg("f.exr"),
            "--exr-beauty".into(),
            "tone-mapped".into(),
            "--aov-png".into(),
            "--hdr-out".into(),
            arg("f.hdr"),
            "--camera-out".into(),
            arg("f.json"),
        ];
        let args: Vec<&str> = args.iter().map(String::as_str).collect();
        ok(&relief(&args));
        sub
    };
    let (a, b) = (run_into("a"), run_into("b"));
    let mut names: Vec<String> = std::fs::read_dir(&a)
        .expect("a/")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    assert_eq!(names.len(), 2 * 11, "files of two frames: {names:?}");
    for name in &names {
        let (x, y) = (std::fs::read(a.join(name)), std::fs::read(b.join(name)));
        assert!(x.expect("first") == y.expect("second"), "{name} differs");
    }
    // The tone-mapped EXR, sRGB-encoded, is the 16-bit PNG (both from one radiance, one curve).
    let image = exr::prelude::read_all_flat_layers_from_file(a.join("f_0002.exr")).expect("EXR");
    let layer = &image.layer_data[0];
    let red = layer
        .channel_data
        .list
        .iter()
        .find(|c| c.name.to_string() == "R")
        .expect("R");
    let exr::prelude::FlatSamples::F32(red) = &red.sample_data else {
        panic!("R is not 32-bit float");
    };
    let png = image::open(a.join("f_0002.png")).expect("PNG").to_rgba16();
    for (r, p) in red.iter().zip(png.pixels()) {
        assert!((0.0..=1.0).contains(r), "tone mapped into 0..1: {r}");
        let encoded = if *r <= 0.003_130_8 {
            r * 12.92
        } else {
            1.055 * r.powf(1.0 / 2.4) - 0.055
        };
        assert!(
            (encoded * 65535.0 - f32::from(p.0[0])).abs() < 2.0,
            "{r} encodes to {encoded}, the PNG holds {}",
            p.0[0]
        );
    }
}
