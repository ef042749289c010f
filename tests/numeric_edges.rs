//! The numerically delicate cases, each with the case that motivated it: rays with a zero xy
//! component (divisions by dx or dy), exactly vertical rays, and node crossings on an 8192^2 map,
//! where half a texel is 6e-5 in uv and a crossing offset that is too small leaves the ray in
//! the node it just left.

mod common;

use relief::bench::{ray_direction, trace_stats, TraceStats};
use relief::heightfield::{build_method_map, Address, Generator, Heightfield};
use relief::method::Method;
use relief::render::{trace_on_gpu, HeightFormat, TraceRequest};

fn trace(
    ctx: &std::sync::Arc<relief::vk::Context>,
    hf: &Heightfield,
    method: Method,
    dir: [f64; 3],
    grid: u32,
) -> TraceStats {
    let map = build_method_map(method, hf, Address::Repeat);
    let req = TraceRequest {
        method,
        dir: dir.map(|x| x as f32),
        depth_scale: 0.1,
        grid: (grid, grid),
        budget: method.info().default_budget,
        address: Address::Repeat,
        format: HeightFormat::R16Unorm,
        map: map.as_ref().map(|(m, _)| m),
        shadow: None,
    };
    let out = trace_on_gpu(ctx, hf, &req).expect("trace runs");
    trace_stats(hf, &out.hits, &out.steps, 0.1f32 as f64, Address::Repeat)
}

/// Worst depth error in texels of an exactly vertical ray on fbm 64^2, per method: measured, rounded
/// up to two significant digits. Steep parallax stops on its 32-step grid (measured 0.197), relief
/// after 5 binary steps (0.0124); the others meet the surface to float rounding (measured 3.8e-7
/// for parallax, 6.1e-7 for pom, 6.9e-7 for the pyramid methods and quadric, 7.5e-7 for the cones).
const VERTICAL_DEPTH_ERROR: &[(&str, f64)] = &[
    ("parallax", 3.9e-7),
    ("steep", 0.20),
    ("relief", 0.013),
    ("pom", 6.1e-7),
    ("csm", 7.5e-7),
    ("rcsm", 7.5e-7),
    ("qrm", 7.0e-7),
    ("pdm", 7.0e-7),
    ("qdm", 7.0e-7),
    ("maxmip", 7.0e-7),
    ("quadric", 7.0e-7),
];

#[test]
fn axis_aligned_and_vertical_rays_stay_finite() {
    let Some(ctx) = common::device("axis_aligned_and_vertical_rays_stay_finite") else {
        return;
    };
    let hf = Generator::Fbm.generate(64, 64, 9).quantized_unorm16();
    for method in Method::all() {
        for azimuth in [0.0, 90.0, 180.0, 270.0] {
            let s = trace(&ctx, &hf, method, ray_direction(30.0, azimuth), 16);
            assert_eq!(s.nan_pixels, 0, "{method} at azimuth {azimuth}: NaN");
            assert_eq!(s.capped_rate, 0.0, "{method} at azimuth {azimuth}: capped");
        }
        // Exactly vertical: dx = dy = 0, so every per-axis division is by zero.
        let s = trace(&ctx, &hf, method, [0.0, 0.0, 1.0], 16);
        assert_eq!(s.nan_pixels, 0, "{method} vertical: NaN");
        // Straight down the uv error is zero by construction: the depth error is the check.
        let bound = VERTICAL_DEPTH_ERROR
            .iter()
            .find(|(id, _)| *id == method.id())
            .map(|(_, b)| *b)
            .expect("every method states its vertical depth error");
        assert!(
            s.depth_error_texels.max <= bound,
            "{method} vertical: depth error {} (bound {bound})",
            s.depth_error_texels.max
        );
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn node_crossings_progress_on_an_8192_map() {
    let Some(ctx) = common::device("node_crossings_progress_on_an_8192_map") else {
        return;
    };
    if ctx.info().max_image_dimension_2d < 8192 {
        eprintln!("SKIPPED: device limit below 8192");
        return;
    }
    let hf = Generator::Ramp.generate(8192, 8192, 1).quantized_unorm16();
    for id in ["qdm", "pdm", "qrm", "maxmip"] {
        let method: Method = id.parse().expect("known id");
        let s = trace(&ctx, &hf, method, ray_direction(30.0, 20.0), 8);
        assert_eq!(s.nan_pixels, 0, "{id}: NaN");
        assert_eq!(
            s.capped_rate, 0.0,
            "{id}: rays stuck at node boundaries ran out of budget"
        );
        assert_eq!(s.gross_rate, 0.0, "{id}: gross errors {:?}", s.error_texels);
    }
    common::assert_no_validation_errors(&ctx);
}
