//! The examples under `examples/` run and do what they say, at small sizes: the renders write a
//! PNG of the size asked for that is not blank (the shader-library example its library files
//! too), the timing example prints both methods with
//! finite error and GPU time, and the viewer presents its frames under Xvfb (SKIPPED without it,
//! as the window tests are). Each example checks the validation layer itself and fails on errors.
//!
//! The binaries are the ones `cargo build --examples` (run by scripts/test.sh before the tests)
//! puts beside this test's own executable; `cargo test` alone builds examples only as test
//! harnesses, which do not run `main`.

mod common;

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// The built example `name`, next to this test's executable (`target/<profile>/examples/`).
fn example(name: &str) -> PathBuf {
    let exe = std::env::current_exe().expect("the test knows its executable");
    let profile_dir = exe
        .parent()
        .and_then(Path::parent)
        .expect("tests run from target/<profile>/deps");
    let path = profile_dir
        .join("examples")
        .join(format!("{name}{}", std::env::consts::EXE_SUFFIX));
    assert!(
        path.is_file(),
        "example {name} is not built at {}: run `cargo build --examples` first \
         (scripts/test.sh does)",
        path.display()
    );
    path
}

/// Runs example `name` with `args` to completion, failing the test unless it succeeds.
fn run(name: &str, args: &[&str], display: Option<&str>) -> String {
    let mut cmd = Command::new(example(name));
    cmd.args(args);
    if let Some(d) = display {
        cmd.env("DISPLAY", d)
            .env_remove("WAYLAND_DISPLAY")
            .env_remove("WAYLAND_SOCKET");
    }
    let out: Output = cmd.output().expect("the example starts");
    let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "example {name} {args:?} failed ({}):\nstdout:\n{stdout}\nstderr:\n{}",
        out.status,
        String::from_utf8_lossy(&out.stderr)
    );
    stdout
}

/// Asserts `path` is a PNG of `width` x `height` with more than a few distinct colours.
fn assert_rendered(path: &Path, width: u32, height: u32) {
    let png = image::open(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()))
        .to_rgba8();
    assert_eq!(png.dimensions(), (width, height), "{}", path.display());
    let mut colours: Vec<[u8; 4]> = png.pixels().map(|p| p.0).collect();
    colours.sort_unstable();
    colours.dedup();
    // A lit, displaced surface shades into hundreds of colours; a cleared or flat target has few.
    assert!(
        colours.len() > 32,
        "{} looks blank: {} distinct colours",
        path.display(),
        colours.len()
    );
}

#[test]
fn render_gltf_draws_the_default_scene_without_a_file() {
    if common::device("render_gltf_draws_the_default_scene").is_none() {
        return;
    }
    let out = common::scratch_dir("example_render_gltf").join("frame.png");
    let printed = run(
        "render_gltf",
        &[out.to_str().expect("utf-8 path"), "--size", "96x54"],
        None,
    );
    assert!(printed.contains("surface"), "per-pass times:\n{printed}");
    assert_rendered(&out, 96, 54);
}

#[test]
fn render_gltf_displaces_a_gltf_file() {
    if common::device("render_gltf_displaces_a_gltf_file").is_none() {
        return;
    }
    let dir = common::scratch_dir("example_render_gltf_file");
    let (bin, views, accessors) = common::plane_gltf::plane_buffer(None);
    std::fs::write(dir.join("plane.bin"), &bin).expect("writes the buffer");
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0.0, 1.3, 1.9], "rotation": [-0.3007058, 0.0, 0.0, 0.953717]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 50.0}}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3, "material": 0
        }]}],
        "materials": [{"name": "plane", "pbrMetallicRoughness": {"baseColorFactor": [0.7, 0.5, 0.4, 1.0]}}],
        "buffers": [{"uri": "plane.bin", "byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
    });
    let scene = dir.join("plane.gltf");
    std::fs::write(&scene, gltf.to_string()).expect("writes the glTF");
    let out = dir.join("plane.png");
    run(
        "render_gltf",
        &[
            scene.to_str().expect("utf-8 path"),
            out.to_str().expect("utf-8 path"),
            "--size",
            "80x60",
        ],
        None,
    );
    assert_rendered(&out, 80, 60);
}

#[test]
fn scene_in_code_renders_its_relief_box() {
    if common::device("scene_in_code_renders_its_relief_box").is_none() {
        return;
    }
    let out = common::scratch_dir("example_scene_in_code").join("scene.png");
    run(
        "scene_in_code",
        &[out.to_str().expect("utf-8 path"), "--size", "96x72"],
        None,
    );
    assert_rendered(&out, 96, 72);
}

#[test]
fn shader_library_draws_its_quad_and_writes_the_library() {
    if common::device("shader_library_draws_its_quad").is_none() {
        return;
    }
    let dir = common::scratch_dir("example_shader_library");
    let (out, glsl) = (dir.join("quad.png"), dir.join("glsl"));
    let args = [
        out.to_str().expect("utf-8 path"),
        "--size",
        "96x54",
        "--glsl",
        glsl.to_str().expect("utf-8 path"),
    ];
    let printed = run("shader_library", &args, None);
    assert_rendered(&out, 96, 54);
    assert!(
        printed.contains("QDM"),
        "it says which method drew: {printed}"
    );
    // The folder an engine's compiler includes from: every file, the entry among them.
    let written = std::fs::read_dir(&glsl)
        .expect("the library folder")
        .count();
    assert_eq!(written, relief::shader_library::files().count());
    let entry = std::fs::read_to_string(glsl.join(relief::shader_library::ENTRY)).expect("entry");
    assert!(
        entry.contains("RELIEF_HEIGHT_POINT"),
        "the entry states its contract"
    );
}

#[test]
fn time_methods_prints_finite_error_and_time_for_two_methods() {
    if common::device("time_methods_prints_two_methods").is_none() {
        return;
    }
    let printed = run("time_methods", &["--size", "32"], None);
    let rows: Vec<Vec<&str>> = printed
        .lines()
        .skip(1)
        .map(|l| l.split_whitespace().collect())
        .collect();
    let methods: Vec<&str> = rows.iter().map(|r| r[0]).collect();
    assert_eq!(methods, ["pom", "qdm"], "one row per method:\n{printed}");
    for row in &rows {
        let error: f64 = row[1].parse().expect("the error is a number");
        let ms: f64 = row[3].parse().expect("the time is a number");
        assert!(error.is_finite() && error >= 0.0, "{printed}");
        assert!(ms.is_finite() && ms > 0.0, "{printed}");
    }
}

#[cfg(feature = "window")]
#[test]
fn viewer_presents_a_counted_run_and_writes_its_last_frame() {
    if common::device("viewer_presents_a_counted_run").is_none() {
        return;
    }
    let Some(x) = common::xvfb::Xvfb::start("viewer_presents_a_counted_run") else {
        return;
    };
    let shot = common::scratch_dir("example_viewer").join("last.png");
    let shot_arg = shot.to_str().expect("utf-8 path");
    let printed = run(
        "viewer",
        &["--frames", "5", "--screenshot", shot_arg],
        Some(&x.display),
    );
    assert!(printed.contains("5 frame(s)"), "{printed}");
    assert_rendered(&shot, 640, 360);
}
