//! Ray queries against the exact CPU occluders, ray by ray (`relief::render::trace_occlusion`
//! beside `SceneOccluders::any_hit`): random segments through scenes with relief casters, and
//! rays through the shared edge of two relief triangles (no crack between neighbouring prisms).

mod common;

use glam::Vec3;
use relief::heightfield::Heightfield;
use relief::render::{trace_occlusion, OcclusionRay, TracedScene};
use relief::scene::{default_heightfield, shadow_scene, ShadowScene};
use relief::shadow_reference::{Occluder, SceneOccluders};

use common::rays::Rng;

fn occluders(kind: ShadowScene) -> SceneOccluders {
    let scene = shadow_scene(kind, 25.0, 0.0);
    let heights = default_heightfield().quantized_unorm16();
    SceneOccluders::new(&scene, Some(&heights), kind.address()).expect("occluders")
}

/// The box around every relief triangle's polygon, widened by a quarter unit.
fn relief_bounds(occ: &SceneOccluders) -> (Vec3, Vec3) {
    let corners: Vec<Vec3> = occ
        .occluders()
        .filter_map(|o| match o {
            Occluder::Relief(shell) => Some(shell.corners()),
            Occluder::Triangle(_) => None,
        })
        .flatten()
        .collect();
    let lo = corners.iter().copied().reduce(Vec3::min).expect("relief");
    let hi = corners.iter().copied().reduce(Vec3::max).expect("relief");
    (lo - 0.25, hi + 0.25)
}

#[test]
fn random_segments_meet_what_the_exact_reference_meets() {
    let Some(ctx) = common::ray_query_device("random_segments_meet_what_the_exact_reference_meets")
    else {
        return;
    };
    for (kind, seed) in [
        (ShadowScene::SlabOverPlane, 7),
        (ShadowScene::BoxOverRelief, 8),
    ] {
        let occ = occluders(kind);
        let traced = TracedScene::new(&ctx, &occ).expect("structures");
        // Aimed at points around the relief, from anywhere about the scene, ending short of
        // their target or past it.
        let rays = aimed_rays(&occ, seed);
        let gpu = trace_occlusion(&ctx, &traced, &rays).expect("traced");
        let cpu: Vec<bool> = rays
            .iter()
            .map(|r| occ.any_hit(r.origin, r.dir, r.t_max))
            .collect();
        let agree = gpu.blocked.iter().zip(&cpu).filter(|(g, c)| g == c).count();
        let blocked = cpu.iter().filter(|&&b| b).count();
        eprintln!(
            "{kind}: {agree} of {} agree; {blocked} blocked; {} prism tests",
            rays.len(),
            gpu.prisms_tested
        );
        assert!(
            blocked > 200 && blocked < 3900,
            "{kind}: a test that means something"
        );
        assert!(gpu.prisms_tested > 500, "{kind}: the rays reach the relief");
        // Only rounding at grazing contacts may part f32 from f64.
        assert!(agree >= rays.len() - 4, "{kind}: {agree} of {}", rays.len());
        assert_eq!(gpu.capped, 0);
    }
    common::assert_no_validation_errors(&ctx);
}

/// 4,096 segments aimed at the relief of `occ` from about the scene (seeded).
fn aimed_rays(occ: &SceneOccluders, seed: u64) -> Vec<OcclusionRay> {
    let mut rng = Rng(seed);
    let (lo, hi) = relief_bounds(occ);
    (0..4096)
        .map(|_| {
            let mut v = || rng.range(-1.0, 1.0) as f32;
            let origin = Vec3::new(3.0 * v(), 0.2 + 2.5 * (v() + 1.0), 3.0 * v());
            let t = Vec3::new(rng.next() as f32, rng.next() as f32, rng.next() as f32);
            let target = lo + (hi - lo) * t;
            let dir = (target - origin).normalize_or(Vec3::NEG_Y);
            OcclusionRay {
                origin,
                t_min: 0.0,
                dir,
                t_max: 2.0 * target.distance(origin) * (rng.next() as f32),
            }
        })
        .collect()
}

#[test]
fn an_edit_of_the_heights_is_traced_next_without_touching_a_structure() {
    let Some(ctx) = common::ray_query_device("an_edit_of_the_heights_is_traced_next") else {
        return;
    };
    let kind = ShadowScene::SlabOverPlane;
    let before = occluders(kind);
    let mut traced = TracedScene::new(&ctx, &before).expect("structures");
    let stats = traced.stats();
    // The edit: the bricks' relief inverted, mortar raised and bricks sunk.
    let field = default_heightfield().quantized_unorm16();
    let inverted: Vec<f32> = field.data().iter().map(|h| 1.0 - h).collect();
    let edited = Heightfield::new(field.width(), field.height(), inverted).expect("heights");
    let scene = shadow_scene(kind, 25.0, 0.0);
    let after = SceneOccluders::new(&scene, Some(&edited), kind.address()).expect("occluders");
    let rays = aimed_rays(&before, 5);
    let old = trace_occlusion(&ctx, &traced, &rays).expect("traced");
    let ms = traced.set_heights(&ctx, &edited).expect("edited");
    let new = trace_occlusion(&ctx, &traced, &rays).expect("traced");
    let cpu: Vec<bool> = rays
        .iter()
        .map(|r| after.any_hit(r.origin, r.dir, r.t_max))
        .collect();
    let agree = new.blocked.iter().zip(&cpu).filter(|(g, c)| g == c).count();
    let changed = new
        .blocked
        .iter()
        .zip(&old.blocked)
        .filter(|(a, b)| a != b)
        .count();
    eprintln!(
        "edit in {ms:.2} ms: {changed} verdicts changed; {agree} of {} agree",
        rays.len()
    );
    assert!(
        changed > 50,
        "the edit changes what the rays meet: {changed}"
    );
    assert!(agree >= rays.len() - 4, "{agree} of {}", rays.len());
    assert_eq!(traced.stats(), stats, "no structure was rebuilt");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn no_ray_slips_between_two_relief_triangles() {
    let Some(ctx) = common::ray_query_device("no_ray_slips_between_two_relief_triangles") else {
        return;
    };
    let occ = occluders(ShadowScene::SlabOverPlane);
    let shells: Vec<[Vec3; 3]> = occ
        .occluders()
        .filter_map(|o| match o {
            Occluder::Relief(shell) => Some(shell.corners()),
            Occluder::Triangle(_) => None,
        })
        .collect();
    // The slab's quad: two relief triangles sharing their diagonal.
    let shared: Vec<Vec3> = shells[0]
        .iter()
        .copied()
        .filter(|c| shells[1].iter().any(|d| d.distance(*c) < 1e-6))
        .collect();
    assert_eq!(shared.len(), 2, "the slab's triangles share an edge");
    let normal = (shells[0][1] - shells[0][0])
        .cross(shells[0][2] - shells[0][0])
        .normalize();
    // Rays from above the slab, down through points of the shared edge, slightly tilted: each
    // crosses the top plane on the edge (or within rounding of it) and must meet the field.
    let mut rng = Rng(11);
    let rays: Vec<OcclusionRay> = (0..2048)
        .map(|k| {
            let s = (k as f32 + 0.5) / 2048.0;
            let on_edge = shared[0].lerp(shared[1], s);
            let tilt = Vec3::new(
                rng.range(-0.3, 0.3) as f32,
                0.0,
                rng.range(-0.3, 0.3) as f32,
            );
            let dir = (-normal + tilt).normalize();
            OcclusionRay {
                origin: on_edge - dir * 0.5,
                t_min: 0.0,
                dir,
                t_max: 2.0,
            }
        })
        .collect();
    let traced = TracedScene::new(&ctx, &occ).expect("structures");
    let gpu = trace_occlusion(&ctx, &traced, &rays).expect("traced");
    let cpu = rays
        .iter()
        .filter(|r| occ.any_hit(r.origin, r.dir, r.t_max))
        .count();
    let through = gpu.blocked.iter().filter(|&&b| !b).count();
    assert_eq!(
        cpu,
        rays.len(),
        "the reference blocks every ray through the slab"
    );
    assert_eq!(through, 0, "{through} rays slipped through the shared edge");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn a_segment_that_is_no_segment_is_refused() {
    let Some(ctx) = common::ray_query_device("a_segment_that_is_no_segment_is_refused") else {
        return;
    };
    let traced = TracedScene::new(&ctx, &occluders(ShadowScene::BoxOverPlane)).expect("built");
    let good = OcclusionRay {
        origin: Vec3::new(0.0, 3.0, 0.0),
        t_min: 0.0,
        dir: Vec3::NEG_Y,
        t_max: 10.0,
    };
    let blocked = trace_occlusion(&ctx, &traced, &[good]).expect("traced");
    assert_eq!(
        blocked.blocked,
        [true],
        "the box and the ground lie under the ray"
    );
    for bad in [
        OcclusionRay {
            t_max: f32::NAN,
            ..good
        },
        OcclusionRay {
            t_min: 5.0,
            t_max: 1.0,
            ..good
        },
        OcclusionRay {
            dir: Vec3::ZERO,
            ..good
        },
        OcclusionRay {
            origin: Vec3::INFINITY,
            ..good
        },
    ] {
        let err = trace_occlusion(&ctx, &traced, &[good, bad]).expect_err("refused");
        assert!(err.to_string().contains("occlusion ray 1"), "{err}");
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn stiff_fields_and_depths_meet_what_the_reference_meets() {
    let Some(ctx) =
        common::ray_query_device("stiff_fields_and_depths_meet_what_the_reference_meets")
    else {
        return;
    };
    let kind = ShadowScene::SlabOverPlane;
    let mut spike = vec![0.0; 64 * 64];
    spike[31 * 64 + 31] = 1.0;
    let fields = [
        ("1x1", Heightfield::new(1, 1, vec![0.5]).expect("1x1"), 1.0),
        (
            "spike",
            Heightfield::new(64, 64, spike).expect("spike"),
            1.0,
        ),
        ("deep", default_heightfield(), 8.0),
        ("shallow", default_heightfield(), 0.01),
    ];
    for (name, field, depth_factor) in fields {
        let mut scene = shadow_scene(kind, 25.0, 0.0);
        for m in &mut scene.materials {
            if let Some(relief) = &mut m.relief {
                relief.depth_scale *= depth_factor;
            }
        }
        let field = field.quantized_unorm16();
        let occ = SceneOccluders::new(&scene, Some(&field), kind.address()).expect("occluders");
        let traced = TracedScene::new(&ctx, &occ).expect("structures");
        let rays = aimed_rays(&occ, 3);
        let gpu = trace_occlusion(&ctx, &traced, &rays).expect("traced");
        let agree = rays
            .iter()
            .zip(&gpu.blocked)
            .filter(|(r, &g)| occ.any_hit(r.origin, r.dir, r.t_max) == g)
            .count();
        eprintln!(
            "{name}: {agree} of {} agree, {} capped, {} prism tests",
            rays.len(),
            gpu.capped,
            gpu.prisms_tested
        );
        assert!(agree >= rays.len() - 4, "{name}: {agree} of {}", rays.len());
        // A walk that runs out of its budget (maxmip's, which grows with the texels a ray
        // crosses up to its limit) says so; only the deep field's grazing rays may.
        let allowed = if depth_factor > 1.0 { 4 } else { 0 };
        assert!(gpu.capped <= allowed, "{name}: {} capped", gpu.capped);
        assert!(gpu.prisms_tested > 0, "{name}");
    }
    common::assert_no_validation_errors(&ctx);
}
