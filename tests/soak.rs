//! The short soak: a few hundred frames of the default scene with an orbiting camera, sampling
//! the process's resident memory and the live Vulkan objects, failing on growth after a warm-up
//! (a fitted slope). A renderer made to leak one frame-sized buffer a frame must fail it, so the
//! check can fail. On a driver known to leak every frame (lavapipe of Mesa before 23.0) it says
//! that it skipped, and why.

mod common;

use std::sync::Mutex;

use common::soak::{judge, sample, Limits, Sample};
use relief::method::Method;
use relief::render::{FrameRequest, RenderOptions, Renderer};
use relief::scene::{default_heightfield, default_scene};
use relief::vk::Context;

/// Resident memory is the whole process's: the two soaks must not run at once.
static ONE_AT_A_TIME: Mutex<()> = Mutex::new(());

const FRAMES: u32 = 300;
const EVERY: u32 = 10;
const WIDTH: u32 = 192;
const HEIGHT: u32 = 108;
/// Frames to settle in: allocators grow their pools, the driver its caches.
const WARM_UP: u32 = 100;
/// A frame's colour is 81 KiB at this size; lavapipe of Mesa 22.3 leaked about 5 MiB a frame.
const RSS_PER_FRAME: f64 = 16.0 * 1024.0;

/// Draws the soak's frames on `ctx` and returns its samples; `leak` makes the renderer keep a
/// frame-sized buffer every frame.
fn soak(ctx: &std::sync::Arc<Context>, leak: bool) -> Vec<Sample> {
    let qdm: Method = "qdm".parse().expect("qdm");
    let scene = default_scene(qdm);
    let hf = default_heightfield();
    let opts = RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT);
    let mut renderer = Renderer::new(ctx, &scene, Some(&hf), &opts).expect("prepares");
    if leak {
        renderer.leak_a_buffer_every_frame_for_tests();
    }
    let start = renderer.default_camera();
    let mut samples = Vec::new();
    let mut retired = 0u32;
    for k in 0..FRAMES {
        let request =
            FrameRequest::new(start.orbited(glam::Vec3::ZERO, (1.5 * k as f32).to_radians()));
        let frame = renderer.submit(&request).expect("submits");
        retired += u32::from(frame.is_some());
        if retired > 0 && retired % EVERY == 0 && frame.is_some() {
            samples.push(sample(ctx, retired));
        }
    }
    renderer.finish().expect("finishes");
    samples
}

fn limits() -> Limits {
    Limits {
        warm_up: WARM_UP,
        rss_per_frame: RSS_PER_FRAME,
    }
}

/// The device, or `None` with the reason printed when the soak cannot judge it.
fn soak_device(test: &str) -> Option<std::sync::Arc<Context>> {
    let ctx = common::device(test)?;
    if let Some(why) = &ctx.info().known_frame_leak {
        eprintln!("SKIPPED: {test}: {why} (scripts/setup.sh upgrades it)");
        return None;
    }
    Some(ctx)
}

fn print(samples: &[Sample]) {
    for s in samples {
        eprintln!("{s}");
    }
}

#[test]
fn a_still_scene_holds_memory_and_objects_flat() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let Some(ctx) = soak_device("a_still_scene_holds_memory_and_objects_flat") else {
        return;
    };
    let samples = soak(&ctx, false);
    print(&samples);
    if let Err(why) = judge(&samples, limits()) {
        panic!("the default scene's frames leak: {why}");
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn a_renderer_that_keeps_a_buffer_a_frame_fails_the_soak() {
    let _one = ONE_AT_A_TIME.lock().unwrap_or_else(|p| p.into_inner());
    let Some(ctx) = soak_device("a_renderer_that_keeps_a_buffer_a_frame_fails_the_soak") else {
        return;
    };
    let samples = soak(&ctx, true);
    print(&samples);
    let why = judge(&samples, limits()).expect_err("a leak of one buffer a frame went unseen");
    for grown in ["rss", "buffers", "allocated_bytes"] {
        assert!(
            why.contains(&format!("{grown} grows")),
            "the soak missed the growth of {grown}: {why}"
        );
    }
    common::assert_no_validation_errors(&ctx);
}
