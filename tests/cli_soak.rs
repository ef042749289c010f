//! `relief soak` through the binary: a short soak of the default scene passes and writes its
//! samples; a run too short to fit a line after its warm-up is refused before any device work.

mod common;

use std::process::Command;

fn relief() -> Command {
    Command::new(env!("CARGO_BIN_EXE_relief"))
}

#[test]
fn a_short_soak_of_the_default_scene_holds_flat_and_writes_its_samples() {
    let Some(ctx) = common::device("cli_soak") else {
        return;
    };
    if let Some(why) = &ctx.info().known_frame_leak {
        eprintln!("SKIPPED: cli_soak: {why}");
        return;
    }
    drop(ctx);
    let dir = common::scratch_dir("cli-soak");
    let csv = dir.join("samples.csv");
    let out = relief()
        .args(["soak", "--frames", "90", "--every", "10", "--warm-up", "30"])
        .args(["--width", "96", "--height", "54", "--csv"])
        .arg(&csv)
        .output()
        .expect("runs relief");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{stdout}\n{stderr}");
    assert!(
        stdout.contains("growth a frame after 30 warm-up frames"),
        "{stdout}"
    );
    assert!(
        stdout.contains("no Vulkan object or allocation"),
        "{stdout}"
    );
    let text = std::fs::read_to_string(&csv).expect("the samples");
    let lines: Vec<&str> = text.lines().collect();
    assert!(lines[0].starts_with("frame,rss_bytes,pipelines,"), "{text}");
    // Samples every 10 retired frames; the last frames retire at finish, unsampled.
    assert!((8..=9).contains(&(lines.len() - 1)), "{text}");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_soak_too_short_to_fit_is_refused_as_bad_usage() {
    let out = relief()
        .args([
            "soak",
            "--frames",
            "100",
            "--every",
            "50",
            "--warm-up",
            "20",
        ])
        .output()
        .expect("runs relief");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("leaves 1 sample(s) to fit; at least 3 are needed"),
        "{stderr}"
    );
    let zero = relief()
        .args(["soak", "--every", "0"])
        .output()
        .expect("runs relief");
    assert_eq!(zero.status.code(), Some(2));
    assert!(String::from_utf8_lossy(&zero.stderr).contains("--every must be at least 1"));
}
