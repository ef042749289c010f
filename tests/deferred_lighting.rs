//! The deferred frame (`RenderOptions::lighting`, `--lighting deferred`): the surface pass writes
//! shading inputs beside the G-buffer and one compute pass lights each pixel after the scene is
//! drawn. It must draw what forward lighting draws: the finished look at one sample (sky light,
//! PCSS shadow maps, relief self-shadows, the tone curve), point and spot lights with their maps,
//! flat ambient light, every relief variant the surface pass has (curved, shells, LOD, layers are
//! the same fragments with other traces). And frames it cannot light are refused with the reason.

mod common;

use std::sync::Arc;

use glam::Vec3;
use relief::heightfield::Heightfield;
use relief::render::{render, Lighting, Pass, RenderOptions, Renderer};
use relief::scene::{
    default_heightfield, default_scene, Light, LightKind, Scene, DEFAULT_SCENE_METHOD,
};
use relief::vk::Context;

/// Largest per-channel difference (8-bit sRGB steps) a pixel may show between the two paths:
/// the shading normal crosses the shading inputs as 2 x 16 bits and the albedo as half floats,
/// which rounds a colour to the neighbouring step at most.
const MAX_STEP: u8 = 1;
/// Share of pixels that may differ at all (by that one step; about 9% do on the default scene).
const MAX_CHANGED: f64 = 0.15;

fn both(
    ctx: &Arc<Context>,
    scene: &Scene,
    heights: &Heightfield,
    opts: &RenderOptions,
) -> (Vec<u8>, Vec<u8>) {
    let forward = opts.clone().with_lighting(Lighting::Forward);
    let deferred = opts.clone().with_lighting(Lighting::Deferred);
    let a = render(ctx, scene, Some(heights), &forward).expect("renders forward");
    let b = render(ctx, scene, Some(heights), &deferred).expect("renders deferred");
    assert!(
        b.plan.deferred && !a.plan.deferred,
        "the plans say where they light"
    );
    (a.rgba, b.rgba)
}

/// Asserts the deferred frame draws the forward one: every channel within MAX_STEP, at most
/// MAX_CHANGED of the pixels different at all; returns the largest difference.
fn assert_alike(what: &str, (forward, deferred): (Vec<u8>, Vec<u8>)) -> u8 {
    let mut changed = 0usize;
    let mut largest = 0u8;
    let mut worst = 0usize;
    for (k, (p, q)) in forward
        .chunks_exact(4)
        .zip(deferred.chunks_exact(4))
        .enumerate()
    {
        let d = (0..3).map(|c| p[c].abs_diff(q[c])).max().unwrap_or(0);
        if d > 0 {
            changed += 1;
        }
        if d > largest {
            largest = d;
            worst = k;
        }
    }
    let pixels = forward.len() / 4;
    let share = changed as f64 / pixels as f64;
    eprintln!(
        "{what}: {changed} of {pixels} pixels differ ({:.3}%), largest step {largest}",
        100.0 * share
    );
    assert!(
        largest <= MAX_STEP,
        "{what}: pixel {worst} differs by {largest} steps between forward and deferred lighting \
         (forward {:?}, deferred {:?})",
        &forward[worst * 4..worst * 4 + 3],
        &deferred[worst * 4..worst * 4 + 3]
    );
    assert!(share <= MAX_CHANGED, "{what}: {changed} pixels differ");
    largest
}

fn look(width: u32, height: u32) -> RenderOptions {
    RenderOptions::finished(width, height).with_msaa(1)
}

#[test]
fn the_finished_look_at_one_sample_is_the_forward_one() {
    let Some(ctx) = common::device("the_finished_look_at_one_sample_is_the_forward_one") else {
        return;
    };
    let heights = default_heightfield();
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    assert!(
        scene.lights.iter().any(|l| l.casts_shadows),
        "the default scene's sun casts shadows (maps and self-shadows)"
    );
    assert_alike(
        "default scene, sky light, PCSS maps, PBR Neutral",
        both(&ctx, &scene, &heights, &look(240, 135)),
    );
    let flat = RenderOptions::default()
        .with_msaa(1)
        .with_width(240)
        .with_height(135);
    assert_alike(
        "default scene, flat ambient light",
        both(&ctx, &scene, &heights, &flat),
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn point_and_spot_lights_with_their_maps_light_alike() {
    let Some(ctx) = common::device("point_and_spot_lights_with_their_maps_light_alike") else {
        return;
    };
    let heights = default_heightfield();
    let mut scene = default_scene(DEFAULT_SCENE_METHOD);
    scene.lights.push(Light {
        kind: LightKind::Point,
        position: Vec3::new(0.8, 1.2, 1.0),
        color: Vec3::new(4.0, 3.0, 2.0),
        casts_shadows: true,
        radius: 0.05,
        ..Light::default_light()
    });
    scene.lights.push(Light {
        kind: LightKind::Spot {
            inner_cone: 0.3,
            outer_cone: 0.6,
        },
        position: Vec3::new(-1.0, 1.5, 1.2),
        direction: Vec3::new(0.5, -0.8, -0.4).normalize(),
        color: Vec3::new(2.0, 3.0, 4.0),
        range: Some(6.0),
        casts_shadows: true,
        ..Light::default_light()
    });
    assert_alike(
        "default scene, sun, point and spot",
        both(&ctx, &scene, &heights, &look(200, 112)),
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn the_gbuffer_shadow_share_is_the_forward_one() {
    let Some(ctx) = common::device("the_gbuffer_shadow_share_is_the_forward_one") else {
        return;
    };
    let heights = default_heightfield();
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let opts = look(160, 90).with_gbuffer(true);
    let forward = render(&ctx, &scene, Some(&heights), &opts).expect("forward");
    let deferred = render(
        &ctx,
        &scene,
        Some(&heights),
        &opts.with_lighting(Lighting::Deferred),
    )
    .expect("deferred");
    let (f, d) = (
        forward.gbuffer.expect("forward G-buffer"),
        deferred.gbuffer.expect("deferred G-buffer"),
    );
    assert_eq!(f.mesh, d.mesh, "the same surfaces are drawn");
    assert_eq!(f.depth, d.depth, "the same depths");
    let shadowed = f.shadow.iter().filter(|&&s| s < 0.5).count();
    assert!(
        shadowed > 100,
        "the sun casts shadows here ({shadowed} pixels)"
    );
    let worst = f
        .shadow
        .iter()
        .zip(&d.shadow)
        .map(|(a, b)| (a - b).abs())
        .fold(0.0f32, f32::max);
    assert!(worst < 2e-3, "shadow share differs by {worst}");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn the_lighting_pass_is_in_the_graph_only_when_deferred() {
    let Some(ctx) = common::device("the_lighting_pass_is_in_the_graph_only_when_deferred") else {
        return;
    };
    let heights = default_heightfield();
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let lit = |lighting| {
        let opts = look(64, 36).with_lighting(lighting);
        let r = Renderer::new(&ctx, &scene, Some(&heights), &opts).expect("renderer");
        let has_lighting = r.graph().passes().any(|p| p == Pass::Lighting);
        has_lighting
    };
    assert!(lit(Lighting::Deferred));
    assert!(!lit(Lighting::Forward));
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn frames_it_cannot_light_are_refused_with_the_reason() {
    let Some(ctx) = common::device("frames_it_cannot_light_are_refused_with_the_reason") else {
        return;
    };
    let heights = default_heightfield();
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let refused = |opts: RenderOptions| {
        let opts = opts.with_lighting(Lighting::Deferred);
        match Renderer::new(&ctx, &scene, Some(&heights), &opts) {
            Ok(_) => panic!("a deferred frame that cannot be lit deferred was built"),
            Err(e) => e.to_string(),
        }
    };
    let msaa = refused(RenderOptions::finished(64, 36));
    assert!(msaa.contains("--msaa 1"), "{msaa}");
    let supersampled = refused(look(64, 36).with_supersample(2));
    assert!(supersampled.contains("--supersample"), "{supersampled}");
    let probed = refused(RenderOptions::default().with_shadow_probe(Some(0)));
    assert!(probed.contains("shadow probe"), "{probed}");
    let mut many = scene.clone();
    for k in 0..4 {
        many.lights.push(Light {
            direction: Vec3::new(0.1 * k as f32, -1.0, 0.2).normalize(),
            casts_shadows: true,
            ..Light::default_light()
        });
    }
    let opts = look(64, 36).with_lighting(Lighting::Deferred);
    let lights = match Renderer::new(&ctx, &many, Some(&heights), &opts) {
        Ok(_) => panic!("five self-shadowing lights lit deferred"),
        Err(e) => e.to_string(),
    };
    assert!(lights.contains("first 4 lights"), "{lights}");
    common::assert_no_validation_errors(&ctx);
}
