//! Golden images: compare a render with `assets/golden/NAME.png` within tolerances, leave the
//! actual and difference images under `target/test-output/golden/` on a mismatch, and rewrite the
//! golden image instead when `RELIEF_UPDATE_GOLDEN=1`.

use std::path::{Path, PathBuf};

/// Mean absolute difference per channel, in 8-bit steps.
pub const MAX_MEAN_DIFF: f64 = 1.5;
/// 99th percentile of the per-pixel max channel difference.
pub const MAX_P99_DIFF: u8 = 24;

pub fn golden_path(name: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
        .join("assets/golden")
        .join(format!("{name}.png"))
}

/// (mean channel difference, 99th percentile of per-pixel max difference, difference image)
pub fn compare(actual: &[u8], expected: &[u8]) -> (f64, u8, Vec<u8>) {
    let mut per_pixel: Vec<u8> = Vec::with_capacity(actual.len() / 4);
    let mut diff_image = Vec::with_capacity(actual.len());
    let mut total = 0u64;
    for (a, e) in actual.chunks_exact(4).zip(expected.chunks_exact(4)) {
        let d: Vec<u8> = (0..3).map(|c| a[c].abs_diff(e[c])).collect();
        total += d.iter().map(|&x| u64::from(x)).sum::<u64>();
        let max = *d.iter().max().unwrap_or(&0);
        per_pixel.push(max);
        diff_image.extend_from_slice(&[max.saturating_mul(4), 0, 0, 255]);
    }
    let mean = total as f64 / (per_pixel.len() * 3) as f64;
    per_pixel.sort_unstable();
    let p99 = per_pixel[(per_pixel.len() * 99 / 100).min(per_pixel.len() - 1)];
    (mean, p99, diff_image)
}

fn save(path: &Path, rgba: &[u8], width: u32, height: u32) {
    image::save_buffer(path, rgba, width, height, image::ColorType::Rgba8).expect("writes PNG")
}

/// Asserts that `rgba` (width x height) matches the golden image `name`.
pub fn check_golden(name: &str, width: u32, height: u32, rgba: &[u8]) {
    let golden = golden_path(name);
    if std::env::var("RELIEF_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
        std::fs::create_dir_all(golden.parent().expect("has parent")).expect("mkdir");
        save(&golden, rgba, width, height);
        eprintln!("updated {}", golden.display());
        return;
    }
    let expected = image::open(&golden)
        .unwrap_or_else(|e| panic!("golden image {}: {e}", golden.display()))
        .to_rgba8();
    assert_eq!(expected.dimensions(), (width, height), "{name}: size");
    let (mean, p99, diff) = compare(rgba, expected.as_raw());
    if mean > MAX_MEAN_DIFF || p99 > MAX_P99_DIFF {
        let dir = super::evidence_dir("golden");
        save(&dir.join(format!("{name}_actual.png")), rgba, width, height);
        save(&dir.join(format!("{name}_diff.png")), &diff, width, height);
        panic!(
            "{name} differs from its golden image: mean {mean:.3} (max {MAX_MEAN_DIFF}), \
             p99 {p99} (max {MAX_P99_DIFF}); actual and difference images in {}",
            dir.display()
        );
    }
}
