//! Ray-traced shadows in the frame (`RenderOptions::traced_shadows`, `--traced-shadows`): the
//! deferred lighting pass casts each shadow-casting light's rays from every shaded pixel through
//! the scene's acceleration structures. Each pixel's shadow (the G-buffer's share of the light
//! that arrives) is checked against the exact CPU reference (`SceneOccluders`) from the same
//! point: ray for ray for a hard sun, in distribution for a soft one and for a point light.

mod common;

use glam::Vec3;
use relief::heightfield::Address;
use relief::render::{frame_camera, render, Frame, Lighting, Pass, RenderOptions};
use relief::scene::{
    default_heightfield, default_scene, Light, LightKind, Scene, DEFAULT_SCENE_METHOD,
};
use relief::shadow_reference::SceneOccluders;

fn traced(width: u32, height: u32) -> RenderOptions {
    RenderOptions::default()
        .with_width(width)
        .with_height(height)
        .with_msaa(1)
        .with_gbuffer(true)
        .with_lighting(Lighting::Deferred)
        .with_traced_shadows(true)
}

/// Per pixel lit by `light` (facing it, so its G-buffer share is that light's visibility): the
/// frame's share and the reference's visible fraction from the same point.
fn shares_against_reference(
    frame: &Frame,
    scene: &Scene,
    light: &Light,
    samples_per_side: u32,
) -> Vec<(f32, f32)> {
    let g = frame.gbuffer.as_ref().expect("the G-buffer");
    let camera = frame_camera(scene);
    let positions = g.positions(&camera);
    let occluders = SceneOccluders::new(
        scene,
        Some(&default_heightfield().quantized_unorm16()),
        Address::Repeat,
    )
    .expect("reference occluders");
    let mut pairs = Vec::new();
    for (k, p) in positions.iter().enumerate() {
        let p = Vec3::from_array(*p);
        let n = Vec3::from_array(g.normal[k]);
        if g.mesh[k] == 0 || !p.is_finite() {
            continue;
        }
        let toward = match light.kind {
            LightKind::Directional => -light.direction,
            _ => (light.position - p).normalize(),
        };
        // Well clear of the terminator: there the frame's and the reference's points, a hair
        // apart, may face the light differently.
        if n.dot(toward) < 0.05 {
            continue;
        }
        let exact = occluders.visible_fraction(p, None, light, samples_per_side);
        pairs.push((g.shadow[k], exact));
    }
    pairs
}

#[test]
fn a_hard_sun_shadows_each_pixel_as_the_exact_reference_does() {
    let Some(ctx) =
        common::ray_query_device("a_hard_sun_shadows_each_pixel_as_the_exact_reference")
    else {
        return;
    };
    let mut scene = default_scene(DEFAULT_SCENE_METHOD);
    scene.lights[0].radius = 0.0;
    let light = scene.lights[0];
    assert!(light.casts_shadows);
    let frame = render(&ctx, &scene, Some(&default_heightfield()), &traced(160, 90))
        .expect("renders with traced shadows");
    assert!(
        frame.plan.shadow_maps.is_empty(),
        "traced shadows build no shadow map"
    );
    assert!(!frame.plan.passes.iter().any(|p| p.pass == Pass::ShadowMaps));
    let pairs = shares_against_reference(&frame, &scene, &light, 1);
    let shadowed = pairs.iter().filter(|(_, e)| *e < 0.5).count();
    let agree = pairs.iter().filter(|(s, e)| (s - e).abs() < 0.5).count();
    let share = agree as f64 / pairs.len() as f64;
    eprintln!(
        "hard sun: {agree} of {} lit pixels agree with the reference ({:.3}%), {shadowed} in shadow",
        pairs.len(),
        100.0 * share
    );
    assert!(
        shadowed > 200,
        "the sun casts shadows here ({shadowed} pixels)"
    );
    assert!(share >= 0.995, "{agree} of {} agree", pairs.len());
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn soft_and_point_lights_agree_with_the_reference_in_distribution() {
    let Some(ctx) = common::ray_query_device("soft_and_point_lights_agree_with_the_reference")
    else {
        return;
    };
    let heights = default_heightfield();
    let mut soft = default_scene(DEFAULT_SCENE_METHOD);
    soft.lights[0].radius = 0.05;
    let mut point = default_scene(DEFAULT_SCENE_METHOD);
    point.lights[0] = Light {
        kind: LightKind::Point,
        position: Vec3::new(1.5, 2.5, 1.5),
        color: Vec3::splat(20.0),
        radius: 0.15,
        casts_shadows: true,
        ..Light::default_light()
    };
    for (what, scene) in [("soft sun", &soft), ("point light", &point)] {
        let frame = render(&ctx, scene, Some(&heights), &traced(128, 72)).expect("renders");
        let pairs = shares_against_reference(&frame, scene, &scene.lights[0], 4);
        let mean: f64 = pairs
            .iter()
            .map(|(s, e)| f64::from((s - e).abs()))
            .sum::<f64>()
            / pairs.len() as f64;
        let penumbra = pairs.iter().filter(|(_, e)| *e > 0.0 && *e < 1.0).count();
        eprintln!(
            "{what}: mean difference {mean:.4} over {} lit pixels, {penumbra} in penumbra",
            pairs.len()
        );
        assert!(pairs.len() > 1000, "{what}: {} pixels", pairs.len());
        assert!(mean < 0.02, "{what}: mean difference {mean}");
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn traced_shadows_need_the_deferred_frame() {
    let Some(ctx) = common::ray_query_device("traced_shadows_need_the_deferred_frame") else {
        return;
    };
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let opts = traced(64, 36).with_lighting(Lighting::Forward);
    let err = match render(&ctx, &scene, Some(&default_heightfield()), &opts) {
        Ok(_) => panic!("traced shadows lit forward"),
        Err(e) => e.to_string(),
    };
    assert!(err.contains("--lighting deferred"), "{err}");
    common::assert_no_validation_errors(&ctx);
}
