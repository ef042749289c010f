//! `relief render --frame-range A..B`: ranges that together cover a sequence write the same files,
//! byte for byte, as the whole sequence (an orbit, and terrain strokes replayed between frames),
//! and bad ranges are refused.

mod common;

use std::path::Path;

use common::cli::{assert_clean_failure, relief};
use relief::heightfield::Generator;

/// Runs `relief render` small with `args`, writing `dir/f.png` (numbered for a sequence).
fn render(dir: &Path, args: &[&str]) {
    std::fs::create_dir_all(dir).unwrap();
    let out = dir.join("f.png");
    let mut all = vec!["render", "--width", "48", "--height", "32"];
    all.extend_from_slice(args);
    all.extend_from_slice(&["--out", out.to_str().unwrap()]);
    let run = relief(&all);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "render {args:?} failed:\n{err}");
}

/// The files of `dir`, sorted by name, with their bytes.
fn files(dir: &Path) -> Vec<(String, Vec<u8>)> {
    let mut list: Vec<(String, Vec<u8>)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let path = e.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read(&path).unwrap())
        })
        .collect();
    list.sort();
    list
}

/// Renders `sequence` whole into one folder and in `ranges` into another; the folders must hold
/// the same files, byte for byte.
fn assert_ranges_cover_the_sequence(test: &str, sequence: &[&str], ranges: &[&str]) {
    let dir = common::scratch_dir(test);
    render(&dir.join("whole"), sequence);
    for range in ranges {
        let mut args = sequence.to_vec();
        args.extend_from_slice(&["--frame-range", range]);
        render(&dir.join("parts"), &args);
    }
    let whole = files(&dir.join("whole"));
    let parts = files(&dir.join("parts"));
    let names = |l: &[(String, Vec<u8>)]| l.iter().map(|f| f.0.clone()).collect::<Vec<_>>();
    assert_eq!(names(&whole), names(&parts));
    for ((name, a), (_, b)) in whole.iter().zip(&parts) {
        assert!(
            a == b,
            "{name} differs between the whole sequence and its range"
        );
    }
    // Every frame differs from the one before (the test would pass vacuously on a still view).
    for pair in whole.windows(2) {
        assert_ne!(pair[0].1, pair[1].1, "{} and {}", pair[0].0, pair[1].0);
    }
}

#[test]
fn ranges_of_an_orbit_write_the_whole_orbits_files() {
    if common::device("ranges_of_an_orbit").is_none() {
        return;
    }
    assert_ranges_cover_the_sequence(
        "frame-range-orbit",
        &["--method", "qdm", "--frames", "5", "--orbit", "120"],
        &["1..2", "3..4", "5..5"],
    );
}

#[test]
fn ranges_of_an_edited_terrain_replay_the_strokes_before_them() {
    if common::device("ranges_of_an_edited_terrain").is_none() {
        return;
    }
    let dir = common::scratch_dir("frame-range-edits-input");
    let elevation = dir.join("elevation.png");
    Generator::Fbm
        .generate(256, 256, 9)
        .save_png16(&elevation)
        .unwrap();
    let strokes = dir.join("strokes.json");
    std::fs::write(
        &strokes,
        r#"[[{"kind": "raise", "x": 100, "y": 130, "radius": 40, "strength": 0.3}],
            [{"kind": "crater", "x": 150, "y": 110, "radius": 40, "strength": 0.3}]]"#,
    )
    .unwrap();
    let (elevation, strokes) = (elevation.to_str().unwrap(), strokes.to_str().unwrap());
    // Three frames after the loaded one: the last range starts after both lists were applied,
    // the middle one between them.
    assert_ranges_cover_the_sequence(
        "frame-range-edits",
        &[
            "--terrain",
            elevation,
            "--terrain-resolution",
            "64",
            "--edits",
            strokes,
            "--frames",
            "4",
            "--orbit",
            "30",
        ],
        &["1..1", "2..3", "4..4"],
    );
}

#[test]
fn bad_ranges_are_refused() {
    if common::device("bad_frame_ranges").is_none() {
        return;
    }
    let dir = common::scratch_dir("frame-range-bad");
    let out = dir.join("f.png");
    let out = out.to_str().unwrap();
    let base = ["render", "--width", "16", "--height", "16", "--no-write"];
    let run = relief(&[&base[..], &["--frames", "4", "--frame-range", "3..5"]].concat());
    assert_clean_failure(&run, &["--frame-range 3..5", "4 frame(s)"]);
    for bad in ["4..2", "0..1", "two..3", "7"] {
        let run = relief(
            &[
                &base[..],
                &["--frames", "9", "--frame-range", bad, "--out", out],
            ]
            .concat(),
        );
        let err = String::from_utf8_lossy(&run.stderr);
        assert_eq!(
            run.status.code(),
            Some(2),
            "{bad}: bad usage expected:\n{err}"
        );
        assert!(err.contains("--frame-range"), "{bad}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    assert!(!dir.join("f_0001.png").exists(), "nothing was drawn");
}
