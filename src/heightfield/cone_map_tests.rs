use super::search::{self, Field, ReachPyramid, REACH_CAP_UV};
use super::sectors::{direction_mask, SECTORS};
use super::*;
use crate::heightfield::reference::{trace, SurfaceModel};
use crate::heightfield::rng::SplitMix64;
use crate::heightfield::Generator;

const CAP: f64 = CONE_RATIO_MAX as f64;

/// Brute force of [`search::conservative`]: every texel of every ring the ring bound does not exclude (the
/// ring bound is a plain distance argument; only the pyramid pruning is under test).
fn brute_conservative(f: &Field<'_>, i: u32, j: u32) -> f64 {
    let hp = f64::from(f.hf.get(i, j));
    let (pu, pv) = f.centre(i, j);
    let rise = f64::from(f.top) - hp;
    let mut best = CAP;
    for r in 0.. {
        let Some((gap, regions)) = f.ring(r, false) else {
            break;
        };
        if rise <= 0.0 || gap / rise >= best {
            break;
        }
        for p in &regions {
            let (w, h) = p.tree.size(0);
            for (qi, qj) in (0..h).flat_map(|qj| (0..w).map(move |qi| (qi, qj))) {
                let hq = f64::from(p.tree.max_at(0, qi, qj));
                if hq > hp {
                    best = best.min(p.rect(0, qi, qj).dist_point(pu, pv) / (hq - hp));
                }
            }
        }
    }
    best
}

/// Brute force of [`search::reach`].
fn brute_reach(f: &Field<'_>, i: u32, j: u32) -> [u16; SECTORS] {
    let hq = f.hf.get(i, j);
    let q = f.texel_rect(i, j);
    let mut e = [f.reach_cap(); SECTORS];
    for r in 0.. {
        let Some((gap, regions)) = f.ring(r, true) else {
            break;
        };
        if gap >= e.iter().fold(0.0f64, |m, &x| m.max(x)) {
            break;
        }
        for p in &regions {
            let (w, h) = p.tree.size(0);
            for (yi, yj) in (0..h).flat_map(|yj| (0..w).map(move |yi| (yi, yj))) {
                if p.tree.max_at(0, yi, yj) >= hq {
                    continue;
                }
                let rect = p.rect(0, yi, yj);
                let d = q.dist_rect(&rect);
                let mask = direction_mask(&q, &rect, true);
                for (k, ek) in e.iter_mut().enumerate() {
                    if mask & (1 << k) != 0 {
                        *ek = ek.min(d);
                    }
                }
            }
        }
    }
    e.map(|x| (x / f.reach_unit()).floor().min(65535.0) as u16)
}

/// Brute force of [`search::relaxed`] given the reach table.
fn brute_relaxed(f: &Field<'_>, reach: &ReachPyramid, i: u32, j: u32, floor: f64) -> f64 {
    let hp = f64::from(f.hf.get(i, j));
    let (pu, pv) = f.centre(i, j);
    let prect = f.texel_rect(i, j);
    let rise = f64::from(f.top) - hp;
    let mut best = CAP;
    for r in 0.. {
        let Some((gap, regions)) = f.ring(r, true) else {
            break;
        };
        if rise <= 0.0 || gap / rise >= best {
            break;
        }
        for p in &regions {
            let (w, h) = p.tree.size(0);
            for (qi, qj) in (0..h).flat_map(|qj| (0..w).map(move |qi| (qi, qj))) {
                let hq = f64::from(p.tree.max_at(0, qi, qj));
                if hq <= hp {
                    continue;
                }
                let rect = p.rect(0, qi, qj);
                let extra = if p.real {
                    reach.min_over(0, qi, qj, direction_mask(&prect, &rect, true))
                } else {
                    0.0
                };
                best = best.min((rect.dist_point(pu, pv) + extra) / (hq - hp));
            }
        }
    }
    best.max(floor)
}

fn small_fields() -> Vec<Heightfield> {
    vec![
        Generator::Noise.generate(9, 7, 1),
        Generator::Fbm.generate(16, 16, 2),
        Generator::Fbm.generate(33, 17, 8),
        Generator::Spikes.generate(13, 5, 3),
        Generator::Step.generate(8, 6, 4),
        Generator::Bricks.generate(12, 12, 5),
        Generator::Noise.generate(1, 6, 6),
        Heightfield::new(3, 1, vec![0.0, 1.0, 0.0]).expect("valid"),
    ]
}

const ADDRESSES: [Address; 2] = [Address::Repeat, Address::Clamp];

#[test]
fn fast_builders_equal_brute_force_bit_for_bit() {
    for hf in small_fields() {
        for address in ADDRESSES {
            let f = Field::new(&hf, address);
            let (w, h) = (hf.width(), hf.height());
            let texels: Vec<(u32, u32)> =
                (0..h).flat_map(|j| (0..w).map(move |i| (i, j))).collect();
            let cons: Vec<f64> = texels
                .iter()
                .map(|&(i, j)| search::conservative(&f, i, j, CAP))
                .collect();
            let reach: Vec<u16> = texels
                .iter()
                .flat_map(|&(i, j)| search::reach(&f, i, j))
                .collect();
            for (n, &(i, j)) in texels.iter().enumerate() {
                let at = format!("{w}x{h} {address} texel ({i}, {j})");
                assert_eq!(
                    cons[n].to_bits(),
                    brute_conservative(&f, i, j).to_bits(),
                    "{at}"
                );
                assert_eq!(
                    reach[n * SECTORS..(n + 1) * SECTORS],
                    brute_reach(&f, i, j),
                    "{at}"
                );
            }
            let pyramid = ReachPyramid::new(&f.main, reach, f.reach_unit());
            for (n, &(i, j)) in texels.iter().enumerate() {
                let fast = search::relaxed(&f, &pyramid, (i, j), cons[n], CAP);
                let slow = brute_relaxed(&f, &pyramid, i, j, cons[n]);
                assert_eq!(
                    fast.to_bits(),
                    slow.to_bits(),
                    "{w}x{h} {address} ({i}, {j})"
                );
            }
        }
    }
}

#[test]
fn hand_computed_ratios() {
    // One bump of height 1 among zeros, W = 3: the nearest higher box is half a texel (1/6 uv) away.
    let hf = Heightfield::new(3, 1, vec![0.0, 1.0, 0.0]).expect("valid");
    for address in ADDRESSES {
        let map = ConeMap::build_box(&hf, ConeKind::Conservative, address);
        assert_eq!(
            map.ratio,
            vec![round_down(1.0 / 6.0), CONE_RATIO_MAX, round_down(1.0 / 6.0)]
        );
        // Every neighbour of the bump is lower, so no ray can stay inside it: relaxed equals conservative.
        assert_eq!(
            ConeMap::build_box(&hf, ConeKind::Relaxed, address).ratio,
            map.ratio
        );
        // Over the bilinear bound the bump's neighbours rise to 0.5 at their shared edges (under
        // clamp the outer halves stay at 0, but the inner half still reaches 0.5): the nearest
        // higher box is the same, half as much higher.
        let bound = ConeMap::build(&hf, ConeKind::Conservative, address);
        assert_eq!(bound.surface, vec![0.5, 1.0, 0.5]);
        assert_eq!(
            bound.ratio,
            vec![round_down(1.0 / 3.0), CONE_RATIO_MAX, round_down(1.0 / 3.0)]
        );
    }
    // A plateau 0.5 high and six texels wide between two zero texels, tiled: from texel 0 the nearest higher
    // box is 1/16 uv away (ratio 1/8), but a ray entering the plateau cannot leave it before the far edge.
    let hf = Heightfield::new(8, 1, vec![0.0, 0.5, 0.5, 0.5, 0.5, 0.5, 0.5, 0.0]).expect("valid");
    let f = Field::new(&hf, Address::Repeat);
    let reach = search::reach(&f, 1, 0);
    for (k, &r) in reach.iter().enumerate() {
        // Rightward sectors see texel 7 at 5/8 uv, capped at REACH_CAP_UV; the rest touch texel 0.
        let expect = if !(4..12).contains(&k) {
            REACH_CAP_UV.min(0.625)
        } else {
            0.0
        };
        assert!(
            (f64::from(r) * f.reach_unit() - expect).abs() < 1e-4,
            "sector {k}: {r}"
        );
    }
    let cons = ConeMap::build_box(&hf, ConeKind::Conservative, Address::Repeat);
    let relaxed = ConeMap::build_box(&hf, ConeKind::Relaxed, Address::Repeat);
    assert_eq!(cons.get(0, 0), 0.125);
    // Texel 1 limits it at (1/16 + reach) / 0.5 (the other plateau texels give at least as much as long as
    // the reach cap is below 5/8), five times the conservative ratio with a cap of 1/4.
    let expect = (0.0625 + REACH_CAP_UV.min(0.625)) / 0.5;
    assert!(
        (f64::from(relaxed.get(0, 0)) - expect).abs() < 1e-4,
        "{}",
        relaxed.get(0, 0)
    );
}

#[test]
fn maps_are_finite_bounded_and_relaxed_is_wider() {
    for (generator, w, h) in [
        (Generator::Fbm, 32, 32),
        (Generator::Noise, 17, 9),
        (Generator::Flat0, 4, 4),
        (Generator::Bricks, 32, 16),
    ] {
        let hf = generator.generate(w, h, 7);
        for address in ADDRESSES {
            let cons = ConeMap::build(&hf, ConeKind::Conservative, address);
            let relaxed = ConeMap::build(&hf, ConeKind::Relaxed, address);
            assert_eq!(cons.surface, relaxed.surface);
            let top = cons.surface.iter().fold(0.0f32, |m, &x| m.max(x));
            assert_eq!(
                (cons.width, cons.height, cons.ratio.len()),
                (w, h, (w * h) as usize)
            );
            for (n, (&c, &r)) in cons.ratio.iter().zip(&relaxed.ratio).enumerate() {
                assert!(c.is_finite() && (0.0..=CONE_RATIO_MAX).contains(&c), "{c}");
                assert!(
                    r >= c && r <= CONE_RATIO_MAX,
                    "{generator} texel {n}: {r} < {c}"
                );
                if cons.surface[n] == top {
                    assert_eq!(c, CONE_RATIO_MAX);
                }
            }
        }
    }
}

#[test]
fn bilinear_bound_is_the_highest_bilinear_point_over_each_texel() {
    // Sampled on a fine grid that includes every box's centre, edge midpoints and corners, the
    // bilinear surface never rises above the bound, and reaches it in every box.
    const SUB: u32 = 8;
    let inside = |k: u32| (f64::from(k) / f64::from(SUB)).min(1.0 - 1e-9);
    for hf in small_fields() {
        for address in ADDRESSES {
            let bound = bilinear_box_bound(&hf, address);
            let (w, h) = (hf.width(), hf.height());
            for j in 0..h {
                for i in 0..w {
                    let mut top = f64::MIN;
                    for (a, b) in (0..=SUB).flat_map(|b| (0..=SUB).map(move |a| (a, b))) {
                        // The far edges just inside the half-open texel.
                        let (du, dv) = (inside(a), inside(b));
                        let (u, v) = (
                            (f64::from(i) + du) / f64::from(w),
                            (f64::from(j) + dv) / f64::from(h),
                        );
                        let d = crate::heightfield::reference::surface_depth(
                            &hf,
                            u,
                            v,
                            1.0,
                            SurfaceModel::Bilinear,
                            address,
                        );
                        top = top.max(1.0 - d);
                    }
                    let b = f64::from(bound.get(i, j));
                    let at = format!("{w}x{h} {address} ({i}, {j})");
                    assert!(top <= b + 1e-12, "{at}: surface {top} above bound {b}");
                    assert!(
                        b - top < 1e-6,
                        "{at}: bound {b} above the surface's top {top}"
                    );
                }
            }
        }
    }
}

/// Elevation in [5, 90] degrees, any azimuth, entry anywhere in the first tile.
fn random_ray(rng: &mut SplitMix64) -> RefRay {
    let e = (5.0 + 85.0 * f64::from(rng.next_f32())).to_radians();
    let a = (360.0 * f64::from(rng.next_f32())).to_radians();
    RefRay {
        u0: f64::from(rng.next_f32()),
        v0: f64::from(rng.next_f32()),
        dx: e.cos() * a.cos(),
        dy: e.cos() * a.sin(),
        dz: e.sin(),
    }
}

fn trace_fields() -> Vec<Heightfield> {
    let mut out = Vec::new();
    for (w, h) in [(16, 16), (33, 17), (64, 64)] {
        for g in [
            Generator::Noise,
            Generator::Fbm,
            Generator::Spikes,
            Generator::Step,
        ] {
            out.push(g.generate(w, h, u64::from(w * 31 + h)));
        }
    }
    out
}

/// The box surface a map's cones are exact for, as a height field.
fn bound_field(map: &ConeMap) -> Heightfield {
    Heightfield::new(map.width, map.height, map.surface.clone()).expect("bound heights are valid")
}

/// Every depth a walk fetches at, and its result.
fn walk(
    hf: &Heightfield,
    map: &ConeMap,
    ray: &RefRay,
    s: f64,
    a: Address,
    steps: u32,
) -> (Vec<f64>, ConeTrace) {
    let mut seen = Vec::new();
    let result = Walk::new(hf, map, ray, s, a).run(steps, 60, |z| seen.push(z));
    (seen, result)
}

#[test]
fn conservative_steps_never_pass_the_first_hit_and_end_on_it() {
    let mut rng = SplitMix64::new(11);
    let mut capped_checked = 0;
    for hf in trace_fields() {
        for address in ADDRESSES {
            let map = ConeMap::build(&hf, ConeKind::Conservative, address);
            let bound = bound_field(&map);
            for _ in 0..120 {
                let ray = random_ray(&mut rng);
                let s = 0.02 + 0.3 * f64::from(rng.next_f32());
                // The walk is exact for the bound's boxes, which lie on or above the bilinear surface.
                let exact = trace(&bound, &ray, s, SurfaceModel::Nearest, address).z;
                let bilinear = trace(&hf, &ray, s, SurfaceModel::Bilinear, address).z;
                let (seen, result) = walk(&hf, &map, &ray, s, address, 100_000);
                let at = format!("{}x{} {address} {ray:?} s={s}", hf.width(), hf.height());
                assert!(
                    exact <= bilinear + 1e-9,
                    "{at}: bound hit {exact} after {bilinear}"
                );
                assert!(
                    seen.iter().all(|&z| z <= exact + 1e-9),
                    "{at}: passed {exact}: {seen:?}"
                );
                assert!(!result.capped, "{at}");
                assert!(
                    (result.z - exact).abs() <= 1e-9,
                    "{at}: {} vs {exact}",
                    result.z
                );
                // A tight budget stops early, still above the surface.
                let short = trace_cone_cpu(&hf, &map, &ray, s, address, 3, 0);
                if short.capped {
                    assert!(short.z <= exact + 1e-9, "{at}");
                    capped_checked += 1;
                }
            }
        }
    }
    assert!(
        capped_checked > 100,
        "too few capped rays exercised: {capped_checked}"
    );
}

/// Whether the ray leaves the nearest-model solid somewhere in `(za, zb)`: at some cell boundary it is
/// inside the cell before (its floor is above the ray) and outside the cell after.
fn leaves_solid(
    hf: &Heightfield,
    ray: &RefRay,
    s: f64,
    address: Address,
    za: f64,
    zb: f64,
) -> bool {
    let (tu, tv) = (ray.dx / ray.dz, ray.dy / ray.dz);
    let (nu, nv) = (f64::from(hf.width()), f64::from(hf.height()));
    let mut cuts = vec![za, zb];
    for (origin, slope, n) in [(ray.u0, tu, nu), (ray.v0, tv, nv)] {
        if slope != 0.0 {
            let (a, b) = ((origin + za * slope) * n, (origin + zb * slope) * n);
            for k in (a.min(b).ceil() as i64)..=(a.max(b).floor() as i64) {
                cuts.push((k as f64 / n - origin) / slope);
            }
        }
    }
    cuts.retain(|z| (za..=zb).contains(z));
    cuts.sort_by(f64::total_cmp);
    cuts.dedup();
    let floor_at = |z: f64| {
        crate::heightfield::reference::surface_depth(
            hf,
            ray.u0 + z * tu,
            ray.v0 + z * tv,
            s,
            SurfaceModel::Nearest,
            address,
        )
    };
    cuts.windows(3).any(|w| {
        let (before, after) = (floor_at(0.5 * (w[0] + w[1])), floor_at(0.5 * (w[1] + w[2])));
        before < w[1] - 1e-12 && after > w[1] + 1e-12
    })
}

#[test]
fn relaxed_steps_cross_at_most_once_and_refine_to_the_first_hit() {
    let mut rng = SplitMix64::new(12);
    for hf in trace_fields() {
        for address in ADDRESSES {
            let map = ConeMap::build(&hf, ConeKind::Relaxed, address);
            let bound = bound_field(&map);
            for _ in 0..120 {
                let ray = random_ray(&mut rng);
                let s = 0.02 + 0.3 * f64::from(rng.next_f32());
                let exact = trace(&bound, &ray, s, SurfaceModel::Nearest, address).z;
                let (seen, result) = walk(&hf, &map, &ray, s, address, 100_000);
                let at = format!("{}x{} {address} {ray:?} s={s}", hf.width(), hf.height());
                assert!(!result.capped, "{at}");
                // All fetches but the last are above the surface, so none may lie past the first hit.
                let (last, above) = seen.split_last().expect("at least one step");
                assert!(
                    above.iter().all(|&z| z <= exact + 1e-9),
                    "{at}: skipped {exact}: {seen:?}"
                );
                for pair in seen.windows(2) {
                    assert!(
                        !leaves_solid(&bound, &ray, s, address, pair[0], pair[1]),
                        "{at}: step {pair:?} exits"
                    );
                }
                assert!(*last >= exact - 1e-9, "{at}");
                assert!(
                    (result.z - exact).abs() <= 1e-9,
                    "{at}: {} vs {exact}",
                    result.z
                );
            }
        }
    }
}

#[test]
fn flat_fields_hit_in_one_or_two_steps() {
    let ray = RefRay {
        u0: 0.3,
        v0: 0.6,
        dx: 0.6,
        dy: 0.0,
        dz: 0.8,
    };
    for kind in [ConeKind::Conservative, ConeKind::Relaxed] {
        let hf = Generator::Flat1.generate(8, 8, 0);
        let map = ConeMap::build(&hf, kind, Address::Repeat);
        let t = trace_cone_cpu(&hf, &map, &ray, 0.1, Address::Repeat, 8, 8);
        assert_eq!((t.z, t.steps, t.capped), (0.0, 1, false));
        let hf = Generator::Flat0.generate(8, 8, 0);
        let map = ConeMap::build(&hf, kind, Address::Clamp);
        let t = trace_cone_cpu(&hf, &map, &ray, 0.1, Address::Clamp, 8, 8);
        assert!(
            (t.z - 0.1).abs() < 1e-12 && t.steps == 2 && !t.capped,
            "{t:?}"
        );
    }
}

#[test]
fn relaxed_needs_fewer_steps_on_a_plateau() {
    let hf = Heightfield::new(
        64,
        1,
        (0..64)
            .map(|i| if (4..60).contains(&i) { 0.8 } else { 0.0 })
            .collect(),
    )
    .expect("valid");
    // About 26 degrees: the ray meets the plateau's cliff face.
    let ray = RefRay {
        u0: 0.01,
        v0: 0.5,
        dx: 0.9,
        dy: 0.0,
        dz: 0.4359,
    };
    let mut steps = Vec::new();
    for kind in [ConeKind::Conservative, ConeKind::Relaxed] {
        let map = ConeMap::build(&hf, kind, Address::Repeat);
        let t = trace_cone_cpu(&hf, &map, &ray, 0.05, Address::Repeat, 1000, 30);
        let exact = trace(
            &bound_field(&map),
            &ray,
            0.05,
            SurfaceModel::Nearest,
            Address::Repeat,
        )
        .z;
        assert!((t.z - exact).abs() < 1e-9, "{kind:?}: {t:?} vs {exact}");
        steps.push(t.steps);
    }
    assert!(steps[1] < steps[0], "{steps:?}");
}

/// Over a 64 x 64 grid of parallel rays at `elevation` degrees: mean and max stepping iterations, and the
/// mean and max uv error in texels against the bilinear reference.
fn step_stats(hf: &Heightfield, map: &ConeMap, elevation: f64, s: f64) -> [f64; 4] {
    let (e, a) = (elevation.to_radians(), 30f64.to_radians());
    let [mut steps, mut max_steps, mut err, mut max_err] = [0.0f64; 4];
    for n in 0..64 * 64 {
        let ray = RefRay {
            u0: (f64::from(n % 64) + 0.5) / 64.0,
            v0: (f64::from(n / 64) + 0.5) / 64.0,
            dx: e.cos() * a.cos(),
            dy: e.cos() * a.sin(),
            dz: e.sin(),
        };
        let t = trace_cone_cpu(hf, map, &ray, s, Address::Repeat, 10_000, 8);
        let exact = trace(hf, &ray, s, SurfaceModel::Bilinear, Address::Repeat).z;
        let dz = t.z - exact;
        let texels = (dz * ray.dx / ray.dz * f64::from(hf.width()))
            .hypot(dz * ray.dy / ray.dz * f64::from(hf.height()));
        steps += f64::from(t.steps) / 4096.0;
        max_steps = max_steps.max(f64::from(t.steps));
        err += texels / 4096.0;
        max_err = max_err.max(texels);
    }
    [steps, max_steps, err, max_err]
}

/// CPU seconds this process has used (user + system, Linux `/proc`; 0 elsewhere): steadier than wall time
/// on a shared machine.
fn cpu_seconds() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap_or_default();
    let after_name = stat.rsplit_once(')').map_or("", |(_, rest)| rest);
    let ticks: f64 = after_name
        .split_whitespace()
        .skip(11)
        .take(2)
        .filter_map(|x| x.parse::<f64>().ok())
        .sum();
    ticks / 100.0
}

/// Build times and step counts for the report:
/// `CONE_SIZES=256,1024 cargo test --release cone_map_build_times -- --ignored --nocapture`
/// (`CONE_KINDS=conservative` or `relaxed` builds only one kind; bricks are added below 4096).
#[test]
#[ignore]
fn cone_map_build_times() {
    let sizes: Vec<u32> = std::env::var("CONE_SIZES")
        .map(|v| v.split(',').filter_map(|x| x.trim().parse().ok()).collect())
        .unwrap_or_else(|_| vec![256, 1024]);
    let kinds: Vec<ConeKind> = match std::env::var("CONE_KINDS").as_deref() {
        Ok("conservative") => vec![ConeKind::Conservative],
        Ok("relaxed") => vec![ConeKind::Relaxed],
        _ => vec![ConeKind::Conservative, ConeKind::Relaxed],
    };
    for n in sizes {
        let generators = if n < 4096 {
            vec![Generator::Fbm, Generator::Bricks]
        } else {
            vec![Generator::Fbm]
        };
        for generator in generators {
            let hf = generator.generate(n, n, 1);
            for kind in kinds.iter().copied() {
                let (start, cpu) = (std::time::Instant::now(), cpu_seconds());
                let map = ConeMap::build(&hf, kind, Address::Repeat);
                let secs = start.elapsed().as_secs_f64();
                let cpu = cpu_seconds() - cpu;
                let mean =
                    map.ratio.iter().map(|&c| f64::from(c)).sum::<f64>() / map.ratio.len() as f64;
                let steps: Vec<String> = [15.0, 30.0, 60.0]
                    .iter()
                    .map(|&e| {
                        let [m, x, err, max_err] = step_stats(&hf, &map, e, 0.1);
                        format!("{e}deg {m:.1}/{x} err {err:.3}/{max_err:.2}")
                    })
                    .collect();
                let steps = steps.join(", ");
                println!("{generator} {n}x{n} {kind:?}: build {secs:.2} s ({cpu:.1} CPU s), mean ratio {mean:.4}");
                println!("    steps and bilinear error (texels) mean/max, s = 0.1: {steps}");
            }
        }
    }
}
