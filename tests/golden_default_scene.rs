//! The built-in default scene matches a small golden image within stated tolerances.
//! Regenerate after an intended change with `RELIEF_UPDATE_GOLDEN=1 cargo test --test golden_default_scene`.

mod common;

use std::path::PathBuf;

use relief::method::Method;
use relief::render::{render, RenderOptions};
use relief::scene::{default_heightfield, default_scene};

const WIDTH: u32 = 192;
const HEIGHT: u32 = 108;
/// Mean absolute difference per channel, in 8-bit steps.
const MAX_MEAN_DIFF: f64 = 1.5;
/// 99th percentile of the per-pixel max channel difference.
const MAX_P99_DIFF: u8 = 24;

fn golden_path() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("assets/golden/default_scene_192x108.png")
}

/// (mean channel difference, 99th percentile of per-pixel max difference, difference image)
fn compare(actual: &[u8], expected: &[u8]) -> (f64, u8, Vec<u8>) {
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

#[test]
fn default_scene_matches_golden() {
    let Some(ctx) = common::device("default_scene_matches_golden") else {
        return;
    };
    let opts = RenderOptions {
        width: WIDTH,
        height: HEIGHT,
        ..RenderOptions::default()
    };
    let frame = render(
        &ctx,
        &default_scene(Method::POM),
        Some(&default_heightfield()),
        &opts,
    )
    .expect("renders");
    common::assert_no_validation_errors(&ctx);
    let save = |path: &std::path::Path, rgba: &[u8]| {
        image::save_buffer(path, rgba, WIDTH, HEIGHT, image::ColorType::Rgba8).expect("writes PNG")
    };
    if std::env::var("RELIEF_UPDATE_GOLDEN").is_ok_and(|v| v == "1") {
        std::fs::create_dir_all(golden_path().parent().expect("has parent")).expect("mkdir");
        save(&golden_path(), &frame.rgba);
        eprintln!("updated {}", golden_path().display());
        return;
    }
    let expected = image::open(golden_path())
        .expect("golden image exists")
        .to_rgba8();
    assert_eq!(expected.dimensions(), (WIDTH, HEIGHT));
    let (mean, p99, diff) = compare(&frame.rgba, expected.as_raw());
    if mean > MAX_MEAN_DIFF || p99 > MAX_P99_DIFF {
        let dir = common::evidence_dir("golden");
        save(&dir.join("default_scene_actual.png"), &frame.rgba);
        save(&dir.join("default_scene_diff.png"), &diff);
        panic!(
            "default scene differs from its golden image: mean {mean:.3} (max {MAX_MEAN_DIFF}), \
             p99 {p99} (max {MAX_P99_DIFF}); actual and difference images in {}",
            dir.display()
        );
    }
}

#[test]
fn relief_changes_the_image() {
    // Guards against a golden image of a flat, undisplaced slab: relief must move pixels.
    let Some(ctx) = common::device("relief_changes_the_image") else {
        return;
    };
    let opts = RenderOptions {
        width: WIDTH,
        height: HEIGHT,
        ..RenderOptions::default()
    };
    let hf = default_heightfield();
    let relief = render(&ctx, &default_scene(Method::POM), Some(&hf), &opts).expect("renders");
    let mut flat_scene = default_scene(Method::POM);
    flat_scene
        .materials
        .iter_mut()
        .for_each(|m| m.relief = None);
    let flat = render(&ctx, &flat_scene, Some(&hf), &opts).expect("renders");
    let (mean, _, _) = compare(&relief.rgba, &flat.rgba);
    assert!(
        mean > 3.0,
        "displaced and flat renders barely differ (mean {mean:.3})"
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn every_method_renders_the_default_scene() {
    // Each method's surface pipeline builds with its maps bound, and its relief stays close to
    // POM's picture (same surface, different tracer).
    let Some(ctx) = common::device("every_method_renders_the_default_scene") else {
        return;
    };
    let opts = RenderOptions {
        width: 96,
        height: 54,
        ..RenderOptions::default()
    };
    let hf = default_heightfield();
    let pom = render(&ctx, &default_scene(Method::POM), Some(&hf), &opts).expect("renders");
    for method in Method::all() {
        let frame = render(&ctx, &default_scene(method), Some(&hf), &opts).expect("renders");
        let (mean, _, _) = compare(&frame.rgba, &pom.rgba);
        let bound = if method.id() == "parallax" { 12.0 } else { 6.0 };
        assert!(
            mean < bound,
            "{method} differs from POM by {mean:.2} on average"
        );
        let shaders: Vec<String> = frame.plan.pipelines.iter().map(|p| p.shader()).collect();
        assert_eq!(
            shaders,
            vec![method.surface_shader_key(), "surface.frag:plain".to_owned()],
            "{method}: the method's pipeline and the plain one, nothing else"
        );
    }
    common::assert_no_validation_errors(&ctx);
}
