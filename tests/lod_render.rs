//! Level of detail on lavapipe: the averaged pyramid equals its CPU definition, and a receding
//! plane rendered with LOD stays within a tolerance of a supersampled render without it, while
//! its minified far region differs from the full-detail render (the traversal stopped early).
//! `--explain` says whether the averaged pyramid was built. LOD off is covered by the golden tests:
//! its variants are unchanged. Never asserts on time.

mod common;

use relief::bench::{downsample, image_error, receding_plane, render_timed};
use relief::heightfield::{mip_level_count, Generator, Heightfield};
use relief::method::Method;
use relief::render::{build_mean_pyramid_on_gpu, HeightFormat};
use relief::scene::Lod;

const W: u32 = 128;
const H: u32 = 72;
const SUPERSAMPLE: u32 = 4;

/// The mean of the finer level's texels each coarse texel covers (mean_pyramid.comp's rule).
fn cpu_mean_levels(hf: &Heightfield) -> Vec<Vec<f32>> {
    let (mut w, mut h) = (hf.width(), hf.height());
    let mut levels = vec![hf.data().to_vec()];
    for _ in 1..mip_level_count(w, h) {
        let (cw, ch) = ((w / 2).max(1), (h / 2).max(1));
        let fine = levels.last().expect("level 0");
        let range = |i: u32, f: u32, c: u32| (i * f / c, ((i + 1) * f).div_ceil(c) - 1);
        let mut coarse = Vec::with_capacity((cw * ch) as usize);
        for y in 0..ch {
            for x in 0..cw {
                let ((x0, x1), (y0, y1)) = (range(x, w, cw), range(y, h, ch));
                let texels = (y0..=y1).flat_map(|j| (x0..=x1).map(move |i| (i, j)));
                let sum: f32 = texels.map(|(i, j)| fine[(j * w + i) as usize]).sum();
                coarse.push(sum / ((x1 - x0 + 1) * (y1 - y0 + 1)) as f32);
            }
        }
        levels.push(coarse);
        (w, h) = (cw, ch);
    }
    levels
}

#[test]
fn averaged_pyramid_matches_the_cpu_mean() {
    let Some(ctx) = common::device("averaged_pyramid_matches_the_cpu_mean") else {
        return;
    };
    let hf = Generator::Fbm.generate(37, 20, 3);
    let gpu = build_mean_pyramid_on_gpu(&ctx, &hf, HeightFormat::R32Float).expect("builds");
    let cpu = cpu_mean_levels(&hf);
    assert_eq!(gpu.len(), cpu.len());
    for (level, (g, c)) in gpu.iter().zip(&cpu).enumerate() {
        assert_eq!(g.len(), c.len(), "level {level} size");
        let worst = g
            .iter()
            .zip(c)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        assert!(worst < 1e-5, "level {level}: off by {worst}");
    }
    common::assert_no_validation_errors(&ctx);
}

/// Mean per-channel difference of rows `rows` of two W x H images.
fn rows_error(a: &[u8], b: &[u8], rows: std::ops::Range<u32>) -> f64 {
    let span =
        |img: &[u8]| img[(rows.start * W * 4) as usize..(rows.end * W * 4) as usize].to_vec();
    image_error(&span(a), &span(b)).mean
}

fn save_evidence(name: &str, rgba: &[u8]) {
    let path = common::evidence_dir("lod").join(format!("{name}.png"));
    image::save_buffer(&path, rgba, W, H, image::ColorType::Rgba8).expect("writes PNG");
}

#[test]
fn lod_on_a_receding_plane_stays_close_to_the_supersampled_render() {
    let Some(ctx) = common::device("lod_on_a_receding_plane") else {
        return;
    };
    let hf = Generator::Fbm.generate(256, 256, 1);
    let format = HeightFormat::R16Unorm;
    for id in ["qdm", "pom"] {
        let method: Method = id.parse().expect("known id");
        let scene = |lod| receding_plane(method, lod, 0.05, 15.0);
        let big = (W * SUPERSAMPLE, H * SUPERSAMPLE);
        let (ss, _) = render_timed(&ctx, &scene(None), &hf, big, 0, format).expect("renders");
        let reference = downsample(&ss, big.0, big.1, SUPERSAMPLE);
        let (off, _) = render_timed(&ctx, &scene(None), &hf, (W, H), 0, format).expect("renders");
        let lod = Some(Lod::default());
        let (on, _) = render_timed(&ctx, &scene(lod), &hf, (W, H), 0, format).expect("renders");
        let (e_on, e_off) = (image_error(&on, &reference), image_error(&off, &reference));
        // The rows below the horizon are strongly minified: QDM's traversal stops early there,
        // so its LOD render must differ from the full-detail one (time is the bench's business).
        let far = rows_error(&on, &off, H / 4..H / 2);
        let ok = e_on.mean <= e_off.mean + 2.0 && e_on.p99 <= e_off.p99 + 24.0;
        let stopped = id != "qdm" || far > 0.25;
        if !(ok && stopped) {
            save_evidence(&format!("{id}_lod"), &on);
            save_evidence(&format!("{id}_off"), &off);
            save_evidence(&format!("{id}_reference"), &reference);
        }
        assert!(ok, "{id}: LOD {e_on:?}, no LOD {e_off:?}");
        assert!(
            stopped,
            "{id}: far rows differ by {far:.3} only: LOD had no effect"
        );
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn lod_fade_ends_in_normal_mapping_without_nan() {
    let Some(ctx) = common::device("lod_fade_ends_in_normal_mapping") else {
        return;
    };
    let hf = Generator::Fbm.generate(64, 64, 2);
    let format = HeightFormat::R16Unorm;
    let method: Method = "qdm".parse().expect("known id");
    // Everything is past the fade's end: no pixel is traced, so the render is normal mapping.
    let faded = Lod {
        fade_start: 0.001,
        fade_end: 0.002,
        ..Lod::default()
    };
    let scene = receding_plane(method, Some(faded), 0.05, 15.0);
    let (img, _) = render_timed(&ctx, &scene, &hf, (W, H), 0, format).expect("renders");
    let flat = receding_plane(method, Some(faded), 1e-6, 15.0);
    let (shallow, _) = render_timed(&ctx, &flat, &hf, (W, H), 0, format).expect("renders");
    // With nothing traced the depth scale only tilts normals; the geometry (silhouette, horizon)
    // is the polygon's, and no pixel is NaN-black where the flat one is lit.
    let dark = |img: &[u8]| img.chunks_exact(4).filter(|p| p[..3] == [0, 0, 0]).count();
    assert_eq!(
        dark(&img),
        dark(&shallow),
        "black pixels appear only with the trace skipped"
    );
    common::assert_no_validation_errors(&ctx);
}

/// `relief render --explain` of the default scene with `extra` flags: the plan as JSON.
fn explain(name: &str, extra: &[&str]) -> serde_json::Value {
    let out = common::scratch_dir(name).join("frame.png");
    // Without the default scene's AO and the sky's environment maps, whose builds are compute
    // pipelines of their own.
    let mut args = vec![
        "render",
        "--explain",
        "--no-pipeline-cache",
        "--method",
        "qdm",
        "--ao",
        "none",
        "--environment",
        "none",
    ];
    args.extend(["--width", "48", "--height", "32", "--out"]);
    args.push(out.to_str().expect("utf-8"));
    args.extend(extra);
    let run = std::process::Command::new(env!("CARGO_BIN_EXE_relief"))
        .args(&args)
        .output()
        .expect("binary runs");
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "render {extra:?} failed:\n{err}");
    serde_json::from_slice(&run.stdout).expect("one JSON object")
}

#[test]
fn explain_says_whether_the_averaged_pyramid_was_built() {
    if common::device("explain_says_whether_the_averaged_pyramid_was_built").is_none() {
        return;
    }
    let skipped = |plan: &serde_json::Value| {
        let list = plan["skipped"].as_array().expect("skipped").clone();
        list.into_iter().find(|s| s["what"] == "averaged_pyramid")
    };
    let off = explain("lod-off", &[]);
    let why = skipped(&off).expect("skipped without LOD");
    assert!(why["why"]
        .as_str()
        .is_some_and(|w| w.contains("no drawn material has LOD")));
    assert_eq!(
        off["created"]["compute_pipelines"], 1,
        "the max pyramid only"
    );

    let on = explain("lod-on", &["--lod"]);
    assert!(skipped(&on).is_none(), "built with LOD: {on}");
    assert_eq!(on["heights"][0]["averaged_pyramid"], true);
    assert_eq!(on["pipelines"][0]["shader"], "surface.frag:qdm:lod");
    assert_eq!(
        on["created"]["compute_pipelines"], 2,
        "max and averaged pyramids"
    );

    let flat = explain("lod-flat", &["--lod-average-below", "0"]);
    let why = skipped(&flat).expect("skipped at average_below 0");
    assert!(why["why"]
        .as_str()
        .is_some_and(|w| w.contains("average_below")));
}
