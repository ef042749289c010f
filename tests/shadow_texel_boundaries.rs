//! Hard self-shadows and the pyramid methods' hits where rays stand exactly on texel boundaries.
//!
//! A 64 x 64 grid of rays enters the top plane at its cells' centres, `(c + 0.5) / 64`: over a
//! 256-texel map that is texel edge `4c + 2`, a boundary of the level-1 pyramid nodes on both
//! axes. Every ray therefore starts on a node boundary, and rays that meet level ground or hit
//! after a whole number of texels of travel end on one. This is where a traversal that finds the
//! node under the ray by `floor()` alone goes wrong: moving toward lower indices it is judged by
//! the node it is leaving, skips the node it crosses, and reports a hit on the far boundary, below
//! the surface, which the hard shadow then finds buried (issue 27: a crater field, QDM at 37 / 211
//! degrees, light at 23 / 71, depth scale 0.08, 99.80% agreement).
//!
//! The crater field is made here (bowls with raised rims punched into level ground, the brush's
//! crater profile), not stored.

mod common;

use std::sync::Arc;

use relief::bench::{compare_fractions, ray_direction, reference_fractions, trace_stats};
use relief::heightfield::visibility::LightDir;
use relief::heightfield::{build_method_map, Address, Heightfield};
use relief::method::Method;
use relief::render::{trace_on_gpu, HeightFormat, ShadowTrace, TraceOutput, TraceRequest};
use relief::scene::ShadowMode;
use relief::vk::Context;

const SIZE: u32 = 256;
const GRID: u32 = 64;
const LIGHT: LightDir = LightDir {
    elevation_deg: 23.0,
    azimuth_deg: 71.0,
    radius_deg: 0.0,
};

/// Level ground at `ground` with `SIZE / 4` seeded craters of radius 3 to 42 texels, wrapping
/// around the tile: a bowl inside 0.8 of the radius and a rim a quarter as high just outside it.
fn crater_field(seed: u64, ground: f32) -> Heightfield {
    let n = f64::from(SIZE);
    let mut rng = common::rays::Rng(seed);
    let mut data = vec![ground; (SIZE * SIZE) as usize];
    let wrapped = |d: f64| d.abs().min(n - d.abs());
    for _ in 0..SIZE / 4 {
        let (cx, cy) = (rng.range(0.0, n), rng.range(0.0, n));
        let radius = rng.range(3.0, n / 6.0);
        let depth = rng.range(0.2, 0.6) as f32;
        for j in 0..SIZE {
            for i in 0..SIZE {
                let dx = wrapped(f64::from(i) + 0.5 - cx);
                let dy = wrapped(f64::from(j) + 0.5 - cy);
                let r = (dx * dx + dy * dy).sqrt() / radius;
                let bowl = (1.0 - (r / 0.8).powi(2)).max(0.0) as f32;
                let rim = (1.0 - ((r - 0.8) / 0.2).abs()).max(0.0) as f32;
                let h = &mut data[(j * SIZE + i) as usize];
                *h = (*h - depth * bowl + 0.25 * depth * rim).clamp(0.0, 1.0);
            }
        }
    }
    Heightfield::new(SIZE, SIZE, data).expect("crater field")
}

/// One view of the grid: the method's hits and, with `light`, its hard-shadow verdicts.
struct View<'a> {
    method: &'a str,
    elevation_deg: f64,
    azimuth_deg: f64,
    depth_scale: f32,
    format: HeightFormat,
    light: Option<LightDir>,
}

fn trace(ctx: &Arc<Context>, hf: &Heightfield, view: &View) -> TraceOutput {
    let method: Method = view.method.parse().expect("a method id");
    let map = build_method_map(method, hf, Address::Repeat);
    let shadow = view
        .light
        .map(|l| ShadowTrace::directional(ShadowMode::Hard, l.elevation_deg, l.azimuth_deg, 0.0));
    let req = TraceRequest {
        method,
        dir: ray_direction(view.elevation_deg, view.azimuth_deg).map(|x| x as f32),
        depth_scale: view.depth_scale,
        grid: (GRID, GRID),
        budget: method.info().default_budget,
        address: Address::Repeat,
        format: view.format,
        map: map.as_ref().map(|(m, _)| m),
        shadow,
    };
    trace_on_gpu(ctx, hf, &req).expect("trace runs")
}

/// Whether the hit's u times the map's width is a whole number (to float's rounding near 1).
fn on_texel_boundary(hit: &[f32; 8]) -> bool {
    let t = f64::from(hit[5]) * f64::from(SIZE);
    (t - t.round()).abs() < 1e-4
}

/// How a view's hard shadows compare with the exact verdicts.
struct ShadowCheck {
    /// Share of all hits whose verdict agrees.
    agreement: f64,
    /// Share of all hits the exact reference finds lit.
    lit: f64,
    /// Hits on a texel boundary.
    boundary: usize,
    /// The hits on a texel boundary whose verdict disagrees, described.
    wrong: Vec<String>,
}

fn shadow_check(ctx: &Arc<Context>, hf: &Heightfield, view: &View) -> ShadowCheck {
    let light = view.light.expect("a lit view");
    let out = trace(ctx, hf, view);
    let s = f64::from(view.depth_scale);
    let exact =
        reference_fractions(hf, &out.hits, s, Address::Repeat, light, 1).expect("reference");
    let stats = compare_fractions(&out.visible, &exact);
    assert_eq!(
        stats.points,
        (GRID * GRID) as usize,
        "every hit is compared"
    );
    let mut boundary = 0;
    let mut wrong = Vec::new();
    for ((hit, &got), exact) in out.hits.iter().zip(&out.visible).zip(&exact) {
        if !on_texel_boundary(hit) {
            continue;
        }
        boundary += 1;
        let exact = exact.expect("a finite hit");
        if (got >= 0.5) != (exact >= 0.5) {
            wrong.push(format!(
                "hit at texel ({:.5}, {:.5}), depth {:.6}: GPU {got}, exact {exact}",
                hit[5] * SIZE as f32,
                hit[6] * SIZE as f32,
                hit[7]
            ));
        }
    }
    ShadowCheck {
        agreement: stats.agreement,
        lit: stats.reference_mean,
        boundary,
        wrong,
    }
}

#[test]
fn hard_shadows_agree_on_hits_at_texel_boundaries() {
    let Some(ctx) = common::device("hard_shadows_agree_on_hits_at_texel_boundaries") else {
        return;
    };
    // Issue 27's view and light over craters in ground at the top plane (hits on the ground are
    // the rays' entry points, all on boundaries) and in lower ground (hits inside the field).
    for (seed, ground) in [(1, 1.0), (2, 1.0), (7, 0.5)] {
        let hf = crater_field(seed, ground).quantized_unorm16();
        let view = View {
            method: "qdm",
            elevation_deg: 37.0,
            azimuth_deg: 211.0,
            depth_scale: 0.08,
            format: HeightFormat::R16Unorm,
            light: Some(LIGHT),
        };
        let c = shadow_check(&ctx, &hf, &view);
        let what = format!("craters {seed} in ground at {ground}");
        eprintln!(
            "{what}: agreement {:.5}, lit {:.3}, {} hits on texel boundaries",
            c.agreement, c.lit, c.boundary
        );
        assert!(c.wrong.is_empty(), "{what}:\n{}", c.wrong.join("\n"));
        assert!(c.agreement >= 0.999, "{what}: agreement {:.5}", c.agreement);
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn hard_shadows_agree_on_buried_ground_hits_at_texel_boundaries() {
    let Some(ctx) = common::device("hard_shadows_agree_on_buried_ground_hits_at_texel_boundaries")
    else {
        return;
    };
    // Exact numbers throughout: ground at 7/8 in a float map, depth scale 1/16, so the ground
    // lies 2/256 deep; a ray at 45 degrees toward -u travels 2 texels to it, so every ground hit
    // lands on the level-1 node boundary two texels on from its entry, below the rims around it.
    let hf = crater_field(3, 0.875);
    let view = View {
        method: "qdm",
        elevation_deg: 45.0,
        azimuth_deg: 180.0,
        depth_scale: 0.0625,
        format: HeightFormat::R32Float,
        light: Some(LIGHT),
    };
    let c = shadow_check(&ctx, &hf, &view);
    eprintln!(
        "ground at 7/8: agreement {:.5}, lit {:.3}, {} hits on texel boundaries",
        c.agreement, c.lit, c.boundary
    );
    // The craters cover most of the tile; the ground between them still holds a tenth of the
    // hits, and the light leaves a share of them in the rims' shadows.
    assert!(
        c.boundary * 10 >= (GRID * GRID) as usize,
        "{} hits on texel boundaries",
        c.boundary
    );
    assert!(c.lit > 0.1 && c.lit < 0.9, "lit share {:.3}", c.lit);
    assert!(c.wrong.is_empty(), "{}", c.wrong.join("\n"));
    assert!(c.agreement >= 0.999, "agreement {:.5}", c.agreement);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn pyramid_methods_hit_exactly_from_node_boundaries() {
    let Some(ctx) = common::device("pyramid_methods_hit_exactly_from_node_boundaries") else {
        return;
    };
    let hf = crater_field(1, 1.0).quantized_unorm16();
    let mut failures = Vec::new();
    for method in ["qdm", "pdm", "maxmip", "qrm"] {
        // Toward lower u and v, toward lower u only, and toward higher indices on both axes.
        for azimuth_deg in [211.0, 160.0, 31.0] {
            let view = View {
                method,
                elevation_deg: 37.0,
                azimuth_deg,
                depth_scale: 0.08,
                format: HeightFormat::R16Unorm,
                light: None,
            };
            let out = trace(&ctx, &hf, &view);
            let stats = trace_stats(&hf, &out.hits, &out.steps, 0.08, Address::Repeat);
            eprintln!(
                "{method} at azimuth {azimuth_deg}: max error {:.2e} texels",
                stats.error_texels.max
            );
            if stats.error_texels.max > 0.01 || stats.capped_rate > 0.0 {
                failures.push(format!(
                    "{method} at azimuth {azimuth_deg}: max error {:.4} texels, capped {}",
                    stats.error_texels.max, stats.capped_rate
                ));
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}
