//! Every method traced ray by ray on the GPU against the exact reference, with repeat and with
//! clamp addressing (the GPU's samplers, the method's map and the reference all use the same):
//! 64x64 parallel rays on three synthetic fields at near-tangent (1 deg), grazing (5 deg), middle
//! (30 deg) and steep (75 deg) views. No NaN anywhere; per view, the share of rays that ran out of
//! budget (capped), and over the rays that did not, the mean and worst error and the gross rate,
//! stay within bounds that are the measured values on lavapipe (Mesa 22.3.6, llvmpipe), rounded up
//! in their last stated digit: a regression that moves any of them fails. The accurate methods,
//! with their default (exact) leaf, have no gross error on a ray that converged; fixed-step
//! methods state their gross errors rather than hide them.

mod common;

use relief::bench::{ray_direction, trace_stats, TraceStats};
use relief::heightfield::{build_method_map, Address, Generator, Heightfield, MapData};
use relief::method::{Budget, Leaf, Method};
use relief::render::{trace_on_gpu, HeightFormat, TraceRequest};

const FIELDS: [Generator; 3] = [Generator::Fbm, Generator::Bricks, Generator::Step];
const ANGLES: [f64; 4] = [1.0, 5.0, 30.0, 75.0];
const SIZE: u32 = 128;
const DEPTH_SCALE: f32 = 0.1;

/// What one view may measure, the worst of the three fields: the mean and the largest error in
/// texels and the gross rate over the rays that converged, and the capped rate over all rays.
#[derive(Debug, Clone, Copy)]
struct View {
    mean: f64,
    max: f64,
    gross: f64,
    capped: f64,
}

const fn v(mean: f64, max: f64, gross: f64, capped: f64) -> View {
    View {
        mean,
        max,
        gross,
        capped,
    }
}

/// Stated bounds per view angle (1, 5, 30, 75 degrees), per addressing: each is the worst of the
/// three fields as measured, rounded up to two significant digits (rates: to the next 0.0001, less
/// than one ray of 4096). The comment above each list is the measurement, per view `mean max
/// gross capped`.
///
/// With clamp addressing at 1 degree, past the map's edge the clamped border is a flat strip the
/// tree cannot skip, so qdm, maxmip and quadric walk it texel by texel (measured: at most 723
/// steps for qdm and maxmip). Under a fixed cap of 256 a quarter of the rays of `bricks` (8% of
/// `fbm`) ran out; the accurate methods' default cap now grows with the texels the ray crosses
/// (~730 here), so none does.
/// At 75 degrees the sampling methods miss by ~2.2 texels on one column of rays (1/64) at the
/// cliffs of `step` and `bricks`: those rays clip the plateau's edge, inside the solid for a
/// tenth of a texel where the bilinear ramp falls away faster than the ray descends. The exact
/// reference counts that first contact; no method that samples the surface at steps sees it.
/// At 1 degree a ray travels ~730 texels down to the bottom plane, and the fixed-step methods'
/// samples are tens of texels apart: most of their rays are gross misses there (a gross rate of
/// 1.0 cannot fail; the mean and max bounds are the check at those views).
struct Bounds {
    method: &'static str,
    repeat: [View; 4],
    clamp: [View; 4],
}

const BOUNDS: &[Bounds] = &[
    Bounds {
        method: "parallax",
        // 159 324 1 0, 45.9 99.5 1 0, 5.36 17.3 1 0, 0.256 2.27 0.0745 0
        repeat: [
            v(160.0, 330.0, 1.0, 0.0),
            v(46.0, 100.0, 1.0, 0.0),
            v(5.4, 18.0, 1.0, 0.0),
            v(0.26, 2.3, 0.0745, 0.0),
        ],
        // 337 577 1 0, 52.7 120 1 0, 5.04 17.3 1 0, 0.258 2.27 0.0745 0
        clamp: [
            v(340.0, 580.0, 1.0, 0.0),
            v(53.0, 120.0, 1.0, 0.0),
            v(5.1, 18.0, 1.0, 0.0),
            v(0.26, 2.3, 0.0745, 0.0),
        ],
    },
    Bounds {
        method: "steep",
        // 61.5 361 1 0, 3.67 77.2 0.8179 0, 0.377 12.3 0.0044 0, 0.0653 2.25 0.0081 0
        repeat: [
            v(62.0, 370.0, 1.0, 0.0),
            v(3.7, 78.0, 0.8179, 0.0),
            v(0.38, 13.0, 0.0044, 0.0),
            v(0.066, 2.3, 0.0081, 0.0),
        ],
        // 102 570 1 0, 4.73 109 0.8323 0, 0.375 12.3 0.0042 0, 0.0654 2.25 0.0081 0
        clamp: [
            v(110.0, 580.0, 1.0, 0.0),
            v(4.8, 110.0, 0.8323, 0.0),
            v(0.38, 13.0, 0.0042, 0.0),
            v(0.066, 2.3, 0.0081, 0.0),
        ],
    },
    Bounds {
        method: "relief",
        // 87.2 406 0.804 0, 3.3 78.3 0.2261 0, 0.0719 11.8 0.0071 0, 0.0409 2.41 0.0156 0
        repeat: [
            v(88.0, 410.0, 0.804, 0.0),
            v(3.4, 79.0, 0.2261, 0.0),
            v(0.072, 12.0, 0.0071, 0.0),
            v(0.041, 2.5, 0.0157, 0.0),
        ],
        // 154 554 0.8862 0, 4.95 107 0.2009 0, 0.0753 16.6 0.0066 0, 0.0202 2.17 0.0081 0
        clamp: [
            v(160.0, 560.0, 0.8863, 0.0),
            v(5.0, 110.0, 0.201, 0.0),
            v(0.076, 17.0, 0.0066, 0.0),
            v(0.021, 2.2, 0.0081, 0.0),
        ],
    },
    Bounds {
        method: "pom",
        // 54.5 343 0.9441 0, 2.26 74.5 0.5525 0, 0.0461 11.7 0.0044 0, 0.017 2.17 0.0081 0
        repeat: [
            v(55.0, 350.0, 0.9441, 0.0),
            v(2.3, 75.0, 0.5525, 0.0),
            v(0.047, 12.0, 0.0044, 0.0),
            v(0.017, 2.2, 0.0081, 0.0),
        ],
        // 88.2 553 0.7073 0, 3.24 106 0.5002 0, 0.0455 11.7 0.0042 0, 0.017 2.17 0.0081 0
        clamp: [
            v(89.0, 560.0, 0.7073, 0.0),
            v(3.3, 110.0, 0.5003, 0.0),
            v(0.046, 12.0, 0.0042, 0.0),
            v(0.017, 2.2, 0.0081, 0.0),
        ],
    },
    Bounds {
        method: "csm",
        // 6.74e-06 0.00101 0 0, 3.02e-06 0.000106 0 0, 1.45e-06 3.92e-05 0 0, 3.24e-07 3.71e-06 0 0
        repeat: [
            v(6.8e-6, 0.0011, 0.0, 0.0),
            v(3.1e-6, 0.00011, 0.0, 0.0),
            v(1.5e-6, 4.0e-5, 0.0, 0.0),
            v(3.3e-7, 3.8e-6, 0.0, 0.0),
        ],
        // 1.49e-05 0.000153 0 0, 2.96e-06 0.000106 0 0, 1.19e-06 3.24e-05 0 0, 3.23e-07 3.71e-06 0 0
        clamp: [
            v(1.5e-5, 0.00016, 0.0, 0.0),
            v(3.0e-6, 0.00011, 0.0, 0.0),
            v(1.2e-6, 3.3e-5, 0.0, 0.0),
            v(3.3e-7, 3.8e-6, 0.0, 0.0),
        ],
    },
    Bounds {
        method: "rcsm",
        // 1.31e-05 0.00101 0 0, 3.02e-06 0.000106 0 0, 1.46e-06 3.92e-05 0 0, 3.28e-07 3.52e-06 0 0
        repeat: [
            v(1.4e-5, 0.0011, 0.0, 0.0),
            v(3.1e-6, 0.00011, 0.0, 0.0),
            v(1.5e-6, 4.0e-5, 0.0, 0.0),
            v(3.3e-7, 3.6e-6, 0.0, 0.0),
        ],
        // 2.96e-05 0.000153 0 0, 3.11e-06 0.000106 0 0, 1.2e-06 3.24e-05 0 0, 3.27e-07 3.52e-06 0 0
        clamp: [
            v(3.0e-5, 0.00016, 0.0, 0.0),
            v(3.2e-6, 0.00011, 0.0, 0.0),
            v(1.2e-6, 3.3e-5, 0.0, 0.0),
            v(3.3e-7, 3.6e-6, 0.0, 0.0),
        ],
    },
    Bounds {
        method: "qrm",
        // 1.11e-05 0.000283 0 0, 3.44e-06 6.41e-05 0 0, 2.83e-05 0.112 0 0, 3.75e-07 3.51e-06 0 0
        repeat: [
            v(1.2e-5, 0.00029, 0.0, 0.0),
            v(3.5e-6, 6.5e-5, 0.0, 0.0),
            v(2.9e-5, 0.12, 0.0, 0.0),
            v(3.8e-7, 3.6e-6, 0.0, 0.0),
        ],
        // 1.76e-05 0.000283 0 0, 3.17e-06 6.37e-05 0 0, 2.83e-05 0.112 0 0, 3.65e-07 3.51e-06 0 0
        clamp: [
            v(1.8e-5, 0.00029, 0.0, 0.0),
            v(3.2e-6, 6.4e-5, 0.0, 0.0),
            v(2.9e-5, 0.12, 0.0, 0.0),
            v(3.7e-7, 3.6e-6, 0.0, 0.0),
        ],
    },
    Bounds {
        method: "pdm",
        // 6.77e-06 0.00101 0 0, 5.5e-06 0.000106 0 0, 1.43e-06 3.92e-05 0 0, 4.34e-07 3.39e-06 0 0
        repeat: [
            v(6.8e-6, 0.0011, 0.0, 0.0),
            v(5.6e-6, 0.00011, 0.0, 0.0),
            v(1.5e-6, 4.0e-5, 0.0, 0.0),
            v(4.4e-7, 3.4e-6, 0.0, 0.0),
        ],
        // 1.76e-05 0.000283 0 0, 5.47e-06 0.000106 0 0, 1.19e-06 3.24e-05 0 0, 4.25e-07 3.39e-06 0 0
        clamp: [
            v(1.8e-5, 0.00029, 0.0, 0.0),
            v(5.5e-6, 0.00011, 0.0, 0.0),
            v(1.2e-6, 3.3e-5, 0.0, 0.0),
            v(4.3e-7, 3.4e-6, 0.0, 0.0),
        ],
    },
    Bounds {
        method: "qdm",
        // 6.77e-06 0.00101 0 0, 5.5e-06 0.000106 0 0, 1.43e-06 3.92e-05 0 0, 4.34e-07 3.39e-06 0 0
        repeat: [
            v(6.8e-6, 0.0011, 0.0, 0.0),
            v(5.6e-6, 0.00011, 0.0, 0.0),
            v(1.5e-6, 4.0e-5, 0.0, 0.0),
            v(4.4e-7, 3.4e-6, 0.0, 0.0),
        ],
        // 1.76e-05 0.000283 0 0, 5.47e-06 0.000106 0 0, 1.19e-06 3.24e-05 0 0, 4.25e-07 3.39e-06 0 0
        clamp: [
            v(1.8e-5, 0.00029, 0.0, 0.0),
            v(5.5e-6, 0.00011, 0.0, 0.0),
            v(1.2e-6, 3.3e-5, 0.0, 0.0),
            v(4.3e-7, 3.4e-6, 0.0, 0.0),
        ],
    },
    Bounds {
        method: "maxmip",
        // 6.77e-06 0.00101 0 0, 5.5e-06 0.000106 0 0, 1.43e-06 3.92e-05 0 0, 4.34e-07 3.39e-06 0 0
        repeat: [
            v(6.8e-6, 0.0011, 0.0, 0.0),
            v(5.6e-6, 0.00011, 0.0, 0.0),
            v(1.5e-6, 4.0e-5, 0.0, 0.0),
            v(4.4e-7, 3.4e-6, 0.0, 0.0),
        ],
        // 1.76e-05 0.000283 0 0, 5.47e-06 0.000106 0 0, 1.19e-06 3.24e-05 0 0, 4.25e-07 3.39e-06 0 0
        clamp: [
            v(1.8e-5, 0.00029, 0.0, 0.0),
            v(5.5e-6, 0.00011, 0.0, 0.0),
            v(1.2e-6, 3.3e-5, 0.0, 0.0),
            v(4.3e-7, 3.4e-6, 0.0, 0.0),
        ],
    },
    Bounds {
        method: "quadric",
        // 1.28e-05 0.000435 0 0, 3.06e-06 6.41e-05 0 0, 1.42e-06 5.30e-05 0 0, 1.65e-07 2.22e-06 0 0
        repeat: [
            v(1.3e-5, 0.00044, 0.0, 0.0),
            v(3.1e-6, 6.5e-5, 0.0, 0.0),
            v(1.5e-6, 5.4e-5, 0.0, 0.0),
            v(1.7e-7, 2.3e-6, 0.0, 0.0),
        ],
        // 1.77e-05 0.000283 0 0, 3.14e-06 6.26e-05 0 0, 1.14e-06 5.30e-05 0 0, 1.65e-07 2.22e-06 0 0
        clamp: [
            v(1.8e-5, 0.00029, 0.0, 0.0),
            v(3.2e-6, 6.3e-5, 0.0, 0.0),
            v(1.2e-6, 5.4e-5, 0.0, 0.0),
            v(1.7e-7, 2.3e-6, 0.0, 0.0),
        ],
    },
];

/// Traces `req`-like rays and compares them with the reference: (all rays, converged rays only).
fn trace_one(
    ctx: &std::sync::Arc<relief::vk::Context>,
    method: Method,
    hf: &Heightfield,
    map: Option<&MapData>,
    angle: f64,
    budget: Budget,
    address: Address,
) -> (TraceStats, TraceStats) {
    let dir = ray_direction(angle, 30.0);
    let req = TraceRequest {
        method,
        dir: dir.map(|x| x as f32),
        depth_scale: DEPTH_SCALE,
        grid: (64, 64),
        budget,
        address,
        format: HeightFormat::R16Unorm,
        map,
        shadow: None,
    };
    let out = trace_on_gpu(ctx, hf, &req).expect("trace runs");
    let s = f64::from(DEPTH_SCALE);
    let (hits, steps): (Vec<[f32; 8]>, Vec<[u32; 2]>) = out
        .hits
        .iter()
        .zip(&out.steps)
        .filter(|(_, st)| st[1] == 0)
        .unzip();
    (
        trace_stats(hf, &out.hits, &out.steps, s, address),
        trace_stats(hf, &hits, &steps, s, address),
    )
}

/// What in `all` (every ray) and `ok` (the converged rays) exceeds `b`.
fn excesses(all: &TraceStats, ok: &TraceStats, b: View) -> Vec<String> {
    let checks = [
        ("NaN hits", all.nan_pixels as f64, 0.0),
        ("capped rate", all.capped_rate, b.capped),
        ("mean error", ok.error_texels.mean, b.mean),
        ("max error", ok.error_texels.max, b.max),
        ("gross rate", ok.gross_rate, b.gross),
    ];
    checks
        .iter()
        .filter(|(_, got, bound)| got > bound)
        .map(|(what, got, bound)| format!("{what} {got:.6} (bound {bound})"))
        .collect()
}

/// Traces `id` on every field at every angle with `address` (the GPU's sampler, the map's build
/// and the reference's), comparing each view with the bounds stated for that addressing.
fn check_method(id: &str, address: Address) {
    let Some(ctx) = common::device(id) else {
        return;
    };
    let method: Method = id.parse().expect("known id");
    let bounds = BOUNDS
        .iter()
        .find(|b| b.method == id)
        .expect("every method states its bounds");
    let per_angle = match address {
        Address::Repeat => bounds.repeat,
        Address::Clamp => bounds.clamp,
    };
    let mut failures = Vec::new();
    for field in FIELDS {
        let hf = field.generate(SIZE, SIZE, 11).quantized_unorm16();
        let map = build_method_map(method, &hf, address);
        for (&angle, &bound) in ANGLES.iter().zip(&per_angle) {
            let budget = method.info().default_budget;
            let map = map.as_ref().map(|(m, _)| m);
            let (all, ok) = trace_one(&ctx, method, &hf, map, angle, budget, address);
            eprintln!(
                "{id:9} {address:6} {:7} {angle:4} deg: mean {:.3e} max {:.3e} gross {:.4} capped {:.4} steps {:.1}/{}",
                field.name(), ok.error_texels.mean, ok.error_texels.max, ok.gross_rate,
                all.capped_rate, all.steps.mean, all.steps.max
            );
            for e in excesses(&all, &ok, bound) {
                failures.push(format!("{} at {angle} deg: {e}", field.name()));
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
    assert!(
        failures.is_empty(),
        "{id} ({address}):\n{}",
        failures.join("\n")
    );
}

#[test]
fn every_method_states_bounds() {
    for m in Method::all() {
        assert!(
            BOUNDS.iter().any(|b| b.method == m.id()),
            "{m} has no stated bounds"
        );
    }
}

/// One test per method and addressing, `repeat::<id>` and `clamp::<id>`, so they run in parallel.
macro_rules! method_tests {
    ($($id:ident),* $(,)?) => {
        mod repeat {
            $(#[test] fn $id() { super::check_method(stringify!($id), super::Address::Repeat); })*
        }
        mod clamp {
            $(#[test] fn $id() { super::check_method(stringify!($id), super::Address::Clamp); })*
        }
    };
}

method_tests!(parallax, steep, relief, pom, qrm, pdm, qdm, maxmip, quadric, csm, rcsm);

/// Rays of 4096 that each method with a leaf choice misses by more than a texel with the paper's
/// refinement, bricks at 5 degrees (measured; with the exact leaf: none).
const PAPER_GROSS_RAYS: &[(&str, u32)] = &[
    ("csm", 1400),
    ("rcsm", 1400),
    ("qrm", 57),
    ("pdm", 89),
    ("qdm", 207),
    // 37 under a fixed cap of 256: with the cap grown to the ray's extent, fewer rays reach the
    // budget's end still above the surface, where the paper's refinement guesses.
    ("quadric", 8),
];

#[test]
fn paper_leaf_stays_selectable() {
    // Specialization constant 2 reaches the shaders: with the paper's refinement each method with
    // a leaf choice misses slivers at a grazing view again, as many as measured within 10%, and
    // with the exact leaf it misses none.
    let Some(ctx) = common::device("paper_leaf_stays_selectable") else {
        return;
    };
    let hf = Generator::Bricks
        .generate(SIZE, SIZE, 11)
        .quantized_unorm16();
    let mut failures = Vec::new();
    for method in Method::all().filter(|m| m.info().leaf_choice) {
        let map = build_method_map(method, &hf, Address::Repeat);
        let map = map.as_ref().map(|(m, _)| m);
        let exact = method.info().default_budget;
        let paper = Budget {
            leaf: Leaf::Paper,
            ..exact
        };
        let e = trace_one(&ctx, method, &hf, map, 5.0, exact, Address::Repeat).0;
        let p = trace_one(&ctx, method, &hf, map, 5.0, paper, Address::Repeat).0;
        let missed = (p.gross_rate * p.rays as f64).round();
        eprintln!(
            "{method:9} bricks 5 deg: exact gross {:.4}, paper gross {:.4} ({missed} rays)",
            e.gross_rate, p.gross_rate
        );
        let (_, measured) = PAPER_GROSS_RAYS
            .iter()
            .find(|(id, _)| *id == method.id())
            .expect("every method with a leaf choice states its paper misses");
        let measured = f64::from(*measured);
        if e.gross_rate > 0.0 || (missed - measured).abs() > 0.1 * measured {
            failures.push(format!(
                "{method}: gross rate {} exact, {missed} rays paper (measured {measured})",
                e.gross_rate
            ));
        }
    }
    common::assert_no_validation_errors(&ctx);
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

#[test]
fn budgets_are_honoured() {
    // A one-step budget must cap the hierarchical methods rather than loop on.
    let Some(ctx) = common::device("budgets_are_honoured") else {
        return;
    };
    let hf = Generator::Fbm.generate(SIZE, SIZE, 3).quantized_unorm16();
    for id in ["qdm", "pdm", "qrm", "maxmip"] {
        let method: Method = id.parse().expect("known id");
        let map = build_method_map(method, &hf, Address::Repeat);
        let req = TraceRequest {
            method,
            dir: ray_direction(20.0, 10.0).map(|x| x as f32),
            depth_scale: DEPTH_SCALE,
            grid: (16, 16),
            budget: Budget {
                max_steps: 1,
                extent_limit: 0,
                ..method.info().default_budget
            },
            address: Address::Repeat,
            format: HeightFormat::R16Unorm,
            map: map.as_ref().map(|(data, _)| data),
            shadow: None,
        };
        let out = trace_on_gpu(&ctx, &hf, &req).expect("trace runs");
        let s = trace_stats(
            &hf,
            &out.hits,
            &out.steps,
            f64::from(DEPTH_SCALE),
            Address::Repeat,
        );
        // Measured: every ray capped, for each of the four.
        assert!(
            s.capped_rate == 1.0,
            "{id} with one step: capped rate {}",
            s.capped_rate
        );
        assert!(
            s.steps.max <= 1,
            "{id} used {} steps with a budget of 1",
            s.steps.max
        );
        assert_eq!(s.nan_pixels, 0);
    }
    common::assert_no_validation_errors(&ctx);
}
