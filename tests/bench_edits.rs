//! The bench's terrain-edit section at small sizes: a brush stroke's and a paint stroke's partial
//! rebuilds against full ones, with sane numbers (finite positive times, fewer texels rebuilt
//! than there are); `relief bench` writes both tables, and `--no-edits` neither.

mod common;

use relief::bench::run_paint_section;
use relief::render::HeightFormat;

#[test]
fn paint_strokes_rebuild_less_than_a_full_rebuild() {
    let Some(ctx) = common::device("paint_strokes_rebuild_less_than_a_full_rebuild") else {
        return;
    };
    let sizes = [64, 128];
    let costs = run_paint_section(&ctx, &sizes, 32.0, HeightFormat::R16Unorm).expect("section");
    assert_eq!(costs.len(), sizes.len());
    for (c, size) in costs.iter().zip(sizes) {
        assert_eq!(
            (c.size, c.splat_size, c.layers),
            (size, size / 8, 4),
            "{c:?}"
        );
        assert_eq!(c.splat_radius, 4.0, "{c:?}");
        for ms in [c.full_ms, c.stroke_ms, c.paint_cpu_ms, c.full_cpu_ms] {
            assert!(ms.is_finite() && ms > 0.0, "implausible time in {c:?}");
        }
        assert!(
            c.stroke_texels > 0 && c.stroke_texels < c.all_texels,
            "a stroke rebuilt {} of {} texels",
            c.stroke_texels,
            c.all_texels
        );
    }
    // The larger field's stroke covers a smaller share of it.
    let share = |c: &relief::bench::PaintCost| c.stroke_texels as f64 / c.all_texels as f64;
    assert!(share(&costs[1]) < share(&costs[0]), "{costs:?}");
    common::assert_no_validation_errors(&ctx);
}

/// `relief bench` with the smallest sweep, the other sections skipped.
fn bench(out: &std::path::Path, extra: &[&str]) -> (serde_json::Value, String) {
    let mut args = vec![
        "bench",
        "--methods",
        "qdm",
        "--fields",
        "fbm",
        "--sizes",
        "64",
        "--angles",
        "30",
        "--azimuths",
        "0",
        "--budgets",
        "32",
        "--frames",
        "1",
        "--resolution",
        "32x32",
        "--sections",
        "main,edits",
        "--no-stability",
        "--no-shading",
        "--no-lod",
        "--no-blending",
        "--out",
        out.to_str().expect("utf-8"),
    ];
    args.extend_from_slice(extra);
    let run = common::cli::relief(&args);
    assert!(
        run.status.success(),
        "bench failed:\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let json = serde_json::from_slice(&std::fs::read(out.join("results.json")).expect("json"))
        .expect("JSON");
    let report = std::fs::read_to_string(out.join("report.md")).expect("report.md");
    (json, report)
}

#[test]
fn bench_reports_painting_weights_beside_terrain_edits() {
    if common::device("bench_reports_painting_weights_beside_terrain_edits").is_none() {
        return;
    }
    let out = common::scratch_dir("bench-edits");
    let (json, report) = bench(&out, &["--edit-sizes", "64"]);
    let edits = json["edits"].as_array().expect("edits");
    let paint = json["paint_edits"].as_array().expect("paint_edits");
    assert_eq!((edits.len(), paint.len()), (1, 1), "{json}");
    let row = &paint[0];
    assert_eq!(
        (row["size"].as_u64(), row["splat_size"].as_u64()),
        (Some(64), Some(8))
    );
    for key in ["full_ms", "stroke_ms", "paint_cpu_ms", "full_cpu_ms"] {
        let ms = row[key].as_f64().expect(key);
        assert!(ms.is_finite() && ms > 0.0, "{key} in {row}");
    }
    let (rebuilt, all) = (row["stroke_texels"].as_u64(), row["all_texels"].as_u64());
    assert!(rebuilt.unwrap() < all.unwrap(), "{row}");
    let edits_at = report.find("## Terrain edits").expect("edit table");
    let paint_at = report.find("### Painting weights").expect("paint table");
    assert!(edits_at < paint_at, "{report}");
    assert!(
        report.contains("| 64^2 | 8^2 | R16Unorm | 32 (4 splat) |"),
        "{report}"
    );

    let (json, report) = bench(&out, &["--no-edits"]);
    assert_eq!(json["paint_edits"].as_array().map(Vec::len), Some(0));
    assert!(!report.contains("Painting weights"), "{report}");
    let _ = std::fs::remove_dir_all(&out);
}
