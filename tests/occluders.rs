//! The occluder pass: relief fragments behind the nearest opaque surface's reach skip their
//! trace, and the image stays what the forward path (`occluders: false`) draws, bit for bit: in
//! stacks whose relief overlaps in depth and stacks whose hidden quads are wholly hidden, in
//! both draw orders, with one sample and with 4x MSAA, behind plain meshes, with readers that cut
//! their silhouettes (curved relief, prism shells) and clamp-addressed maps.

mod common;

use std::sync::Arc;

use glam::{Mat4, Vec3};
use relief::heightfield::{Address, Generator, Heightfield};
use relief::method::Method;
use relief::render::{render, Pass, RenderOptions, Renderer};
use relief::scene::{
    box_mesh, default_heightfield, default_scene, relief_stack_scene, sphere_mesh, Material,
    Relief, Scene, Silhouettes,
};
use relief::vk::Context;

fn options(msaa: u32) -> RenderOptions {
    RenderOptions::default()
        .with_width(192)
        .with_height(108)
        .with_msaa(msaa)
}

/// The frame with and without the occluder pass.
fn both(
    ctx: &Arc<Context>,
    scene: &Scene,
    heights: &Heightfield,
    opts: &RenderOptions,
) -> (Vec<u8>, Vec<u8>) {
    let culled = render(ctx, scene, Some(heights), opts).expect("renders with occluders");
    let forward = opts.clone().with_occluders(false);
    let traced = render(ctx, scene, Some(heights), &forward).expect("renders without");
    (culled.rgba, traced.rgba)
}

/// Pixels whose colour differs, and the largest channel difference.
fn differences(a: &[u8], b: &[u8]) -> (usize, u8) {
    let mut count = 0;
    let mut largest = 0;
    for (p, q) in a.chunks_exact(4).zip(b.chunks_exact(4)) {
        let d = p
            .iter()
            .zip(q)
            .map(|(x, y)| x.abs_diff(*y))
            .max()
            .unwrap_or(0);
        if d > 0 {
            count += 1;
            largest = largest.max(d);
        }
    }
    (count, largest)
}

fn assert_same(what: &str, (culled, traced): (Vec<u8>, Vec<u8>)) {
    let (count, largest) = differences(&culled, &traced);
    assert_eq!(
        count, 0,
        "{what}: {count} pixel(s) differ from the forward path (largest channel difference {largest})"
    );
}

/// The stack with each quad slid sideways by its own fraction of the height map's tile, so the
/// relief of one quad does not line up with the next one's (aligned, a quad behind never shows
/// through the one in front: at each pixel both have the same depth under their tops).
fn staggered(mut scene: Scene) -> Scene {
    for mesh in &mut scene.meshes {
        let behind = -mesh.transform.w_axis.z;
        let shift = Mat4::from_translation(Vec3::new(2.3 * behind, 1.1 * behind, 0.0));
        mesh.transform = shift * mesh.transform;
    }
    scene
}

#[test]
fn hidden_relief_skipped_leaves_the_stacks_image_unchanged() {
    let Some(ctx) = common::device("hidden_relief_skipped_leaves_the_stacks_image_unchanged")
    else {
        return;
    };
    // Bricks: mortar 0.24 units under the top, so 0.1 apart the quads behind show through the
    // mortar of the ones in front (some 4,000 of the frame's 20,736 pixels); 1 apart, every quad
    // behind the first is wholly hidden.
    let heights = Generator::Bricks.generate(128, 128, 7);
    for spacing in [0.1f32, 1.0] {
        for nearest_first in [true, false] {
            let scene = staggered(relief_stack_scene(4, spacing, nearest_first, Method::QDM));
            for msaa in [1, 4] {
                let what = format!(
                    "stack {spacing} apart, {} first, {msaa} sample(s)",
                    if nearest_first { "nearest" } else { "farthest" }
                );
                assert_same(&what, both(&ctx, &scene, &heights, &options(msaa)));
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}

/// A relief quad half behind a plain box, a curved-relief sphere and a prism-shell sphere half
/// behind the quad, all opaque; `method` traces the quad.
fn mixed_scene(method: Method) -> Scene {
    let mut scene = relief_stack_scene(1, 1.0, true, method);
    let curved = Material {
        name: "curved".into(),
        relief: Some(Relief {
            silhouettes: Silhouettes::Curved,
            ..Relief::new(0.04, Method::RELIEF)
        }),
        ..Material::default()
    };
    let shells = Material {
        name: "shells".into(),
        relief: Some(Relief {
            silhouettes: Silhouettes::Shells,
            ..Relief::new(0.04, Method::RELIEF)
        }),
        ..Material::default()
    };
    let plain = Material {
        name: "plain".into(),
        base_color: [0.2, 0.4, 0.8, 1.0],
        ..Material::default()
    };
    scene.materials.extend([curved, shells, plain]);
    let mut box_in_front = box_mesh("box", Vec3::new(0.6, 0.6, 0.6), 3);
    box_in_front.transform = Mat4::from_translation(Vec3::new(-1.2, 0.3, 1.2));
    let mut curved_sphere = sphere_mesh("curved sphere", 1.0, 16, 32, 1);
    curved_sphere.transform = Mat4::from_translation(Vec3::new(1.4, 0.0, -0.5));
    let mut shell_sphere = sphere_mesh("shell sphere", 1.0, 12, 24, 2);
    shell_sphere.transform = Mat4::from_translation(Vec3::new(-1.4, -0.6, -0.6));
    scene
        .meshes
        .extend([box_in_front, curved_sphere, shell_sphere]);
    scene
}

#[test]
fn readers_that_cut_their_outline_and_plain_occluders_keep_their_image() {
    let Some(ctx) =
        common::device("readers_that_cut_their_outline_and_plain_occluders_keep_their_image")
    else {
        return;
    };
    let heights = Generator::Fbm.generate(64, 64, 3);
    for method in [Method::QDM, Method::POM] {
        let scene = mixed_scene(method);
        for msaa in [1, 4] {
            let what = format!("mixed scene, quad traced by {method}, {msaa} sample(s)");
            assert_same(&what, both(&ctx, &scene, &heights, &options(msaa)));
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn the_default_look_and_clamped_maps_keep_their_image() {
    let Some(ctx) = common::device("the_default_look_and_clamped_maps_keep_their_image") else {
        return;
    };
    let heights = default_heightfield();
    let scene = default_scene(Method::QDM);
    let look = RenderOptions::finished(192, 108);
    assert_same("default look", both(&ctx, &scene, &heights, &look));
    let clamped = options(1).with_address(Address::Clamp);
    assert_same(
        "clamp-addressed map",
        both(&ctx, &scene, &heights, &clamped),
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn the_plan_runs_the_pass_only_where_it_can_skip_a_trace() {
    let Some(ctx) = common::device("the_plan_runs_the_pass_only_where_it_can_skip_a_trace") else {
        return;
    };
    let heights = default_heightfield();
    let plans = |scene: &Scene, on: bool| {
        let opts = options(1).with_occluders(on);
        let renderer = Renderer::new(&ctx, scene, Some(&heights), &opts).expect("prepares");
        let plan = renderer.plan().clone();
        let runs = plan.passes.iter().any(|p| p.pass == Pass::Occluders);
        let skipped = plan
            .skipped
            .iter()
            .find(|s| s.what == Pass::Occluders.name())
            .map(|s| s.why.clone());
        (runs, skipped)
    };
    let scene = default_scene(Method::QDM);
    let (runs, skipped) = plans(&scene, true);
    assert!(
        runs && skipped.is_none(),
        "the default scene has relief to skip"
    );
    let (runs, skipped) = plans(&scene, false);
    assert!(!runs, "--occluders off ran the pass");
    assert!(
        skipped.is_some_and(|why| why.contains("--occluders off")),
        "--occluders off is not said"
    );
    let mut flat = scene.clone();
    for material in &mut flat.materials {
        material.relief = None;
    }
    let (runs, skipped) = plans(&flat, true);
    assert!(!runs, "a scene without relief ran the pass");
    assert!(
        skipped.is_some_and(|why| why.contains("no relief")),
        "a scene without relief does not say why the pass is left out"
    );
    common::assert_no_validation_errors(&ctx);
}
