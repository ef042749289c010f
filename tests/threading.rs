//! The threading model (docs/architecture.md, "Threads"): the types an engine shares are `Send`
//! and `Sync`; renderers on one context draw on several threads at once and each draws what it
//! draws alone; a renderer dropped while another submits takes nothing of the other with it;
//! ray queries run from several threads at once. All under validation.

mod common;

use std::sync::Arc;

use relief::render::{
    trace_occlusion, FrameRequest, OcclusionRay, RenderOptions, Renderer, TracedScene,
};
use relief::scene::{
    default_heightfield, default_scene, shadow_scene, ShadowScene, DEFAULT_SCENE_METHOD,
};
use relief::shadow_reference::SceneOccluders;
use relief::vk::{AccelerationStructure, Buffer, Context, Image};

fn shared<T: Send + Sync>() {}

#[test]
fn the_types_an_engine_shares_are_send_and_sync() {
    // Fails to compile, not at run time, when one of them stops being shareable.
    shared::<Context>();
    shared::<Buffer>();
    shared::<Image>();
    shared::<AccelerationStructure>();
    shared::<Renderer>();
    shared::<TracedScene>();
}

fn options() -> RenderOptions {
    RenderOptions::default().with_width(64).with_height(36)
}

/// `frames` frames of the default scene from one renderer, the last read back.
fn draw(ctx: &Arc<Context>, frames: u32) -> Vec<u8> {
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let mut renderer =
        Renderer::new(ctx, &scene, Some(&default_heightfield()), &options()).expect("prepares");
    let camera = renderer.default_camera();
    let mut last = Vec::new();
    for k in 0..frames {
        let request = FrameRequest::new(camera).with_read_back(k + 1 == frames);
        let out = renderer.draw(&request).expect("draws");
        if let Some(rgba) = out.rgba {
            last = rgba;
        }
    }
    last
}

fn assert_same_image(a: &[u8], b: &[u8], what: &str) {
    assert_eq!(a.len(), b.len(), "{what}");
    let worst = a
        .iter()
        .zip(b)
        .map(|(x, y)| x.abs_diff(*y))
        .max()
        .unwrap_or(0);
    assert!(worst <= 1, "{what}: a channel differs by {worst}");
}

#[test]
fn renderers_on_one_context_draw_on_several_threads_as_they_draw_alone() {
    let Some(ctx) = common::device("renderers_on_one_context_draw_on_several_threads") else {
        return;
    };
    let alone = draw(&ctx, 3);
    let together: Vec<Vec<u8>> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..3).map(|_| s.spawn(|| draw(&ctx, 3))).collect();
        workers
            .into_iter()
            .map(|w| w.join().expect("a renderer thread panicked"))
            .collect()
    });
    for (k, image) in together.iter().enumerate() {
        assert_same_image(&alone, image, &format!("thread {k}"));
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn a_renderer_dropped_while_another_submits_takes_nothing_with_it() {
    let Some(ctx) = common::device("a_renderer_dropped_while_another_submits") else {
        return;
    };
    let alone = draw(&ctx, 2);
    let busy = std::thread::scope(|s| {
        let worker = s.spawn(|| draw(&ctx, 12));
        // Meanwhile renderers come and go on this thread, each dropped with a frame of its own
        // in flight.
        let scene = default_scene(DEFAULT_SCENE_METHOD);
        for _ in 0..4 {
            let mut r = Renderer::new(&ctx, &scene, Some(&default_heightfield()), &options())
                .expect("prepares");
            let camera = r.default_camera();
            r.submit(&FrameRequest::new(camera).with_read_back(false))
                .expect("submits");
            drop(r);
        }
        worker.join().expect("the drawing thread panicked")
    });
    assert_same_image(&alone, &busy, "the renderer that kept drawing");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn ray_queries_run_from_several_threads_at_once() {
    let Some(ctx) = common::ray_query_device("ray_queries_run_from_several_threads_at_once") else {
        return;
    };
    let kind = ShadowScene::SlabOverPlane;
    let scene = shadow_scene(kind, 25.0, 0.0);
    let heights = default_heightfield().quantized_unorm16();
    let occ = SceneOccluders::new(&scene, Some(&heights), kind.address()).expect("occluders");
    let traced = TracedScene::new(&ctx, &occ).expect("structures");
    // A fan of rays down through the slab and beside it.
    let rays: Vec<OcclusionRay> = (0..2048)
        .map(|k| {
            let x = -3.0 + 6.0 * (k as f32 + 0.5) / 2048.0;
            OcclusionRay {
                origin: glam::Vec3::new(x, 4.0, 0.3),
                t_min: 0.0,
                dir: glam::Vec3::new(0.2, -1.0, 0.1).normalize(),
                t_max: 10.0,
            }
        })
        .collect();
    let alone = trace_occlusion(&ctx, &traced, &rays).expect("traced");
    let together: Vec<Vec<bool>> = std::thread::scope(|s| {
        let workers: Vec<_> = (0..4)
            .map(|_| {
                s.spawn(|| {
                    trace_occlusion(&ctx, &traced, &rays)
                        .expect("traced")
                        .blocked
                })
            })
            .collect();
        workers
            .into_iter()
            .map(|w| w.join().expect("a tracing thread panicked"))
            .collect()
    });
    for blocked in &together {
        assert_eq!(blocked, &alone.blocked);
    }
    assert!(alone.blocked.iter().any(|&b| b) && alone.blocked.iter().any(|&b| !b));
    common::assert_no_validation_errors(&ctx);
}
