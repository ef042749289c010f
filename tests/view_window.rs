//! `relief view` through a real swapchain: under Xvfb (started here when installed, on a free
//! display), the default scene's last frame read back from the swapchain matches an offscreen
//! render of the same view within the golden tolerances, before and after a scripted resize, with
//! the validation layer on. Without Xvfb the window tests print SKIPPED. Without any display the
//! viewer fails with one line, and `render` never needs a display or links a display library.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::xvfb::Xvfb;

use relief::render::{render, RenderOptions};
use relief::scene::{default_heightfield, default_scene, DEFAULT_SCENE_METHOD};

fn view(display: Option<&str>, args: &[&str]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_relief"));
    cmd.arg("view")
        .args(args)
        .env_remove("WAYLAND_DISPLAY")
        .env_remove("WAYLAND_SOCKET");
    match display {
        Some(d) => cmd.env("DISPLAY", d),
        None => cmd.env_remove("DISPLAY"),
    };
    cmd.output().expect("runs relief")
}

/// The default scene rendered offscreen at `width` x `height`, as `relief render` draws it
/// (the command line's 4x MSAA, PBR Neutral tone mapping and built-in sky, lighting and
/// behind the scene).
fn offscreen(width: u32, height: u32) -> Option<Vec<u8>> {
    let ctx = common::device("view offscreen reference")?;
    let opts = RenderOptions::finished(width, height);
    let frame = render(
        &ctx,
        &default_scene(DEFAULT_SCENE_METHOD),
        Some(&default_heightfield()),
        &opts,
    )
    .expect("renders offscreen");
    common::assert_no_validation_errors(&ctx);
    Some(frame.rgba)
}

/// Compares the screenshot at `path` with the offscreen render at the same size.
fn assert_matches_offscreen(path: &Path, width: u32, height: u32, what: &str) {
    let shot = image::open(path)
        .unwrap_or_else(|e| panic!("{what}: screenshot {}: {e}", path.display()))
        .to_rgba8();
    assert_eq!(
        shot.dimensions(),
        (width, height),
        "{what}: screenshot size"
    );
    let Some(expected) = offscreen(width, height) else {
        return;
    };
    let (mean, p99, diff) = common::golden::compare(shot.as_raw(), &expected);
    if mean > common::golden::MAX_MEAN_DIFF || p99 > common::golden::MAX_P99_DIFF {
        let dir = common::evidence_dir("view");
        image::save_buffer(
            dir.join(format!("{what}_diff.png")),
            &diff,
            width,
            height,
            image::ColorType::Rgba8,
        )
        .expect("writes the difference image");
        panic!(
            "{what}: the swapchain's frame differs from the offscreen render: mean {mean:.3}, \
             p99 {p99}; difference image in {}",
            dir.display()
        );
    }
}

/// Checks a finished viewer run: success, the device line, validation on under CI.
fn assert_ran(out: &Output, what: &str) -> String {
    let stderr = String::from_utf8_lossy(&out.stderr).into_owned();
    assert!(
        out.status.success(),
        "{what}: relief view failed:\n{stderr}"
    );
    if common::under_ci() {
        assert!(
            stderr.contains("validation on"),
            "{what}: under CI the viewer must run with the validation layer:\n{stderr}"
        );
    }
    stderr
}

#[test]
fn thirty_frames_through_the_swapchain_match_the_offscreen_render() {
    let Some(x) = Xvfb::start("thirty_frames_through_the_swapchain") else {
        return;
    };
    let dir = common::scratch_dir("view_thirty_frames");
    let shot = dir.join("shot.png");
    let out = view(
        Some(&x.display),
        &[
            "--width",
            "192",
            "--height",
            "108",
            "--frames",
            "30",
            "--no-vsync",
            "--screenshot",
            shot.to_str().expect("utf-8 path"),
        ],
    );
    let stderr = assert_ran(&out, "30 frames");
    assert!(stderr.contains("30 frame(s)"), "{stderr}");
    assert!(
        stderr.contains("surface"),
        "the readout names the passes: {stderr}"
    );
    assert_matches_offscreen(&shot, 192, 108, "thirty_frames");
}

#[test]
fn a_resize_mid_run_rebuilds_the_swapchain_and_targets() {
    let Some(x) = Xvfb::start("a_resize_mid_run") else {
        return;
    };
    let dir = common::scratch_dir("view_resize");
    let shot = dir.join("shot.png");
    let out = view(
        Some(&x.display),
        &[
            "--width",
            "160",
            "--height",
            "90",
            "--frames",
            "30",
            "--resize-at",
            "10:240x136",
            "--screenshot",
            shot.to_str().expect("utf-8 path"),
        ],
    );
    assert_ran(&out, "resize");
    assert_matches_offscreen(&shot, 240, 136, "resized");
}

#[test]
fn without_a_display_the_viewer_says_so_in_one_line() {
    let out = view(None, &["--frames", "1"]);
    assert!(!out.status.success());
    let stderr = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = stderr.lines().collect();
    assert_eq!(lines.len(), 1, "one line: {stderr}");
    assert!(
        lines[0].starts_with("relief: error:") && lines[0].contains("no display"),
        "{stderr}"
    );
    assert!(lines[0].contains("Xvfb"), "says what to do: {stderr}");
}

#[test]
fn bad_view_flags_are_refused_before_any_window() {
    for (args, says) in [
        (&["--resize-at", "10:0x5"][..], "1..=16384"),
        (&["--resize-at", "ten"][..], "N:WxH"),
        (&["--screenshot", "x.png"][..], "--frames"),
        (&["--frames", "0"][..], "frames"),
    ] {
        let out = view(None, args);
        assert!(!out.status.success(), "{args:?} must fail");
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(stderr.contains(says), "{args:?}: {stderr}");
    }
}

#[test]
fn render_needs_no_display_library() {
    // The window system's libraries are loaded by the viewer at run time, never linked.
    let Ok(out) = Command::new("ldd")
        .arg(env!("CARGO_BIN_EXE_relief"))
        .output()
    else {
        eprintln!("SKIPPED: render_needs_no_display_library: no ldd");
        return;
    };
    let libs = String::from_utf8_lossy(&out.stdout);
    for lib in ["libX11", "libxcb", "libwayland", "libxkbcommon"] {
        assert!(!libs.contains(lib), "relief links {lib}:\n{libs}");
    }
}
