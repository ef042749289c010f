//! The GPU quadric map against the CPU builder (the reference), on seeded synthetic fields at
//! awkward sizes under both addressings: the height channel equal bit for bit; the profiles an
//! upper bound of the bilinear surface around points of every texel (checked point by point); no
//! profile higher than the CPU's profile a fixed factor farther out (it may be lower: the GPU fits
//! its cap to the points exactly, the CPU to its hull's vertices by the paper's formula); and a CPU
//! trace through the GPU map finds the exact reference's first hit.

mod common;

use std::sync::Arc;

use relief::heightfield::quadric_map::{profile_height, trace_quadric_cpu, QuadricMap};
use relief::heightfield::reference::{surface_depth, trace, Address, SurfaceModel};
use relief::heightfield::{Generator, Heightfield, MapData};
use relief::render::QuadricMapPass;
use relief::vk::Context;

use common::rays::Rng;

const FIELDS: [Generator; 5] = [
    Generator::Fbm,
    Generator::Noise,
    Generator::Step,
    Generator::Spikes,
    Generator::Bricks,
];
const SIZES: [(u32, u32); 5] = [(1, 1), (2, 2), (3, 5), (64, 64), (257, 129)];
const ADDRESSES: [Address; 2] = [Address::Repeat, Address::Clamp];

/// Slack for the bound checks, in normalized height: the surface and the bound are evaluated in
/// f64 from the same f32 values, so only that arithmetic's rounding is left.
const BOUND_TOL: f64 = 1e-9;
/// Quantiles (p50, p90, p99, max) the GPU profile over the CPU's may reach, over every texel and
/// radius (heights capped at 1, the most anything rises). The GPU's points stand for their nodes
/// from nearer than the CPU's hull (rings of RING nodes against its ACCEPT_RATIO), and its cone
/// is fitted to the near texels only, leaving steeper farther points to the parabola (on Step
/// fields 10/7 of the CPU's cone slope); its rounding margins add 1.2e-4 to all (b). Measured at
/// RING 3: at most 1.0002, 1.43, 1.51 and 5.2.
const RATIO_LIMITS: [f64; 4] = [1.01, 1.6, 2.0, 8.0];

/// Steps a tracer may take through the GPU map, over those through the CPU map (measured 0.876:
/// fewer, the parabola beyond the near cone lets rays step farther than the CPU's longer cone).
const STEP_RATIO: f64 = 1.1;

/// The GPU map as a `QuadricMap`, so the CPU tracer can walk it.
fn as_quadric_map(data: &MapData) -> QuadricMap {
    assert_eq!(data.channels, 4, "a, b, c, h");
    QuadricMap {
        width: data.width,
        height: data.height,
        texels: data
            .texels
            .chunks_exact(4)
            .map(|t| [t[0], t[1], t[2], t[3]])
            .collect(),
    }
}

/// Radii (uv) at which profiles are compared: from a tenth of a texel to the whole map.
fn radii(hf: &Heightfield) -> Vec<f64> {
    let texel = 1.0 / f64::from(hf.width().max(hf.height()));
    (0..24).map(|k| texel * 0.1 * 1.5f64.powi(k)).collect()
}

/// Compares the GPU map of `hf` with the CPU's; returns the GPU map.
fn check(pass: &QuadricMapPass, hf: &Heightfield, address: Address, what: &str) -> QuadricMap {
    let (data, gpu_ms) = pass.build(hf, address).expect("GPU quadric map builds");
    assert!(gpu_ms >= 0.0, "{what}: GPU time {gpu_ms}");
    assert_eq!(
        (data.width, data.height),
        (hf.width(), hf.height()),
        "{what}"
    );
    let gpu = as_quadric_map(&data);
    let cpu = QuadricMap::build(hf, address);
    let radii = radii(hf);
    let mut ratios = Vec::new();
    for (k, (g, c)) in gpu.texels.iter().zip(&cpu.texels).enumerate() {
        let texel = (k as u32 % hf.width(), k as u32 / hf.width());
        let [a, b, cc, h] = *g;
        assert_eq!(
            h.to_bits(),
            c[3].to_bits(),
            "{what} {texel:?}: height channel"
        );
        assert!(
            a.is_finite() && a > 0.0 && b.is_finite() && b >= 0.0 && cc.is_finite() && cc >= a,
            "{what} {texel:?}: profile {g:?}"
        );
        for &r in &radii {
            let (fg, fc) = (
                profile_height(*g, r).min(1.0),
                profile_height(*c, r).min(1.0),
            );
            if fc > 1e-3 {
                ratios.push(fg / fc);
            }
        }
    }
    ratios.sort_by(f64::total_cmp);
    if let Some(&max) = ratios.last() {
        let at = |f: f64| ratios[((ratios.len() - 1) as f64 * f) as usize];
        let quantiles = [at(0.5), at(0.9), at(0.99), max];
        eprintln!("{what}: GPU over CPU profile p50, p90, p99, max {quantiles:.4?}");
        for (q, limit) in quantiles.iter().zip(RATIO_LIMITS) {
            assert!(
                *q <= limit,
                "{what}: GPU profiles too far above the CPU's: {quantiles:?} over {RATIO_LIMITS:?}"
            );
        }
    }
    gpu
}

fn bilinear(hf: &Heightfield, p: (f64, f64), address: Address) -> f64 {
    1.0 - surface_depth(hf, p.0, p.1, 1.0, SurfaceModel::Bilinear, address)
}

/// The uv distance between `q` and `x`, on the torus under `Repeat`.
fn uv_distance(q: (f64, f64), x: (f64, f64), address: Address) -> f64 {
    let wrap = |d: f64| match address {
        Address::Repeat => {
            let d = d.rem_euclid(1.0);
            d.min(1.0 - d)
        }
        Address::Clamp => d.abs(),
    };
    wrap(x.0 - q.0).hypot(wrap(x.1 - q.1))
}

/// The profile of the texel holding `q` (nearest fetch, addressed).
fn profile_at(map: &QuadricMap, q: (f64, f64), address: Address) -> [f32; 4] {
    let index = |x: f64, n: u32| {
        let k = (x * f64::from(n)).floor() as i64;
        match address {
            Address::Repeat => k.rem_euclid(i64::from(n)) as u32,
            Address::Clamp => k.clamp(0, i64::from(n) - 1) as u32,
        }
    };
    map.get(index(q.0, map.width), index(q.1, map.height))
}

/// Every texel's corners, edge midpoints and centre against every texel centre, plus random
/// pairs near and far: the surface never rises above `B(q) + F(|x - q|)`.
fn check_upper_bound(
    hf: &Heightfield,
    map: &QuadricMap,
    address: Address,
    what: &str,
    rng: &mut Rng,
) {
    let (w, h) = (f64::from(hf.width()), f64::from(hf.height()));
    let check_pair = |q: (f64, f64), x: (f64, f64)| {
        let bound = bilinear(hf, q, address)
            + profile_height(profile_at(map, q, address), uv_distance(q, x, address));
        let surface = bilinear(hf, x, address);
        assert!(
            surface <= bound + BOUND_TOL,
            "{what} q={q:?} x={x:?}: surface {surface} above the bound {bound}"
        );
    };
    let small = hf.texel_count() <= 64 * 64;
    for j in 0..hf.height() {
        for i in 0..hf.width() {
            for (fu, fv) in [
                (0.0, 0.0),
                (0.5, 0.0),
                (0.5, 0.5),
                (0.999, 0.5),
                (0.999, 0.999),
            ] {
                let q = ((f64::from(i) + fu) / w, (f64::from(j) + fv) / h);
                let x = if small {
                    let k = (i * 7 + j * 13) % hf.width();
                    ((f64::from(k) + 0.5) / w, rng.next())
                } else {
                    (rng.next(), rng.next())
                };
                check_pair(q, x);
                // A point within a few texels, where the cone and the gradient bound matter.
                let r = 10f64.powf(rng.range(-3.0, 0.7)) / w.max(h);
                let phi = rng.range(0.0, std::f64::consts::TAU);
                check_pair(q, (q.0 + r * phi.cos(), q.1 + r * phi.sin()));
            }
        }
    }
}

fn context() -> Option<(Arc<Context>, QuadricMapPass)> {
    let ctx = common::device("quadric_map_gpu")?;
    let pass = QuadricMapPass::new(&ctx).expect("quadric map pipeline");
    Some((ctx, pass))
}

#[test]
fn gpu_quadric_map_bounds_the_surface_close_to_the_cpu_builder() {
    let Some((ctx, pass)) = context() else {
        return;
    };
    let mut rng = Rng(3);
    for (k, generator) in FIELDS.into_iter().enumerate() {
        for (w, h) in SIZES {
            let hf = generator.generate(w, h, 17 + k as u64);
            for address in ADDRESSES {
                let what = format!("{generator:?} {w}x{h} {address}");
                let map = check(&pass, &hf, address, &what);
                check_upper_bound(&hf, &map, address, &what, &mut rng);
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn flat_fields_get_the_flat_profile() {
    let Some((ctx, pass)) = context() else {
        return;
    };
    let flat = Generator::Flat0.generate(9, 7, 1);
    for address in ADDRESSES {
        let map = check(&pass, &flat, address, &format!("flat {address}"));
        assert!(
            map.texels.iter().all(|t| t[..3] == [1.0, 0.0, 1.0]),
            "{address}"
        );
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn tracing_the_gpu_map_finds_the_exact_first_hit() {
    let Some((ctx, pass)) = context() else {
        return;
    };
    let mut rng = Rng(5);
    let mut errors = Vec::new();
    // Steps through the GPU map and through the CPU map, over all rays.
    let (mut gpu_steps, mut cpu_steps) = (0u64, 0u64);
    for generator in [
        Generator::Fbm,
        Generator::Spikes,
        Generator::Step,
        Generator::Bricks,
    ] {
        for (w, h) in [(16, 16), (33, 17)] {
            let hf = generator.generate(w, h, u64::from(w * 31 + h));
            for address in ADDRESSES {
                let what = format!("{generator:?} {w}x{h} {address}");
                let map = check(&pass, &hf, address, &what);
                let cpu_map = QuadricMap::build(&hf, address);
                for _ in 0..100 {
                    let ray = rng.ray();
                    let s = [0.02, 0.1, 0.3][(rng.next() * 3.0) as usize];
                    let exact = trace(&hf, &ray, s, SurfaceModel::Bilinear, address).z;
                    let walked = trace_quadric_cpu(&hf, &map, &ray, s, address, 20_000, 0);
                    let at = format!("{what} {ray:?} s={s}");
                    assert!(!walked.capped, "{at}: capped");
                    assert!(
                        walked.z <= exact + BOUND_TOL,
                        "{at}: stopped at {} past the hit {exact}",
                        walked.z
                    );
                    let cpu = trace_quadric_cpu(&hf, &cpu_map, &ray, s, address, 20_000, 0);
                    gpu_steps += u64::from(walked.steps);
                    cpu_steps += u64::from(cpu.steps);
                    let lateral = ray.dx.hypot(ray.dy) / ray.dz;
                    errors.push((exact - walked.z) * lateral.max(1.0) * f64::from(w.max(h)));
                }
            }
        }
    }
    errors.sort_by(f64::total_cmp);
    let (p99, max) = (errors[errors.len() * 99 / 100], errors[errors.len() - 1]);
    eprintln!(
        "{} rays: error (texels) p99 {p99:.2e}, max {max:.2e}",
        errors.len()
    );
    assert!(p99 <= 0.01, "p99 error {p99} texels");
    assert!(max <= 1.0, "gross error {max} texels");
    // Higher profiles would cost steps; STEP_RATIO bounds how many.
    let ratio = gpu_steps as f64 / cpu_steps as f64;
    eprintln!("steps through the GPU map over the CPU map's: {ratio:.3}");
    assert!(
        ratio <= STEP_RATIO,
        "GPU map takes {ratio:.3}x the CPU map's steps"
    );
    common::assert_no_validation_errors(&ctx);
}
