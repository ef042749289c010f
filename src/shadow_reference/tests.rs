//! Scenes built by hand: a box over a plane, a relief slab with a groove, and the default scene.

use glam::{Mat4, Vec3};

use super::bvh::{Aabb, Bvh};
use super::triangle::Triangle;
use super::*;
use crate::heightfield::rng::SplitMix64;
use crate::scene::{
    box_mesh, default_heightfield, default_scene, quad_mesh, AlphaMode, LightKind, Material, Relief,
};

fn scene(meshes: Vec<crate::scene::Mesh>, materials: Vec<Material>) -> Scene {
    Scene {
        meshes,
        materials,
        ..Scene::default()
    }
}

/// A 1 x 1 x 1 box floating with its bottom at y = 1 over an 8 x 8 ground at y = 0.
fn box_over_plane(box_material: Material) -> Scene {
    let ground = quad_mesh("ground", 8.0, 8.0, 1.0, 0);
    let mut cube = box_mesh("box", Vec3::splat(0.5), 1);
    cube.transform = Mat4::from_translation(Vec3::new(0.0, 1.5, 0.0));
    scene(vec![ground, cube], vec![Material::default(), box_material])
}

fn sun(direction_toward: Vec3, radius_deg: f32) -> Light {
    Light {
        direction: -direction_toward.normalize(),
        radius: radius_deg.to_radians(),
        casts_shadows: true,
        ..Light::default_light()
    }
}

#[test]
fn box_shadows_the_ground_under_it_and_nothing_beside() {
    let occ =
        SceneOccluders::new(&box_over_plane(Material::default()), None, Address::Repeat).unwrap();
    let light = sun(Vec3::Y, 0.0);
    assert_eq!(
        occ.visible_fraction(Vec3::ZERO, Some(Vec3::Y), &light, 4),
        0.0
    );
    assert_eq!(
        occ.visible_fraction(Vec3::new(2.0, 0.0, 1.0), Some(Vec3::Y), &light, 4),
        1.0
    );
    // Queries do not offset their origin: a ray from the ground meets the ground at 0.
    assert_eq!(occ.first_hit(Vec3::ZERO, Vec3::Y, 5.0), Some(0.0));
    let up = occ.first_hit(Vec3::Y * 0.25, Vec3::Y, 5.0);
    assert_eq!(up, Some(0.75), "the ray up meets the box's bottom first");
}

#[test]
fn soft_penumbra_is_partial_and_monotone_across_the_edge() {
    let occ =
        SceneOccluders::new(&box_over_plane(Material::default()), None, Address::Repeat).unwrap();
    let light = sun(Vec3::Y, 5.0);
    let fractions: Vec<f32> = (0..=12)
        .map(|k| {
            let x = 0.2 + 0.05 * k as f32;
            occ.visible_fraction(Vec3::new(x, 0.0, 0.0), Some(Vec3::Y), &light, 8)
        })
        .collect();
    assert_eq!(fractions[0], 0.0, "{fractions:?}");
    assert_eq!(fractions[12], 1.0, "{fractions:?}");
    assert!(
        fractions.iter().any(|&f| f > 0.1 && f < 0.9),
        "{fractions:?}"
    );
    assert!(fractions.windows(2).all(|w| w[0] <= w[1]), "{fractions:?}");
}

#[test]
fn back_faces_block_and_blend_casts_nothing() {
    // A ground-facing ceiling seen from below: the ray meets its back face.
    let mut ceiling = quad_mesh("ceiling", 2.0, 2.0, 1.0, 0);
    ceiling.transform = Mat4::from_translation(Vec3::Y);
    let occ = SceneOccluders::new(
        &scene(vec![ceiling.clone()], vec![Material::default()]),
        None,
        Address::Repeat,
    )
    .unwrap();
    assert!(occ.any_hit(Vec3::ZERO, Vec3::Y, 10.0));
    let glass = Material {
        alpha_mode: AlphaMode::Blend,
        ..Material::default()
    };
    let occ = SceneOccluders::new(&box_over_plane(glass), None, Address::Repeat).unwrap();
    assert_eq!(occ.triangle_counts(), (2, 0));
    assert_eq!(
        occ.visible_fraction(Vec3::ZERO, None, &sun(Vec3::Y, 0.0), 1),
        1.0
    );
}

#[test]
fn bvh_first_hit_equals_brute_force() {
    let mut rng = SplitMix64::new(27);
    let mut point = |scale: f32| {
        Vec3::new(rng.next_f32(), rng.next_f32(), rng.next_f32()) * (2.0 * scale) - scale
    };
    let triangles: Vec<Triangle> = (0..300)
        .map(|_| {
            let c = point(4.0);
            Triangle {
                corners: [c + point(0.5), c + point(0.5), c + point(0.5)],
            }
        })
        .collect();
    let boxes: Vec<Aabb> = triangles.iter().map(|t| Aabb::around(&t.corners)).collect();
    let bvh = Bvh::build(&boxes);
    let mut hits = 0;
    for _ in 0..2000 {
        let (origin, dir) = (point(5.0), point(1.0).normalize());
        let max_t = 12.0;
        let brute = triangles
            .iter()
            .filter_map(|t| t.hit(origin, dir, max_t))
            .reduce(f32::min);
        let found = bvh.first_hit(origin, dir, max_t, |k, limit| {
            triangles[k].hit(origin, dir, limit)
        });
        assert_eq!(found, brute, "ray {origin} {dir}");
        let any = bvh.any_hit(origin, dir, max_t, |k, limit| {
            triangles[k].hit(origin, dir, limit).is_some()
        });
        assert_eq!(any, brute.is_some());
        hits += usize::from(brute.is_some());
    }
    assert!(hits > 200 && hits < 1900, "a useful mix of hits: {hits}");
}

/// A 16 x 16 map at the top plane except a groove 4 texels wide along v (texels 6..=9 in u, height 0), so the
/// bilinear floor is flat for u in [6.5, 9.5] / 16.
fn grooved() -> Heightfield {
    let data = (0..16 * 16)
        .map(|k| {
            if (6..=9).contains(&(k % 16)) {
                0.0
            } else {
                1.0
            }
        })
        .collect();
    Heightfield::new(16, 16, data).unwrap()
}

const GROOVE_DEPTH: f32 = 0.25;

/// A 1 x 1 relief quad at y = 0 (u along +x, v along +z, one uv unit per world unit) over the grooved map.
fn relief_slab() -> Scene {
    let relief = Relief::new(GROOVE_DEPTH, crate::method::Method::QDM);
    let material = Material {
        relief: Some(relief),
        ..Material::default()
    };
    scene(vec![quad_mesh("slab", 1.0, 1.0, 1.0, 0)], vec![material])
}

fn slab_occluders() -> (SceneOccluders, SceneOccluders) {
    let scene = relief_slab();
    let displaced = SceneOccluders::new(&scene, Some(&grooved()), Address::Clamp).unwrap();
    (displaced, SceneOccluders::flat(&scene).unwrap())
}

#[test]
fn a_ray_through_the_groove_passes_the_displaced_caster_but_not_the_flat_one() {
    let (displaced, flat) = slab_occluders();
    assert_eq!(displaced.triangle_counts(), (0, 2));
    // Enters the top plane in the groove and leaves the footprint's side 0.025 below it, over the floor.
    let through = |x: f32| (Vec3::new(x, 0.05, -1.0), Vec3::new(0.0, -0.05, 1.0));
    let (origin, dir) = through(0.0);
    assert!(!displaced.any_hit(origin, dir, 2.0));
    assert!(flat.any_hit(origin, dir, 2.0));
    // The same ray over the bricks meets them where it enters the top plane.
    let (origin, dir) = through(0.3);
    let t = displaced
        .first_hit(origin, dir, 2.0)
        .expect("blocked by bricks");
    assert!((t - 1.0).abs() < 1e-4, "hit at the top plane, t = {t}");
    assert!(flat.any_hit(origin, dir, 2.0));
}

#[test]
fn relief_receivers_see_past_their_own_surface_and_are_shadowed_by_its_walls() {
    let (displaced, _) = slab_occluders();
    let floor = Vec3::new(0.0, -GROOVE_DEPTH, 0.0);
    let brick = Vec3::new(0.3, 0.0, 0.1);
    let along_groove = sun(Vec3::new(0.0, 1.0, 1.0), 0.0);
    let across = sun(Vec3::new(1.0, 0.6, 0.0), 0.0);
    assert_eq!(
        displaced.visible_fraction(floor, None, &along_groove, 1),
        1.0
    );
    assert_eq!(displaced.visible_fraction(floor, None, &across, 1), 0.0);
    assert_eq!(displaced.visible_fraction(brick, None, &across, 1), 1.0);
    assert_eq!(
        displaced.visible_fraction(brick, None, &along_groove, 1),
        1.0
    );
    // A receiver a hair under the floor (a method's error) is moved onto it, not shadowed by it.
    let under = floor - Vec3::Y * 0.004;
    assert_eq!(
        displaced.visible_fraction(under, None, &along_groove, 1),
        1.0
    );
    assert!((displaced.receiver(under) - floor).length() < 1e-5);
}

#[test]
fn relief_blocking_is_symmetric_and_matches_dense_sampling() {
    let (displaced, _) = slab_occluders();
    let field = grooved();
    let mut rng = SplitMix64::new(2027);
    let (mut mismatches, mut blocked) = (0, 0);
    for _ in 0..300 {
        // Both ends over the footprint: one above the slab, one inside its shell.
        let mut pick = |y0: f32, y1: f32| {
            Vec3::new(
                rng.next_f32() - 0.5,
                y0 + (y1 - y0) * rng.next_f32(),
                rng.next_f32() - 0.5,
            )
        };
        let (a, b) = (pick(0.05, 1.0), pick(-GROOVE_DEPTH, 0.0));
        let forward = displaced.any_hit(a, b - a, 1.0);
        assert_eq!(forward, displaced.any_hit(b, a - b, 1.0), "{a} {b}");
        let sampled = (0..=4000).any(|k| {
            let p = a + (b - a) * (k as f32 / 4000.0);
            let (u, v) = (f64::from(p.x) + 0.5, f64::from(p.z) + 0.5);
            let d = crate::heightfield::reference::surface_depth(
                &field,
                u,
                v,
                f64::from(GROOVE_DEPTH),
                crate::heightfield::reference::SurfaceModel::Bilinear,
                Address::Clamp,
            );
            f64::from(-p.y) >= d + 1e-6
        });
        assert!(
            !sampled || forward,
            "sampling finds a block the shell misses: {a} {b}"
        );
        mismatches += usize::from(forward && !sampled);
        blocked += usize::from(forward);
    }
    assert!(mismatches <= 2, "{mismatches} blocks no sample sees");
    assert!(
        (30..=270).contains(&blocked),
        "a useful mix: {blocked} of 300 blocked"
    );
}

#[test]
fn light_samples_fill_the_cone_and_stop_at_the_sphere() {
    let light = sun(Vec3::new(0.2, 1.0, 0.1), 3.0);
    let axis = -light.direction;
    let samples = light_samples(Vec3::ZERO, &light, 5);
    assert_eq!(samples.len(), 25);
    for s in &samples {
        assert!(s.dir.angle_between(axis) <= 3f32.to_radians() + 1e-5);
        assert_eq!(s.max_t, f32::INFINITY);
    }
    let mean: Vec3 = samples.iter().map(|s| s.dir).sum::<Vec3>() / 25.0;
    assert!(mean.normalize().angle_between(axis) < 0.5f32.to_radians());
    assert_eq!(light_samples(Vec3::ZERO, &sun(Vec3::Y, 0.0), 7).len(), 1);
    let bulb = Light {
        kind: LightKind::Point,
        position: Vec3::new(0.0, 4.0, 0.0),
        radius: 0.5,
        ..Light::default_light()
    };
    let central = light_samples(
        Vec3::ZERO,
        &Light {
            radius: 0.0,
            ..bulb
        },
        3,
    );
    assert_eq!(central.len(), 1);
    assert!((central[0].max_t - 4.0).abs() < 1e-5);
    for s in light_samples(Vec3::ZERO, &bulb, 4) {
        let end = s.dir * s.max_t;
        assert!((end.distance(bulb.position) - 0.5).abs() < 5e-3, "{end}");
    }
    assert!(light_samples(Vec3::new(0.0, 3.8, 0.0), &bulb, 4).is_empty());
}

#[test]
fn agreement_counts_acne_leaks_and_leaves_out_the_band() {
    // Row-major 4 x 2: a shadow edge between columns 1 and 2, plus background and faces-away markers.
    let exact = [1.0, 1.0, 0.0, 0.0, 1.0, -1.0, 0.0, -2.0];
    let relief = [0.2, 1.0, 0.9, 0.0, 1.0, 0.5, 0.0, 0.0];
    let none = measure_agreement(&exact, &relief, &[]);
    assert_eq!((none.pixels, none.excluded_band), (6, 0));
    assert_eq!((none.acne.count, none.leaks.count), (1, 1));
    assert!((none.hard_agreement - 4.0 / 6.0).abs() < 1e-12);
    assert!((none.mean_abs_error - 1.7 / 6.0).abs() < 1e-6);
    assert!((none.max_abs_error - 0.9).abs() < 1e-6);
    let band = shadow_edge_band(&exact, 4, 2, &[0.0]);
    assert_eq!(band, [false, true, true, false, false, false, false, false]);
    let banded = measure_agreement(&exact, &relief, &band);
    assert_eq!((banded.pixels, banded.excluded_band), (4, 2));
    assert_eq!((banded.acne.count, banded.leaks.count), (1, 0));
    let wide = shadow_edge_band(&exact, 4, 2, &[1.0]);
    assert_eq!(wide, [true, true, true, true, false, true, true, false]);
    assert!(none.to_string().contains("acne 1"));
    assert!(serde_json::to_string(&none).unwrap().contains("\"leaks\""));
}

#[test]
fn parallel_fractions_match_one_by_one() {
    let occ =
        SceneOccluders::new(&box_over_plane(Material::default()), None, Address::Repeat).unwrap();
    let light = sun(Vec3::new(0.3, 1.0, 0.0), 4.0);
    let points: Vec<Option<Vec3>> = (0..40)
        .map(|k| (k % 7 != 0).then(|| Vec3::new(k as f32 * 0.05 - 1.0, 0.0, 0.1)))
        .collect();
    let all = occ.visible_fractions(&points, &light, 4);
    for (p, f) in points.iter().zip(&all) {
        let one = p.map_or(NO_RECEIVER, |p| occ.visible_fraction(p, None, &light, 4));
        assert_eq!(*f, one);
    }
}

#[test]
fn default_scene_cube_shadows_the_ground_and_the_slab_is_displaced() {
    let scene = default_scene(crate::method::Method::QDM);
    let occ = SceneOccluders::new(&scene, Some(&default_heightfield()), Address::Repeat).unwrap();
    let (plain, relief) = occ.triangle_counts();
    assert_eq!(relief, 2);
    assert!(plain > 12);
    let light = scene.lights[0];
    let toward = -light.direction;
    // The ground behind the cube, seen from the light, and a ground point well clear of everything.
    let behind = Vec3::new(1.7, -0.6, -0.6) - Vec3::new(toward.x, 0.0, toward.z).normalize() * 0.5;
    assert_eq!(occ.visible_fraction(behind, Some(Vec3::Y), &light, 1), 0.0);
    let clear = Vec3::new(4.0, -0.6, -4.0);
    assert_eq!(occ.visible_fraction(clear, Some(Vec3::Y), &light, 3), 1.0);
}

#[test]
fn a_floating_grooved_slab_lets_light_through_its_groove_where_the_flat_one_blocks() {
    let mut scene = relief_slab();
    scene.meshes[0].transform = Mat4::from_translation(Vec3::Y);
    scene.meshes.push(quad_mesh("ground", 8.0, 8.0, 1.0, 1));
    scene.materials.push(Material::default());
    let displaced = SceneOccluders::new(&scene, Some(&grooved()), Address::Clamp).unwrap();
    let flat = SceneOccluders::flat(&scene).unwrap();
    // Low light along the groove: this ground point's ray enters the groove's open end 0.1 below the
    // polygon and leaves through the polygon a third of a unit later.
    let light = sun(Vec3::new(0.0, 0.3, 1.0), 0.0);
    let in_line = Vec3::new(0.0, 0.0, -3.5);
    assert_eq!(
        displaced.visible_fraction(in_line, Some(Vec3::Y), &light, 1),
        1.0
    );
    assert_eq!(
        flat.visible_fraction(in_line, Some(Vec3::Y), &light, 1),
        0.0
    );
    // Beside the groove the same ray meets the bricks' wall.
    let beside = Vec3::new(0.3, 0.0, -3.5);
    assert_eq!(
        displaced.visible_fraction(beside, Some(Vec3::Y), &light, 1),
        0.0
    );
}

#[test]
fn normals_facing_away_and_point_lights_bound_the_rays() {
    let occ =
        SceneOccluders::new(&box_over_plane(Material::default()), None, Address::Repeat).unwrap();
    let open = Vec3::new(3.0, 0.0, 3.0);
    let light = sun(Vec3::Y, 10.0);
    assert_eq!(occ.visible_fraction(open, Some(-Vec3::Y), &light, 4), 0.0);
    // A disk straddling the horizon: only its upper half can be seen.
    let low = sun(Vec3::X, 10.0);
    let half = occ.visible_fraction(open, Some(Vec3::Y), &low, 8);
    assert!((half - 0.5).abs() < 0.1, "{half}");
    let bulb = |y: f32| Light {
        kind: LightKind::Point,
        position: Vec3::new(0.0, y, 0.0),
        radius: 0.1,
        ..Light::default_light()
    };
    assert_eq!(
        occ.visible_fraction(Vec3::ZERO, Some(Vec3::Y), &bulb(0.5), 3),
        1.0
    );
    assert_eq!(
        occ.visible_fraction(Vec3::ZERO, Some(Vec3::Y), &bulb(3.0), 3),
        0.0
    );
    assert_eq!(
        occ.visible_fraction(Vec3::NAN, None, &bulb(3.0), 3),
        NO_RECEIVER
    );
}

#[test]
fn a_height_texture_with_a_uv_transform_casts_as_the_frame_map_does() {
    use crate::heightfield::Channel;
    use crate::scene::{HeightSource, SceneImage, TextureRef, UvTransform};
    // The frame map over a quad whose uvs repeat twice, against the same map as a texture whose transform
    // repeats it twice over uvs that span the quad once: the same heights at the same places, and the same
    // depth unit (half a world unit per uv in both).
    let light = sun(Vec3::new(0.4, 0.5, 0.7), 2.0);
    let mut frame_scene = relief_slab();
    frame_scene.meshes[0] = quad_mesh("slab", 1.0, 1.0, 2.0, 0);
    let codes: Vec<u16> = grooved().to_unorm16();
    let image = image::ImageBuffer::from_raw(16, 16, codes).unwrap();
    let mut texture_scene = relief_slab();
    texture_scene.images.push(SceneImage {
        name: "grooves".into(),
        pixels: std::sync::Arc::new(image::DynamicImage::ImageLuma16(image)),
    });
    let texture = TextureRef {
        image: 0,
        tex_coord: 0,
        transform: UvTransform {
            scale: [2.0, 2.0],
            ..UvTransform::default()
        },
        sampler: Default::default(),
    };
    let relief = texture_scene.materials[0].relief.as_mut().unwrap();
    relief.height = HeightSource::Texture {
        texture,
        channel: Channel::default(),
        invert: false,
    };
    let by_frame = SceneOccluders::new(&frame_scene, Some(&grooved()), Address::Repeat).unwrap();
    let by_texture = SceneOccluders::new(&texture_scene, None, Address::Clamp).unwrap();
    let points: Vec<Option<Vec3>> = (0..400)
        .map(|k| {
            let (i, j) = ((k % 20) as f32 / 19.0 - 0.5, (k / 20) as f32 / 19.0 - 0.5);
            Some(Vec3::new(i * 0.98, -0.06, j * 0.98))
        })
        .collect();
    let a = by_frame.visible_fractions(&points, &light, 3);
    let b = by_texture.visible_fractions(&points, &light, 3);
    assert_eq!(a, b);
    assert!(a.contains(&0.0) && a.contains(&1.0), "{a:?}");
}

#[test]
fn extreme_lights_give_finite_fractions() {
    let (displaced, _) = slab_occluders();
    let lights = [
        sun(Vec3::new(1.0, 0.0, 0.0), 0.0),
        sun(Vec3::new(1.0, 0.0, 0.3), 5.0),
        sun(Vec3::Y, 0.0),
        sun(Vec3::Y, 0.5),
        sun(Vec3::new(0.2, 1.0, 0.0), 89.0),
        sun(Vec3::new(0.2, 1.0, 0.0), 400.0),
    ];
    let points = [
        Vec3::new(0.0, -GROOVE_DEPTH, 0.0),
        Vec3::new(0.3, 0.0, 0.1),
        Vec3::new(0.1, -0.2, -0.45),
    ];
    let inside = Vec3::new(0.3, -0.1, 0.0);
    assert!(
        displaced.any_hit(inside, Vec3::ZERO, 1.0),
        "a point inside a brick"
    );
    assert!(!displaced.any_hit(inside, Vec3::NAN, 1.0));
    assert!(!displaced.any_hit(Vec3::NAN, Vec3::Y, 1.0));
    for light in &lights {
        for p in points {
            let f = displaced.visible_fraction(p, Some(Vec3::Y), light, 4);
            assert!((0.0..=1.0).contains(&f), "{light:?} at {p}: {f}");
        }
    }
}
