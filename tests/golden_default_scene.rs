//! The built-in default scene matches small golden images within stated tolerances: as the
//! library draws it by default, and as `relief render` does (`RenderOptions::finished`).
//! Regenerate after an intended change with `RELIEF_UPDATE_GOLDEN=1 cargo test --test golden_default_scene`.

mod common;

use relief::method::Method;
use relief::render::{render, RenderOptions};
use relief::scene::{default_heightfield, default_scene, DEFAULT_SCENE_METHOD};

const WIDTH: u32 = 192;
const HEIGHT: u32 = 108;

#[test]
fn default_scene_matches_golden() {
    let Some(ctx) = common::device("default_scene_matches_golden") else {
        return;
    };
    let opts = RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT);
    let frame = render(
        &ctx,
        &default_scene(DEFAULT_SCENE_METHOD),
        Some(&default_heightfield()),
        &opts,
    )
    .expect("renders");
    common::assert_no_validation_errors(&ctx);
    common::golden::check_golden("default_scene_192x108", WIDTH, HEIGHT, &frame.rgba);
}

#[test]
fn default_scene_as_relief_render_draws_it_matches_golden() {
    let Some(ctx) = common::device("default_scene_as_relief_render_draws_it_matches_golden") else {
        return;
    };
    // 4x MSAA, PBR Neutral, the built-in sky's light and background.
    let frame = render(
        &ctx,
        &default_scene(DEFAULT_SCENE_METHOD),
        Some(&default_heightfield()),
        &RenderOptions::finished(WIDTH, HEIGHT),
    )
    .expect("renders");
    common::assert_no_validation_errors(&ctx);
    assert!(frame.plan.environment.is_some());
    common::golden::check_golden("default_scene_finished_192x108", WIDTH, HEIGHT, &frame.rgba);
}

#[test]
fn relief_changes_the_image() {
    // Guards against a golden image of a flat, undisplaced slab: relief must move pixels.
    let Some(ctx) = common::device("relief_changes_the_image") else {
        return;
    };
    let opts = RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT);
    let hf = default_heightfield();
    let relief = render(&ctx, &default_scene(Method::POM), Some(&hf), &opts).expect("renders");
    let mut flat_scene = default_scene(Method::POM);
    flat_scene
        .materials
        .iter_mut()
        .for_each(|m| m.relief = None);
    let flat = render(&ctx, &flat_scene, Some(&hf), &opts).expect("renders");
    let (mean, _, _) = common::golden::compare(&relief.rgba, &flat.rgba);
    assert!(
        mean > 3.0,
        "displaced and flat renders barely differ (mean {mean:.3})"
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn every_method_renders_the_default_scene() {
    // Each method's surface pipeline builds with its maps bound, and its relief stays close to
    // POM's picture (same surface, different tracer).
    let Some(ctx) = common::device("every_method_renders_the_default_scene") else {
        return;
    };
    let opts = RenderOptions::default().with_width(96).with_height(54);
    let hf = default_heightfield();
    let pom = render(&ctx, &default_scene(Method::POM), Some(&hf), &opts).expect("renders");
    for method in Method::all() {
        let frame = render(&ctx, &default_scene(method), Some(&hf), &opts).expect("renders");
        let (mean, _, _) = common::golden::compare(&frame.rgba, &pom.rgba);
        let bound = if method.id() == "parallax" { 12.0 } else { 6.0 };
        assert!(
            mean < bound,
            "{method} differs from POM by {mean:.2} on average"
        );
        let shaders: Vec<String> = frame.plan.pipelines.iter().map(|p| p.shader()).collect();
        assert_eq!(
            shaders,
            vec![method.surface_shader_key(), "surface.frag:plain".to_owned()],
            "{method}: the method's pipeline and the plain one, nothing else"
        );
    }
    common::assert_no_validation_errors(&ctx);
}
