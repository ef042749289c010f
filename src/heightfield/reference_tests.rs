//! Tests of the reference tracer: closed-form cases, and an independent brute-force march on random fields.

use super::*;
use crate::heightfield::test_support::{field, Rng};

const MODELS: [SurfaceModel; 2] = [SurfaceModel::Bilinear, SurfaceModel::Nearest];
const ADDRESSES: [Address; 2] = [Address::Repeat, Address::Clamp];

/// Heights on `levels + 1` steps from 0 to 1: plateaus, exact ties and the top plane itself, as 8-bit maps have.
fn quantized_field(rng: &mut Rng, w: u32, h: u32, levels: u64) -> Heightfield {
    let data = (0..w * h)
        .map(|_| (rng.below(levels + 1) as f64 / levels as f64) as f32)
        .collect();
    Heightfield::new(w, h, data).unwrap()
}

fn random_field(rng: &mut Rng, w: u32, h: u32) -> Heightfield {
    let data = (0..w * h).map(|_| rng.unit() as f32).collect();
    Heightfield::new(w, h, data).unwrap()
}

/// A bench-style ray: elevation and azimuth in degrees.
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

fn random_ray(rng: &mut Rng, min_elevation: f64, uv: (f64, f64)) -> RefRay {
    let (u0, v0) = (rng.range(uv.0, uv.1), rng.range(uv.0, uv.1));
    ray_at(
        u0,
        v0,
        rng.range(min_elevation, 90.0),
        rng.range(0.0, 360.0),
    )
}

/// f(z) = z - d(p(z)) through the public surface: >= 0 means at or under the surface.
fn gap(hf: &Heightfield, ray: &RefRay, z: f64, s: f64, m: SurfaceModel, a: Address) -> f64 {
    let (u, v) = (ray.u0 + z * ray.dx / ray.dz, ray.v0 + z * ray.dy / ray.dz);
    z - surface_depth(hf, u, v, s, m, a)
}

/// Depth step of the brute-force march: 1e-3 texel of uv travel (or 1e-3 s for steep rays).
fn march_step(hf: &Heightfield, ray: &RefRay, s: f64) -> f64 {
    let speed = ray.dx.hypot(ray.dy) / ray.dz;
    let texel = 1.0 / f64::from(hf.width().max(hf.height()));
    let step = 1e-3 * s;
    if speed > 0.0 {
        step.min(1e-3 * texel / speed)
    } else {
        step
    }
}

/// Independent ground truth for the ground truth: march z in fine steps through `surface_depth` and
/// bisect the first sign change of f. It can only miss a hit region narrower than one step.
fn brute_force(hf: &Heightfield, ray: &RefRay, s: f64, m: SurfaceModel, a: Address) -> f64 {
    let f = |z: f64| gap(hf, ray, z, s, m, a);
    if f(0.0) >= 0.0 {
        return 0.0;
    }
    let step = march_step(hf, ray, s);
    let n = (s / step).ceil() as u64;
    let mut prev = 0.0;
    for k in 1..=n {
        let z = (k as f64 * step).min(s);
        if f(z) >= 0.0 {
            let (mut lo, mut hi) = (prev, z);
            while hi - lo > 1e-15 * s.max(1e-300) {
                let mid = 0.5 * (lo + hi);
                if mid <= lo || mid >= hi {
                    break;
                }
                if f(mid) >= 0.0 {
                    hi = mid
                } else {
                    lo = mid
                }
            }
            return hi;
        }
        prev = z;
    }
    s
}

/// A depth difference in texels: the larger of the uv distance it moves the hit and the depth itself.
fn texels(hf: &Heightfield, ray: &RefRay, dz: f64) -> f64 {
    let (w, h) = (f64::from(hf.width()), f64::from(hf.height()));
    let uv = (dz * ray.dx / ray.dz * w).hypot(dz * ray.dy / ray.dz * h);
    uv.max(dz.abs() * w)
}

#[test]
fn address_parses_and_prints() {
    for a in ADDRESSES {
        assert_eq!(a.to_string().parse::<Address>(), Ok(a));
    }
    assert_eq!("clamp".parse::<Address>(), Ok(Address::Clamp));
    assert!("mirror".parse::<Address>().is_err());
}

#[test]
fn flat_field_hits_at_its_depth_from_any_direction() {
    let mut rng = Rng::new(1);
    let hf = field(4, 3, |_, _| 0.375);
    for _ in 0..500 {
        let ray = random_ray(&mut rng, 2.0, (-3.0, 4.0));
        let s = rng.range(0.01, 1.0);
        for (m, a) in MODELS.into_iter().flat_map(|m| ADDRESSES.map(|a| (m, a))) {
            let hit = trace(&hf, &ray, s, m, a);
            assert!(
                (hit.z - s * 0.625).abs() < 1e-13,
                "{m:?} {a:?} {ray:?}: {hit:?}"
            );
            assert!((hit.u - (ray.u0 + hit.z * ray.dx / ray.dz)).abs() < 1e-12);
        }
    }
}

#[test]
fn rays_entering_at_the_top_plane_hit_at_zero() {
    let mut rng = Rng::new(13);
    let hf = field(4, 4, |i, _| if i == 0 { 0.0 } else { 1.0 });
    for _ in 0..200 {
        // Between the centres of columns 1..3 the bilinear surface is the top plane.
        let ray = random_ray(&mut rng, 5.0, (1.5 / 4.0, 3.5 / 4.0));
        for (m, a) in MODELS.into_iter().flat_map(|m| ADDRESSES.map(|a| (m, a))) {
            let hit = trace(&hf, &ray, 0.3, m, a);
            assert_eq!((hit.z, hit.cells_visited), (0.0, 1), "{m:?} {a:?} {ray:?}");
        }
    }
}

#[test]
fn one_by_one_map_is_flat() {
    let hf = field(1, 1, |_, _| 0.625);
    let mut rng = Rng::new(2);
    for _ in 0..200 {
        let ray = random_ray(&mut rng, 5.0, (-2.0, 3.0));
        for (m, a) in MODELS.into_iter().flat_map(|m| ADDRESSES.map(|a| (m, a))) {
            let hit = trace(&hf, &ray, 0.2, m, a);
            assert!((hit.z - 0.2 * 0.375).abs() < 1e-14, "{m:?} {a:?}: {hit:?}");
        }
    }
}

#[test]
fn bilinear_ramp_matches_closed_form() {
    // h = i/8 at texel centres, so between the first and last centre h(u) = u - 1/16 exactly.
    let hf = field(8, 2, |i, _| i as f32 / 8.0);
    let s = 0.25;
    for (u0, v0, dx, dy, dz) in [
        (0.5, 0.3, 0.6, 0.0, 0.8),
        (0.5, 0.9, -0.6, 0.3, 0.8),
        (0.3, 0.1, 0.2, -0.5, 0.5),
    ] {
        let ray = RefRay { u0, v0, dx, dy, dz };
        let t = dx / dz;
        // z = s (1 - (u0 + z t - 1/16))
        let z = s * (1.0 + 1.0 / 16.0 - u0) / (1.0 + s * t);
        let u = u0 + z * t;
        assert!(
            (1.0 / 16.0..15.0 / 16.0).contains(&u),
            "test ray leaves the linear region"
        );
        for a in ADDRESSES {
            let hit = trace(&hf, &ray, s, SurfaceModel::Bilinear, a);
            assert!(
                (hit.z - z).abs() < 1e-14,
                "{a:?} {ray:?}: {hit:?}, expected z = {z}"
            );
            assert!((hit.u - u).abs() < 1e-14);
        }
    }
}

#[test]
fn cliff_face_is_hit_where_the_ray_reaches_it() {
    // Low (h = 0.2) for i < 4, high (h = 0.8) from i = 4: a cliff at u = 0.5; depths 0.4 and 0.1.
    let hf = field(8, 4, |i, _| if i < 4 { 0.2 } else { 0.8 } as f32);
    let s = 0.5;
    let (low, high) = (f64::from(0.2f32), f64::from(0.8f32));
    let ray = RefRay {
        u0: 0.3,
        v0: 0.4,
        dx: 1.0,
        dy: 0.25,
        dz: 1.0,
    };
    // Nearest: the ray reaches u = 0.5 at z = 0.2, between the two depths: the face.
    let hit = trace(&hf, &ray, s, SurfaceModel::Nearest, Address::Clamp);
    assert!(
        (hit.z - 0.2).abs() < 1e-15 && (hit.u - 0.5).abs() < 1e-15,
        "{hit:?}"
    );
    // Bilinear: between the centres at u = 3.5/8 and 4.5/8 the cliff is a ramp.
    // z = s (1 - (low + (high - low) (8 (u0 + z) - 3.5)))
    let k = high - low;
    let z = s * (1.0 - low - k * (8.0 * 0.3 - 3.5)) / (1.0 + s * k * 8.0);
    assert!((3.5 / 8.0..4.5 / 8.0).contains(&(0.3 + z)));
    let hit = trace(&hf, &ray, s, SurfaceModel::Bilinear, Address::Clamp);
    assert!((hit.z - z).abs() < 1e-14, "{hit:?}, expected {z}");
    // From the high side going down-slope, nearest lands on the top at its depth.
    let ray = RefRay {
        u0: 0.7,
        v0: 0.4,
        dx: -1.0,
        dy: 0.0,
        dz: 1.0,
    };
    let hit = trace(&hf, &ray, s, SurfaceModel::Nearest, Address::Clamp);
    assert!((hit.z - s * (1.0 - high)).abs() < 1e-15, "{hit:?}");
}

#[test]
fn nearest_spike_is_hit_on_its_side_its_top_or_passed_over() {
    // Flat floor (h = 0, depth 0.4) with texel (5, 5) raised to h = 0.5 (depth 0.2).
    let hf = field(8, 8, |i, j| if (i, j) == (5, 5) { 0.5 } else { 0.0 });
    let s = 0.4;
    for a in ADDRESSES {
        let at = |dx: f64| {
            let ray = RefRay {
                u0: 0.5,
                v0: 5.5 / 8.0,
                dx,
                dy: 0.0,
                dz: 1.0,
            };
            trace(&hf, &ray, s, SurfaceModel::Nearest, a)
        };
        // Reaches u = 5/8 at z = 0.25, already below the top: the side.
        let side = at(0.5);
        assert!(
            (side.z - 0.25).abs() < 1e-15 && (side.u - 0.625).abs() < 1e-15,
            "{side:?}"
        );
        // Reaches the spike at z = 0.125 and its top depth at u = 0.7 < 0.75: the top.
        let top = at(1.0);
        assert!(
            (top.z - 0.2).abs() < 1e-15 && (top.u - 0.7).abs() < 1e-15,
            "{top:?}"
        );
        // Leaves the spike at z = 0.125 above its top: the floor beyond.
        let floor = at(2.0);
        assert!((floor.z - 0.4).abs() < 1e-15, "{floor:?}");
    }
}

#[test]
fn vertical_rays_hit_the_surface_below_them_in_one_cell() {
    let mut rng = Rng::new(3);
    for (w, h) in [(1, 1), (8, 8), (5, 3)] {
        let hf = random_field(&mut rng, w, h);
        for k in 0..300 {
            // Some entries exactly on texel edges and centres.
            let (u0, v0) = if k % 3 == 0 {
                (
                    rng.below(3 * u64::from(w)) as f64 / f64::from(2 * w) - 0.5,
                    rng.below(8) as f64 / 4.0,
                )
            } else {
                (rng.range(-2.0, 3.0), rng.range(-2.0, 3.0))
            };
            let ray = RefRay {
                u0,
                v0,
                dx: 0.0,
                dy: 0.0,
                dz: rng.range(0.1, 2.0),
            };
            for (m, a) in MODELS.into_iter().flat_map(|m| ADDRESSES.map(|a| (m, a))) {
                let hit = trace(&hf, &ray, 0.3, m, a);
                let d = surface_depth(&hf, u0, v0, 0.3, m, a);
                assert!(
                    (hit.z - d).abs() < 1e-15,
                    "{m:?} {a:?} {ray:?}: {hit:?} vs {d}"
                );
                assert_eq!((hit.u, hit.v, hit.cells_visited), (u0, v0, 1));
            }
        }
    }
}

#[test]
fn zero_depth_scale_hits_at_the_top() {
    let mut rng = Rng::new(4);
    let hf = random_field(&mut rng, 6, 5);
    for _ in 0..300 {
        let ray = random_ray(&mut rng, 1.0, (-2.0, 3.0));
        for (m, a) in MODELS.into_iter().flat_map(|m| ADDRESSES.map(|a| (m, a))) {
            let hit = trace(&hf, &ray, 0.0, m, a);
            assert_eq!((hit.z, hit.u, hit.v), (0.0, ray.u0, ray.v0));
        }
    }
}

/// Compares the tracer with the brute force over `rays` random rays per model and address; returns how
/// many rays the march straddled (see below).
fn compare_with_brute_force(hf: &Heightfield, rng: &mut Rng, rays: usize, uv: (f64, f64)) -> usize {
    let mut straddled = 0;
    for (m, a) in MODELS.into_iter().flat_map(|m| ADDRESSES.map(|a| (m, a))) {
        for _ in 0..rays {
            let ray = random_ray(rng, 12.0, uv);
            let s = rng.range(0.02, 0.3);
            let hit = trace(hf, &ray, s, m, a);
            let brute = brute_force(hf, &ray, s, m, a);
            let err = texels(hf, &ray, hit.z - brute);
            if err < 1e-6 {
                continue;
            }
            // The only tolerated disagreement: the march stepped over a hit region narrower than its step
            // (a near-tangent touch or a clipped corner), so the brute force is later. Then the tracer's hit
            // must be a real contact (f >= 0 there or just after it, a cliff being half-open) lying strictly
            // between two march samples that both see the ray above the surface.
            let f = |z: f64| gap(hf, &ray, z, s, m, a);
            let step = march_step(hf, &ray, s);
            let before = (hit.z / step).floor() * step;
            let real = f(hit.z).max(f(hit.z + 1e-12 * s)) >= -1e-12;
            let between = f(before) < 0.0 && f((before + step).min(s)) < 0.0;
            assert!(
                brute > hit.z && real && between,
                "{m:?} {a:?} s={s} {ray:?}: traced {hit:?}, brute force z = {brute} ({err} texels)"
            );
            straddled += 1;
        }
    }
    straddled
}

#[test]
fn random_fields_match_brute_force() {
    let mut rng = Rng::new(5);
    let (mut rays, mut straddled) = (0, 0);
    for (w, h) in [(8, 8), (5, 3), (16, 16), (1, 4), (3, 1)] {
        let hf = random_field(&mut rng, w, h);
        straddled += compare_with_brute_force(&hf, &mut rng, 100, (0.0, 1.0));
        straddled += compare_with_brute_force(&hf, &mut rng, 50, (-3.0, 4.0));
        rays += 4 * 150;
    }
    for (w, h) in [(8, 8), (7, 5)] {
        let hf = quantized_field(&mut rng, w, h, 4);
        straddled += compare_with_brute_force(&hf, &mut rng, 100, (-1.0, 2.0));
        rays += 4 * 100;
    }
    assert!(
        straddled * 200 < rays,
        "{straddled} of {rays} rays straddled: too many to be tangent touches"
    );
}

#[test]
fn rays_along_cell_edges_match_brute_force() {
    let mut rng = Rng::new(6);
    let hf = random_field(&mut rng, 8, 8);
    let s = 0.6;
    for (m, a) in MODELS.into_iter().flat_map(|m| ADDRESSES.map(|a| (m, a))) {
        // Along texel edges, texel centre lines (the bilinear cell edges), and diagonals through corners.
        for k in 0..=16 {
            let c = k as f64 / 16.0;
            for (u0, v0, azimuth) in [
                (0.1, c, 0.0),
                (c, 0.9, 270.0),
                (c, c, 45.0),
                (c, 1.0 - c, 135.0),
            ] {
                // Exact directions, so the diagonals really pass through lattice corners.
                let (dx, dy) = match azimuth {
                    0.0 => (1.0, 0.0),
                    270.0 => (0.0, -1.0),
                    45.0 => (1.0, 1.0),
                    _ => (-1.0, 1.0),
                };
                let ray = RefRay {
                    u0,
                    v0,
                    dx,
                    dy,
                    dz: 1.0,
                };
                let hit = trace(&hf, &ray, s, m, a);
                let brute = brute_force(&hf, &ray, s, m, a);
                let err = texels(&hf, &ray, hit.z - brute);
                assert!(
                    err < 1e-6,
                    "{m:?} {a:?} {ray:?}: {hit:?} vs brute {brute} ({err} texels)"
                );
            }
        }
    }
}

#[test]
fn bilinear_hits_are_roots_of_the_public_surface() {
    let mut rng = Rng::new(7);
    let hf = random_field(&mut rng, 9, 7);
    for a in ADDRESSES {
        for _ in 0..2000 {
            let ray = random_ray(&mut rng, 1.0, (-2.0, 3.0));
            let s = rng.range(0.01, 0.5);
            let hit = trace(&hf, &ray, s, SurfaceModel::Bilinear, a);
            let f = gap(&hf, &ray, hit.z, s, SurfaceModel::Bilinear, a);
            assert!(
                hit.z == 0.0 && f >= 0.0 || f.abs() < 1e-13,
                "{a:?} {ray:?}: {hit:?}, f = {f}"
            );
        }
    }
}

#[test]
fn repeat_is_periodic_in_the_entry_point() {
    let mut rng = Rng::new(8);
    let hf = random_field(&mut rng, 6, 4);
    for m in MODELS {
        for _ in 0..300 {
            let ray = random_ray(&mut rng, 10.0, (0.0, 1.0));
            let far = RefRay {
                u0: ray.u0 + 7.0,
                v0: ray.v0 - 3.0,
                ..ray
            };
            let (near, far_hit) = (
                trace(&hf, &ray, 0.2, m, Address::Repeat),
                trace(&hf, &far, 0.2, m, Address::Repeat),
            );
            assert!(
                (near.z - far_hit.z).abs() < 1e-12,
                "{m:?} {ray:?}: {near:?} vs {far_hit:?}"
            );
            assert!(
                (far_hit.u - near.u - 7.0).abs() < 1e-12
                    && (far_hit.v - near.v + 3.0).abs() < 1e-12
            );
        }
    }
}

#[test]
fn grazing_rays_stay_finite_and_clamp_walks_stay_short() {
    let mut rng = Rng::new(9);
    let hf = random_field(&mut rng, 8, 8);
    for k in 0..20 {
        let ray = ray_at(rng.unit(), rng.unit(), 0.001, rng.range(0.0, 360.0));
        let s = 0.1;
        let hit = trace(&hf, &ray, s, SurfaceModel::Bilinear, Address::Repeat);
        let f = gap(&hf, &ray, hit.z, s, SurfaceModel::Bilinear, Address::Repeat);
        assert!(
            hit.z > 0.0 && hit.z <= s && f.abs() < 1e-9,
            "{k}: {ray:?} {hit:?} f = {f}"
        );
        assert!(hit.cells_visited < MAX_CELLS);
        // Clamp: beyond the map each axis is one cell, however far the ray travels.
        for m in MODELS {
            let hit = trace(&hf, &ray, s, m, Address::Clamp);
            assert!(hit.z.is_finite() && (0.0..=s).contains(&hit.z));
            assert!(hit.cells_visited <= 8 + 8 + 4, "{m:?} {ray:?}: {hit:?}");
            let f = gap(&hf, &ray, hit.z, s, m, Address::Clamp);
            assert!(
                m == SurfaceModel::Nearest || f.abs() < 1e-9,
                "{ray:?}: {hit:?} f = {f}"
            );
        }
    }
}

#[test]
fn clamp_outside_the_map_uses_the_border_values() {
    // Entering far left of the map going +u: the surface there is column 0 extended.
    let hf = field(4, 4, |i, j| (0.1 + 0.2 * i as f64 + 0.05 * j as f64) as f32);
    let ray = RefRay {
        u0: -5.0,
        v0: 0.3,
        dx: 0.0,
        dy: 0.0,
        dz: 1.0,
    };
    for m in MODELS {
        let hit = trace(&hf, &ray, 0.5, m, Address::Clamp);
        assert!((hit.z - surface_depth(&hf, 0.0, 0.3, 0.5, m, Address::Clamp)).abs() < 1e-15);
    }
    let mut rng = Rng::new(10);
    let mut straddled = compare_with_brute_force(&hf, &mut rng, 100, (-6.0, 7.0));
    straddled += compare_with_brute_force(&hf, &mut rng, 100, (-0.3, 1.3));
    assert!(straddled < 4, "{straddled} straddled rays");
}

#[test]
fn the_cell_cap_falls_back_to_the_bottom_plane() {
    let mut rng = Rng::new(11);
    let hf = random_field(&mut rng, 8, 8);
    let ray = ray_at(0.3, 0.6, 0.01, 20.0);
    let hit = trace_capped(&hf, &ray, 0.1, SurfaceModel::Bilinear, Address::Repeat, 10);
    assert_eq!((hit.z, hit.cells_visited), (0.1, 10));
    assert!((hit.u - (0.3 + 0.1 * ray.dx / ray.dz)).abs() < 1e-9);
}

#[test]
fn random_rays_never_produce_nan_or_leave_the_slab() {
    let mut rng = Rng::new(12);
    for _ in 0..200 {
        let (w, h) = (1 + rng.below(9) as u32, 1 + rng.below(9) as u32);
        let hf = random_field(&mut rng, w, h);
        for _ in 0..100 {
            let s = if rng.below(10) == 0 {
                0.0
            } else {
                rng.range(0.0, 1.0)
            };
            let elevation = [90.0, 45.0, 0.5, rng.range(0.5, 90.0)][rng.below(4) as usize];
            let azimuth = [0.0, 90.0, 180.0, 270.0, rng.range(0.0, 360.0)][rng.below(5) as usize];
            let (u0, v0) = if rng.below(2) == 0 {
                (
                    rng.below(41) as f64 / 4.0 - 5.0,
                    rng.below(41) as f64 / 8.0 - 2.0,
                )
            } else {
                (rng.range(-10.0, 10.0), rng.range(-10.0, 10.0))
            };
            let ray = ray_at(u0, v0, elevation, azimuth);
            for (m, a) in MODELS.into_iter().flat_map(|m| ADDRESSES.map(|a| (m, a))) {
                let hit = trace(&hf, &ray, s, m, a);
                assert!(hit.u.is_finite() && hit.v.is_finite(), "{ray:?}: {hit:?}");
                assert!(
                    (0.0..=s).contains(&hit.z),
                    "{m:?} {a:?} s={s} {ray:?}: {hit:?}"
                );
                // Under the surface at the hit, or (a nearest cliff face being half-open) a hair ahead.
                // Per axis, since a component of 1e-16 moves u by less than its rounding.
                let hair = |d: f64| if d == 0.0 { 0.0 } else { 1e-9f64.copysign(d) };
                let (nu, nv) = (hit.u + hair(ray.dx), hit.v + hair(ray.dy));
                let ahead = hit.z - surface_depth(&hf, nu, nv, s, m, a);
                let f = gap(&hf, &ray, hit.z, s, m, a).max(ahead);
                assert!(
                    f >= -1e-12 * s.max(1.0),
                    "{m:?} {a:?} {w}x{h} s={s} {ray:?}: {hit:?} f = {f}"
                );
            }
        }
    }
}
