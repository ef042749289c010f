//! The frame's graph of passes (`Renderer::graph`): what each scene records, in which order, and
//! what it leaves out, checked on the renderers the plan makes for a few scenes; and that the
//! frames recorded from the graph are the frames the forward path drew before it (the golden
//! and reference tests hold the images themselves).

mod common;

use relief::render::{Pass, RenderOptions, Renderer};
use relief::scene::{default_heightfield, default_scene, quad_mesh, Material, Scene};

fn passes(renderer: &Renderer) -> Vec<Pass> {
    renderer.graph().nodes.iter().map(|n| n.pass).collect()
}

#[test]
fn the_default_scene_records_its_maps_occluders_surface_sky_and_tone_map_in_order() {
    let Some(ctx) = common::device("the_default_scene_records_its_graph") else {
        return;
    };
    let scene = default_scene(relief::scene::DEFAULT_SCENE_METHOD);
    let heights = default_heightfield();
    let opts = RenderOptions::finished(64, 36);
    let renderer = Renderer::new(&ctx, &scene, Some(&heights), &opts).expect("renderer");
    let order = passes(&renderer);
    let at = |pass: Pass| order.iter().position(|&p| p == pass);
    for pass in [
        Pass::Pyramid,
        Pass::ShadowMaps,
        Pass::Surface,
        Pass::ToneMap,
    ] {
        assert!(at(pass).is_some(), "{pass} missing from {order:?}");
    }
    // Every writer before its readers.
    assert!(at(Pass::Pyramid) < at(Pass::ShadowMaps));
    assert!(at(Pass::ShadowMaps) < at(Pass::Surface));
    assert!(at(Pass::Surface) < at(Pass::Background));
    assert_eq!(order.last(), Some(&Pass::ToneMap));
    assert!(renderer.graph().dropped.is_empty());
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn a_plain_scene_builds_no_map_pass_and_the_g_buffer_is_a_write_of_the_surface() {
    let Some(ctx) = common::device("a_plain_scene_builds_no_map_pass") else {
        return;
    };
    let scene = Scene {
        meshes: vec![quad_mesh("floor", 2.0, 2.0, 1.0, 0)],
        materials: vec![Material::default()],
        ..Scene::default()
    };
    let opts = RenderOptions::default()
        .with_width(32)
        .with_height(32)
        .with_gbuffer(true);
    let renderer = Renderer::new(&ctx, &scene, None, &opts).expect("renderer");
    assert_eq!(passes(&renderer), [Pass::Surface, Pass::ToneMap]);
    let surface = &renderer.graph().nodes[0];
    assert!(surface.reads.is_empty(), "{surface:?}");
    let writes: Vec<String> = surface.writes.iter().map(|w| w.to_string()).collect();
    assert_eq!(writes, ["radiance", "depth", "g-buffer"]);
    common::assert_no_validation_errors(&ctx);
}
