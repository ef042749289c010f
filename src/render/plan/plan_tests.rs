//! The plan's tests: what each kind of scene needs, shares and skips.

use super::*;
use crate::heightfield::Generator;
use crate::scene::{quad_mesh, Material, Relief};

fn scene(methods: &[Option<&str>], shadows: bool) -> Scene {
    let materials = methods
        .iter()
        .enumerate()
        .map(|(k, m)| Material {
            name: format!("m{k}"),
            relief: m.map(|id| Relief::new(0.05, id.parse().expect("known id"))),
            ..Material::default()
        })
        .collect();
    let meshes = (0..methods.len())
        .map(|k| quad_mesh(&format!("q{k}"), 1.0, 1.0, 1.0, k))
        .collect();
    let lights = if shadows {
        vec![Light {
            casts_shadows: true,
            radius: 0.0,
            ..Light::default_light()
        }]
    } else {
        Vec::new()
    };
    Scene {
        meshes,
        materials,
        lights,
        ..Scene::default()
    }
}

fn plan(scene: &Scene) -> Plan {
    let hf = Generator::Fbm.generate(16, 16, 1);
    Plan::derive(scene, Some(&hf)).expect("plans")
}

#[test]
fn plain_scene_needs_no_heights_and_no_shadow_work() {
    let p = plan(&scene(&[None, None], true));
    assert_eq!(p.pipelines.len(), 1);
    assert_eq!(p.pipelines[0].method, None);
    assert!(p.heights.is_empty());
    assert!(p.passes.iter().all(|x| x.pass != Pass::SelfShadowRays));
    assert!(p.skipped.iter().any(|s| s.what == "self-shadow rays"));
}

#[test]
fn methods_sharing_a_height_map_share_its_upload() {
    // pom and qdm read the same frame map and no method map: one upload, with the pyramid.
    let p = plan(&scene(&[Some("pom"), Some("qdm"), None], false));
    assert_eq!(p.pipelines.len(), 3);
    assert_eq!(p.heights.len(), 1);
    assert!(p.heights[0].pyramid);
    assert_eq!(p.draws[0].heights, p.draws[1].heights);
    assert_eq!(p.draws[2].heights, None);
}

#[test]
fn each_map_kind_gets_its_own_height_upload() {
    let p = plan(&scene(&[Some("csm"), Some("quadric"), Some("csm")], true));
    let kinds: Vec<_> = p.heights.iter().map(|h| h.map).collect();
    assert_eq!(
        kinds,
        [Some(MapKind::ConservativeCone), Some(MapKind::Quadric)]
    );
    assert!(p
        .pipelines
        .iter()
        .all(|k| k.shadows.mode == ShadowMode::Hard));
    assert!(p.skipped.iter().any(|s| s.what == "relaxed_cone_map"));
}

#[test]
fn unused_materials_and_empty_meshes_are_skipped_with_reasons() {
    let mut s = scene(&[Some("pom"), None], false);
    s.meshes[1].indices.clear();
    let p = plan(&s);
    assert_eq!(p.draws.len(), 1);
    let whats: Vec<&str> = p.skipped.iter().map(|x| x.what.as_str()).collect();
    assert!(whats.contains(&"mesh \"q1\""), "{whats:?}");
    assert!(whats.contains(&"material \"m1\""), "{whats:?}");
}

#[test]
fn ao_maps_are_planned_only_when_asked_and_shared() {
    let mut s = scene(&[Some("pom"), Some("pom"), Some("qdm")], false);
    let p = plan(&s);
    assert!(p.ao_maps.is_empty());
    assert!(p.skipped.iter().any(|k| k.what == "ao map"));
    let horizon = AoMode::Horizon {
        directions: 8,
        rotated: false,
    };
    for m in &mut s.materials[..2] {
        m.relief.as_mut().expect("relief").ao = horizon;
    }
    let p = plan(&s);
    assert_eq!(
        p.ao_maps.len(),
        1,
        "two materials, one map: {:?}",
        p.ao_maps
    );
    assert_eq!(p.draws[0].ao, Some(0));
    assert_eq!(p.draws[1].ao, Some(0));
    assert_eq!(p.draws[2].ao, None);
    let pom_heights = p.draws[0].heights.expect("relief");
    assert!(
        p.heights[pom_heights].pyramid,
        "horizon AO reads the pyramid"
    );
    assert!(p.passes.iter().any(|x| x.pass == Pass::AmbientOcclusion));
    s.materials[1].relief.as_mut().expect("relief").depth_scale = 0.1;
    assert_eq!(plan(&s).ao_maps.len(), 2, "AO depends on the depth scale");
}
