//! Tests of the quadric map: the hull and the fitted profile bound the bilinear surface, the tracer never passes
//! the exact bilinear hit and converges onto it, and the step formula is the exact 2D intersection.
//!
//! Ground truth is the reference tracer with `SurfaceModel::Bilinear`, the surface the map is built for.

use std::time::Instant;

use super::*;
use crate::heightfield::reference::trace;
use crate::heightfield::rng::SplitMix64;
use crate::heightfield::Generator;

const ADDRESSES: [Address; 2] = [Address::Repeat, Address::Clamp];

/// Slack for comparisons of bounds computed in f64 from the same f32 heights.
const BOUND_TOL: f64 = 1e-9;

fn unit(rng: &mut SplitMix64) -> f64 {
    (rng.next_u64() >> 11) as f64 / (1u64 << 53) as f64
}

fn range(rng: &mut SplitMix64, lo: f64, hi: f64) -> f64 {
    lo + (hi - lo) * unit(rng)
}

/// A ray entering at `(u0, v0)`, elevation and azimuth in degrees (docs/conventions.md).
fn ray_at(u0: f64, v0: f64, elevation: f64, azimuth: f64) -> RefRay {
    let (e, a) = (elevation.to_radians(), azimuth.to_radians());
    RefRay {
        u0,
        v0,
        dx: e.cos() * a.cos(),
        dy: e.cos() * a.sin(),
        dz: e.sin(),
    }
}

/// The small maps the bound tests run on: every texel of each is checked.
fn small_maps() -> Vec<(&'static str, Heightfield)> {
    vec![
        ("noise 8x8", Generator::Noise.generate(8, 8, 3)),
        ("fbm 16x16", Generator::Fbm.generate(16, 16, 4)),
        ("spikes 16x16", Generator::Spikes.generate(16, 16, 5)),
        ("step 9x7", Generator::Step.generate(9, 7, 0)),
        ("noise 7x3", Generator::Noise.generate(7, 3, 6)),
        ("fbm 1x5", Generator::Fbm.generate(1, 5, 7)),
    ]
}

/// Every texel's point of the radial bound of texel `(i, j)`, by brute force (no pyramid).
fn brute_points(builder: &Builder, i: u32, j: u32) -> Vec<(f64, f64)> {
    let tb = builder.texel_bound(i, j);
    let hf = builder.hf;
    let mut points = Vec::new();
    for l in 0..hf.height() {
        for k in 0..hf.width() {
            let value = f64::from(hf.get(k, l)) - tb.h_lo;
            if value > 0.0 {
                let d = builder.distance(&tb, Node(0, k, l));
                points.push((builder.corner(&tb, d, value), value));
            }
        }
    }
    points
}

fn hull_of(points: &[(f64, f64)]) -> Hull {
    let mut hull = Hull::new();
    for &(r, v) in points {
        if hull.eval(r) < v {
            hull.insert(Vertex {
                r,
                value: v,
                source: None,
            });
        }
    }
    hull
}

/// The pyramid search's hull `fast` against the hull of every texel's point `slow`: never below it, and, since far
/// nodes stand in for their texels, at most `slow` stretched by the accept ratio.
fn check_against_brute_force(builder: &Builder, i: u32, j: u32, seeds: &[Node], tag: &str) -> Hull {
    let fast = builder.radial_hull(i, j, seeds);
    let slow = hull_of(&brute_points(builder, i, j));
    let samples = fast.vertices.iter().chain(&slow.vertices).map(|p| p.r);
    for r in samples.chain((0..200).map(|k| f64::from(k) / 100.0)) {
        let (f, s) = (fast.eval(r), slow.eval(r));
        assert!(f >= s - BOUND_TOL, "{tag} r={r}: {f} below {s}");
        let stretched = slow.eval(r * (1.0 + ACCEPT_RATIO));
        assert!(
            f <= stretched + BOUND_TOL,
            "{tag} r={r}: {f} above {stretched}"
        );
    }
    fast
}

#[test]
fn pyramid_hull_bounds_the_brute_force_hull_within_the_accept_ratio() {
    let mut maps = small_maps();
    maps.push(("fbm 64x64", Generator::Fbm.generate(64, 64, 20)));
    for (name, hf) in maps {
        for address in ADDRESSES {
            let builder = Builder::new(&hf, address);
            for j in 0..hf.height() {
                // Also with the warm start the build uses: seeds from the texel before.
                let mut seeds = Vec::new();
                for i in 0..hf.width() {
                    check_against_brute_force(
                        &builder,
                        i,
                        j,
                        &[],
                        &format!("{name} {address} ({i},{j})"),
                    );
                    let tag = format!("{name} {address} ({i},{j}) seeded");
                    let hull = check_against_brute_force(&builder, i, j, &seeds, &tag);
                    seeds = hull.vertices.iter().filter_map(|v| v.source).collect();
                }
            }
        }
    }
}

#[test]
fn hull_is_concave_non_decreasing_and_above_the_radial_bound() {
    for (name, hf) in small_maps() {
        for address in ADDRESSES {
            let builder = Builder::new(&hf, address);
            for j in 0..hf.height() {
                for i in 0..hf.width() {
                    let hull = builder.radial_hull(i, j, &[]);
                    let points = brute_points(&builder, i, j);
                    let vs: Vec<(f64, f64)> =
                        hull.vertices.iter().map(|v| (v.r, v.value)).collect();
                    assert_eq!(vs[0], (0.0, 0.0));
                    let slopes: Vec<f64> = vs
                        .windows(2)
                        .map(|w| (w[1].1 - w[0].1) / (w[1].0 - w[0].0))
                        .collect();
                    assert!(
                        slopes.iter().all(|&m| m > 0.0),
                        "{name} ({i},{j}) not increasing: {vs:?}"
                    );
                    // Concave; points on the gradient bound's line may stay as vertices up to rounding.
                    let concave = slopes.windows(2).all(|m| m[0] * (1.0 + 1e-12) > m[1]);
                    assert!(concave, "{name} ({i},{j}) not concave: {vs:?}");
                    // Above the radial bound m(r) = max { value : r_t <= r } at every point and between them.
                    for &(r, _) in &points {
                        for r in [r, r * 1.5, r + 0.01] {
                            let m = points
                                .iter()
                                .filter(|p| p.0 <= r)
                                .fold(0.0, |m: f64, p| m.max(p.1));
                            assert!(
                                hull.eval(r) >= m - BOUND_TOL,
                                "{name} {address} ({i},{j}) r={r}"
                            );
                        }
                    }
                }
            }
        }
    }
}

#[test]
fn fitted_profile_lies_above_the_hull() {
    for (name, hf) in small_maps() {
        for address in ADDRESSES {
            let builder = Builder::new(&hf, address);
            let map = QuadricMap::build(&hf, address);
            for j in 0..hf.height() {
                for i in 0..hf.width() {
                    let hull = builder.radial_hull(i, j, &[]);
                    let texel = map.get(i, j);
                    let [a, b, c] = [texel[0], texel[1], texel[2]].map(f64::from);
                    assert!(a > 0.0 && b >= 0.0 && c >= a, "{name} ({i},{j}): {texel:?}");
                    if let Some(&Vertex {
                        r: r1, value: v1, ..
                    }) = hull.vertices.get(1)
                    {
                        assert!(
                            a >= r1 && b / a >= v1 / r1,
                            "{name} ({i},{j}) cone below first edge"
                        );
                    }
                    for &Vertex { r, value: v, .. } in &hull.vertices {
                        assert!(
                            profile_height(texel, r) >= v,
                            "{name} {address} ({i},{j}) vertex r={r}"
                        );
                    }
                    let mut last = 0.0;
                    for k in 0..=2000 {
                        let r = 1.5 * f64::from(k) / 2000.0;
                        let f = profile_height(texel, r);
                        assert!(
                            f >= hull.eval(r) - BOUND_TOL,
                            "{name} {address} ({i},{j}) r={r}"
                        );
                        assert!(f >= last, "{name} ({i},{j}) profile falls at r={r}");
                        last = f;
                    }
                }
            }
        }
    }
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

fn bilinear(hf: &Heightfield, p: (f64, f64), address: Address) -> f64 {
    1.0 - surface_depth(hf, p.0, p.1, 1.0, SurfaceModel::Bilinear, address)
}

#[test]
fn surface_never_rises_above_the_profile_around_any_point_of_the_texel() {
    let mut rng = SplitMix64::new(11);
    let mut maps = small_maps();
    maps.push(("fbm 33x17", Generator::Fbm.generate(33, 17, 8)));
    for (name, hf) in maps {
        let (w, h) = (f64::from(hf.width()), f64::from(hf.height()));
        for address in ADDRESSES {
            let map = QuadricMap::build(&hf, address);
            for _ in 0..20_000 {
                // q anywhere (outside the map too under Clamp); x near q (log-uniform radius) or anywhere.
                let spill = if address == Address::Clamp { 0.2 } else { 0.0 };
                let q = (
                    range(&mut rng, -spill, 1.0 + spill),
                    range(&mut rng, -spill, 1.0 + spill),
                );
                let x = if rng.below(2) == 0 {
                    let r = 10f64.powf(range(&mut rng, -4.0, 0.5)) / w.max(h);
                    let phi = range(&mut rng, 0.0, std::f64::consts::TAU);
                    (q.0 + r * phi.cos(), q.1 + r * phi.sin())
                } else {
                    (
                        range(&mut rng, -spill, 1.0 + spill),
                        range(&mut rng, -spill, 1.0 + spill),
                    )
                };
                let texel = map.fetch(q.0, q.1, address);
                let bound =
                    bilinear(&hf, q, address) + profile_height(texel, uv_distance(q, x, address));
                let surface = bilinear(&hf, x, address);
                assert!(
                    surface <= bound + BOUND_TOL,
                    "{name} {address} q={q:?} x={x:?}: {surface} > {bound}"
                );
            }
        }
    }
}

#[test]
fn quadric_step_is_the_first_crossing_of_ray_and_profile() {
    let mut rng = SplitMix64::new(12);
    for _ in 0..20_000 {
        let a = range(&mut rng, 1e-3, 0.2);
        let texel = [
            a,
            range(&mut rng, 0.0, 0.5) * a * 50.0,
            a + range(&mut rng, 0.0, 2.0),
            0.5,
        ]
        .map(|x| x as f32);
        let (gap, s) = (range(&mut rng, 1e-4, 0.3), range(&mut rng, 0.01, 0.5));
        let lambda = if rng.below(10) == 0 {
            0.0
        } else {
            10f64.powf(range(&mut rng, -2.0, 2.5))
        };
        let t = quadric_step(gap, lambda, s, texel);
        assert!((0.0..=gap).contains(&t), "t={t} gap={gap}");
        // At t the ray is on the profile (it may also be on the cap's plane); before t it is strictly above.
        let above = |tau: f64| (gap - tau) / s - profile_height(texel, lambda * tau);
        assert!(
            above(t).abs() <= 1e-9 * (1.0 + gap / s),
            "off the profile: {}",
            above(t)
        );
        for k in 0..64 {
            let tau = t * f64::from(k) / 64.0;
            assert!(above(tau) > -1e-12, "crossed before t at {tau} (t={t})");
        }
    }
}

/// Every depth the quadric loop reaches, and its result.
fn traced_path(
    hf: &Heightfield,
    map: &QuadricMap,
    ray: &RefRay,
    s: f64,
    address: Address,
    budget: u32,
) -> (Vec<f64>, QuadricTrace) {
    let mut path = Vec::new();
    let tracer = Tracer::new(hf, map, ray, s, address);
    let result = tracer.run(budget, 0, quadric_step, &mut |z| path.push(z));
    (path, result)
}

/// The error, in texels, of a depth `dz` off along the ray: the larger of the uv distance and the depth error
/// (docs/conventions.md).
fn texels_along(hf: &Heightfield, ray: &RefRay, dz: f64) -> f64 {
    let du = dz * ray.dx / ray.dz * f64::from(hf.width());
    let dv = dz * ray.dy / ray.dz * f64::from(hf.height());
    du.hypot(dv).max(dz.abs() * f64::from(hf.width()))
}

#[test]
fn tracer_never_passes_the_exact_hit_and_converges_onto_it() {
    const BUDGET: u32 = 20_000;
    let mut rng = SplitMix64::new(13);
    let mut errors = Vec::new();
    let (mut rays, mut steps, mut capped) = (0, 0u64, 0);
    for generator in [
        Generator::Noise,
        Generator::Fbm,
        Generator::Spikes,
        Generator::Step,
    ] {
        for (w, h) in [(16, 16), (33, 17), (64, 64)] {
            let hf = generator.generate(w, h, u64::from(w * 31 + h));
            for address in ADDRESSES {
                let map = QuadricMap::build(&hf, address);
                for _ in 0..100 {
                    let ray = ray_at(
                        unit(&mut rng),
                        unit(&mut rng),
                        range(&mut rng, 5.0, 90.0),
                        range(&mut rng, 0.0, 360.0),
                    );
                    let s = [0.02, 0.1, 0.3][rng.below(3) as usize];
                    let exact = trace(&hf, &ray, s, SurfaceModel::Bilinear, address).z;
                    let (path, result) = traced_path(&hf, &map, &ray, s, address, BUDGET);
                    let tag = format!("{generator} {w}x{h} {address} s={s} {ray:?}");
                    for pair in path.windows(2) {
                        assert!(pair[1] >= pair[0], "{tag}: went back up");
                    }
                    for &z in &path {
                        assert!(
                            z <= exact + BOUND_TOL,
                            "{tag}: reached {z} past the hit {exact}"
                        );
                    }
                    assert!(!result.capped, "{tag}: capped");
                    rays += 1;
                    steps += u64::from(result.steps);
                    capped += usize::from(result.capped);
                    errors.push(texels_along(&hf, &ray, exact - result.z));
                }
            }
        }
    }
    errors.sort_by(f64::total_cmp);
    let p99 = errors[errors.len() * 99 / 100];
    let max = errors[errors.len() - 1];
    let gross = errors.iter().filter(|&&e| e > 1.0).count();
    println!(
        "{rays} rays, mean {:.1} steps, {capped} capped; error (texels) p50 {:.2e} p99 {p99:.2e} max {max:.2e}, {gross} gross",
        steps as f64 / rays as f64,
        errors[errors.len() / 2]
    );
    assert!(p99 <= 0.01, "p99 error {p99} texels");
    assert!(gross * 200 <= rays, "{gross} gross errors in {rays} rays");
}

#[test]
fn flat_fields_and_vertical_rays_hit_in_one_step() {
    for generator in [
        Generator::Flat0,
        Generator::Flat1,
        Generator::Fbm,
        Generator::Noise,
    ] {
        let hf = generator.generate(16, 16, 9);
        for address in ADDRESSES {
            let map = QuadricMap::build(&hf, address);
            let vertical = ray_at(0.3, 0.7, 90.0, 0.0);
            let exact = trace(&hf, &vertical, 0.1, SurfaceModel::Bilinear, address).z;
            let result = trace_quadric_cpu(&hf, &map, &vertical, 0.1, address, 8, 0);
            assert!(
                result.steps <= 1 && (result.z - exact).abs() < 1e-12,
                "{generator} vertical: {result:?}"
            );
            if matches!(generator, Generator::Flat0 | Generator::Flat1) {
                let slanted = ray_at(0.3, 0.7, 20.0, 130.0);
                let result = trace_quadric_cpu(&hf, &map, &slanted, 0.1, address, 8, 0);
                let exact = trace(&hf, &slanted, 0.1, SurfaceModel::Bilinear, address).z;
                assert!(
                    result.steps <= 1 && (result.z - exact).abs() < 1e-12,
                    "{generator} slanted: {result:?}"
                );
            }
        }
    }
}

#[test]
fn zero_depth_scale_hits_at_the_top_and_zero_budget_is_capped() {
    let hf = Generator::Fbm.generate(16, 16, 10);
    let map = QuadricMap::build(&hf, Address::Repeat);
    let ray = ray_at(0.5, 0.5, 30.0, 45.0);
    let flat = trace_quadric_cpu(&hf, &map, &ray, 0.0, Address::Repeat, 8, 8);
    assert_eq!((flat.z, flat.steps, flat.capped), (0.0, 0, false));
    let none = trace_quadric_cpu(&hf, &map, &ray, 0.1, Address::Repeat, 0, 0);
    assert_eq!((none.z, none.steps, none.capped), (0.0, 0, true));
}

#[test]
fn refinement_of_a_capped_ray_brackets_the_hit() {
    let hf = Generator::Fbm.generate(32, 32, 14);
    let map = QuadricMap::build(&hf, Address::Repeat);
    let mut rng = SplitMix64::new(15);
    let (mut improved, mut total) = (0, 0);
    for _ in 0..200 {
        let ray = ray_at(
            unit(&mut rng),
            unit(&mut rng),
            range(&mut rng, 20.0, 70.0),
            range(&mut rng, 0.0, 360.0),
        );
        let exact = trace(&hf, &ray, 0.1, SurfaceModel::Bilinear, Address::Repeat).z;
        let raw = trace_quadric_cpu(&hf, &map, &ray, 0.1, Address::Repeat, 6, 0);
        let refined = trace_quadric_cpu(&hf, &map, &ray, 0.1, Address::Repeat, 6, 12);
        assert!(raw.z <= exact + BOUND_TOL);
        if raw.capped {
            total += 1;
            // Refinement either keeps the safe depth or lands on a crossing (at or under the surface).
            let tracer = Tracer::new(&hf, &map, &ray, 0.1, Address::Repeat);
            assert!(refined.z == raw.z || tracer.gap(refined.z) <= 0.0);
            improved += usize::from((refined.z - exact).abs() < (raw.z - exact).abs());
        }
    }
    println!("refinement improved {improved} of {total} capped rays");
    assert!(total > 0);
}

#[test]
fn map_layout_and_build_are_deterministic() {
    let hf = Generator::Noise.generate(33, 17, 16);
    let map = QuadricMap::build(&hf, Address::Clamp);
    assert_eq!((map.width, map.height, map.texels.len()), (33, 17, 33 * 17));
    for j in 0..17 {
        for i in 0..33 {
            assert_eq!(map.get(i, j)[3], hf.get(i, j));
            assert_eq!(map.get(i, j), map.texels[(j * 33 + i) as usize]);
        }
    }
    assert_eq!(QuadricMap::build(&hf, Address::Clamp), map);
    assert_ne!(QuadricMap::build(&hf, Address::Repeat), map);
}

/// Mean steps to converge with quadric steps and with plain conservative cone steps over the same bound (the cone
/// of slope b/a, the hull's first edge, extended forever), and the mean error of each after a budget of 8.
#[test]
fn quadric_versus_cone_step_counts() {
    let hf = Generator::Fbm.generate(64, 64, 17);
    let address = Address::Repeat;
    let map = QuadricMap::build(&hf, address);
    let cone_step = |gap: f64, lambda: f64, s: f64, t: [f32; 4]| {
        gap / (1.0 + s * lambda * f64::from(t[1]) / f64::from(t[0]))
    };
    let mut rng = SplitMix64::new(18);
    for s in [0.05, 0.1, 0.2] {
        for elevation in [30.0, 60.0] {
            let (mut q_steps, mut c_steps, mut q_err, mut c_err, n) = (0u64, 0u64, 0.0, 0.0, 400);
            for _ in 0..n {
                let ray = ray_at(
                    unit(&mut rng),
                    unit(&mut rng),
                    elevation,
                    range(&mut rng, 0.0, 360.0),
                );
                let exact = trace(&hf, &ray, s, SurfaceModel::Bilinear, address).z;
                let tracer = Tracer::new(&hf, &map, &ray, s, address);
                q_steps += u64::from(tracer.run(100_000, 0, quadric_step, &mut |_| {}).steps);
                c_steps += u64::from(tracer.run(100_000, 0, cone_step, &mut |_| {}).steps);
                q_err += texels_along(
                    &hf,
                    &ray,
                    exact - tracer.run(8, 0, quadric_step, &mut |_| {}).z,
                );
                c_err += texels_along(
                    &hf,
                    &ray,
                    exact - tracer.run(8, 0, cone_step, &mut |_| {}).z,
                );
            }
            let n = f64::from(n);
            println!(
                "fbm 64x64 s={s} elev {elevation}: mean steps quadric {:.1} cone {:.1}; error after 8 steps (texels) quadric {:.2} cone {:.2}",
                q_steps as f64 / n,
                c_steps as f64 / n,
                q_err / n,
                c_err / n
            );
        }
    }
}

/// Release build times: `cargo test --release -- --ignored --nocapture quadric_build_times`
/// (4096^2 only with `QUADRIC_4096=1`).
#[test]
#[ignore]
fn quadric_build_times() {
    let mut sizes = vec![256, 1024];
    if std::env::var_os("QUADRIC_4096").is_some() {
        sizes.push(4096);
    }
    for n in sizes {
        let hf = Generator::Fbm.generate(n, n, 19);
        for address in ADDRESSES {
            let start = Instant::now();
            let map = QuadricMap::build(&hf, address);
            let secs = start.elapsed().as_secs_f64();
            println!(
                "fbm {n}x{n} {address}: {secs:.2} s on {} threads ({:.2} us per texel-thread)",
                thread::available_parallelism().map_or(1, |n| n.get()),
                secs * 1e6 * thread::available_parallelism().map_or(1, |n| n.get()) as f64
                    / f64::from(n * n)
            );
            assert_eq!(map.texels.len(), (n * n) as usize);
        }
    }
}
