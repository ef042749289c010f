//! `relief ao` through the binary: the dump is an (H, W) float32 `.npy` of the GPU's AO map whose
//! error against the exact reference, recomputed here, is what the JSON line says; bad input gives
//! one error line naming the problem and exit 1, without a panic (and without needing a device).

mod common;

use std::path::Path;

use common::cli::relief;

use relief::heightfield::ambient_occlusion::ao_reference;
use relief::heightfield::{Address, Generator, Heightfield};

/// Runs `relief ao` on `map` and checks the dump and the printed statistics against the reference.
fn check_dump(map: &Path, hf: &Heightfield, mode: &str, address: Address, bound: f64) {
    let dump = map.with_extension(format!("{mode}.{address}.npy"));
    let out = relief(&[
        "ao",
        "--heightmap",
        map.to_str().expect("utf-8"),
        "--depth-scale",
        "0.08",
        "--address",
        &address.to_string(),
        "--ao",
        mode,
        "--dump",
        dump.to_str().expect("utf-8"),
    ]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(out.status.success(), "{err}");
    let printed: serde_json::Value = serde_json::from_slice(&out.stdout).expect("one JSON line");
    let (shape, values) = common::npy::read_npy(&std::fs::read(&dump).expect("dump written"));
    assert_eq!(shape, [hf.height() as usize, hf.width() as usize]);
    assert!(values.iter().all(|v| (0.0..=1.0).contains(v)));
    let reference = ao_reference(hf, 0.08, address, 256).expect("reference");
    let mean = values
        .iter()
        .zip(&reference)
        .map(|(a, b)| f64::from((a - b).abs()))
        .sum::<f64>()
        / values.len() as f64;
    let what = format!("{mode} {address}");
    assert_eq!(printed["reference"]["texels"], hf.texel_count(), "{what}");
    let said = printed["error"]["mean"].as_f64().expect("error.mean");
    assert!(
        (said - mean).abs() < 1e-6,
        "{what}: printed {said}, recomputed {mean}"
    );
    assert!(mean <= bound, "{what}: mean abs error {mean}");
    assert_eq!(printed["ao"], mode);
    assert!(
        printed["gpu_ms"].as_f64().is_some_and(|t| t >= 0.0),
        "{printed}"
    );
}

#[test]
fn dump_is_the_map_the_statistics_describe() {
    if common::device("cli_ao dump").is_none() {
        return;
    }
    let dir = common::scratch_dir("cli-ao-dump");
    // Not square, so a swapped (H, W) shows; 16-bit, so the file holds the heights exactly enough.
    let hf = Generator::Fbm.generate(20, 12, 9);
    let map = dir.join("fbm.png");
    hf.save_png16(&map).expect("PNG written");
    let hf = Heightfield::load_png(&map, &Default::default()).expect("PNG reads back");
    check_dump(&map, &hf, "exact-horizon", Address::Repeat, 0.01);
    check_dump(&map, &hf, "horizon-8", Address::Clamp, 0.03);
}

#[test]
fn bad_input_fails_with_one_clear_line() {
    let dir = common::scratch_dir("cli-ao-bad");
    let field = ["ao", "--field", "fbm", "--size", "8"];
    let with = |extra: &[&str]| relief(&[&field[..], extra].concat());
    for scale in ["0", "-0.1", "nan", "inf"] {
        let out = with(&[&format!("--depth-scale={scale}")]);
        common::cli::assert_clean_failure(&out, &["--depth-scale"]);
    }
    common::cli::assert_clean_failure(&with(&["--ao", "horizon-5"]), &["horizon-5"]);
    common::cli::assert_clean_failure(&with(&["--ao", "none"]), &["none"]);
    let missing = dir.join("no-such-map.png");
    let out = relief(&["ao", "--heightmap", missing.to_str().expect("utf-8")]);
    common::cli::assert_clean_failure(&out, &["no-such-map.png"]);
    let garbage = dir.join("not-a-png.png");
    std::fs::write(&garbage, b"these bytes are no PNG").expect("scratch is writable");
    let out = relief(&["ao", "--heightmap", garbage.to_str().expect("utf-8")]);
    common::cli::assert_clean_failure(&out, &["not-a-png.png"]);
    common::cli::assert_clean_failure(&relief(&["ao"]), &["--heightmap"]);
}
