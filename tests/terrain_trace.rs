//! Pyramid methods on blended terrain: QDM and maxmip traced through the conservative blended
//! pyramid (`terrain::blended_pyramid`, from the layers' and weights' pyramids) against the exact
//! reference of the blended surface, and their iterations against the same rays through the
//! exact pyramid of the blended field (what a single-layer field of that shape costs).

mod common;

use relief::bench::{ray_direction, trace_stats};
use relief::heightfield::{Address, Generator, Heightfield, MaxPyramid};
use relief::method::Method;
use relief::render::{trace_on_gpu, trace_through_pyramid, HeightFormat, TraceRequest};
use relief::terrain::{blended_field, blended_pyramid, BlendMode, LayerStack, SplatMap};

const DEPTH_SCALE: f32 = 0.05;

#[test]
fn pyramid_methods_trace_blended_terrain_through_the_conservative_pyramid() {
    let Some(ctx) = common::device("pyramid_methods_trace_blended_terrain") else {
        return;
    };
    let heights: Vec<Heightfield> = [Generator::Fbm, Generator::Bricks, Generator::Fbm]
        .iter()
        .enumerate()
        .map(|(k, g)| g.generate(256, 256, 10 + k as u64))
        .collect();
    // A coarse splat map, as terrain painters use (paper 001: 32^2 for 1024^2 fields).
    let texels = (0..64)
        .map(|t| {
            let (x, y) = ((t % 8) as f32 / 7.0, (t / 8) as f32 / 7.0);
            [1.0 - x, x * (1.0 - y), x * y, 0.0]
        })
        .collect();
    let stack = LayerStack::from_splat(heights, &SplatMap::new(8, 8, texels).unwrap()).unwrap();
    let format = HeightFormat::R32Float;
    for mode in BlendMode::ALL {
        let field = blended_field(&stack, mode);
        let bound = blended_pyramid(&stack, mode, |hf| {
            MaxPyramid::build_bilinear_bound(hf, true)
        });
        let methods: Vec<Method> = ["qdm", "maxmip", "pdm"]
            .iter()
            .map(|id| id.parse().expect("a method id"))
            .collect();
        for &method in &methods {
            for angle in [5.0, 30.0, 60.0] {
                let req = TraceRequest {
                    method,
                    dir: ray_direction(angle, 30.0).map(|x| x as f32),
                    depth_scale: DEPTH_SCALE,
                    grid: (48, 48),
                    budget: method.info().default_budget,
                    address: Address::Repeat,
                    format,
                    map: None,
                    shadow: None,
                };
                let through_bound = trace_through_pyramid(&ctx, &bound, &req).expect("traces");
                let through_exact = trace_on_gpu(&ctx, &field, &req).expect("traces");
                let s = f64::from(DEPTH_SCALE);
                let blended = trace_stats(
                    &field,
                    &through_bound.hits,
                    &through_bound.steps,
                    s,
                    Address::Repeat,
                );
                let single = trace_stats(
                    &field,
                    &through_exact.hits,
                    &through_exact.steps,
                    s,
                    Address::Repeat,
                );
                let what = format!("{method} {mode} {angle} deg");
                eprintln!(
                    "{what}: steps {:.2} through the bound, {:.2} through the exact pyramid ({:.3}x); gross {:.4} / {:.4}",
                    blended.steps.mean,
                    single.steps.mean,
                    blended.steps.mean / single.steps.mean,
                    blended.gross_rate,
                    single.gross_rate
                );
                assert_eq!(blended.nan_pixels, 0, "{what}");
                assert_eq!(blended.capped_rate, 0.0, "{what}: rays ran out of steps");
                // No gross error against the exact reference of the blended surface.
                assert_eq!(blended.gross_rate, 0.0, "{what}: {blended:?}");
                // A looser bound only ever costs steps: never fewer than the exact pyramid's.
                assert!(blended.steps.mean >= single.steps.mean * 0.999, "{what}");
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}
