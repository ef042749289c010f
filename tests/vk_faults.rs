//! Faults feigned through `ContextOptions::faults` while the default scene is prepared and drawn:
//! an allocation that fails halfway through the uploads, a device lost at a submission with
//! frames in flight, a submission whose fence never signals. Each must end in an error that
//! says what happened, with no panic; after the first two every Vulkan object the renderer made
//! is destroyed again (the context counts them), under validation.

mod common;

use std::sync::Arc;
use std::time::Duration;

use relief::method::Method;
use relief::render::{FrameRequest, RenderOptions, Renderer};
use relief::scene::{default_heightfield, default_scene};
use relief::vk::{Context, ContextOptions, Faults, LiveObjects};

const FRAMES: u32 = 12;

fn context(test: &str, faults: Faults, timeout: Option<Duration>) -> Option<Arc<Context>> {
    let options = ContextOptions::default()
        .with_faults(Some(faults))
        .with_gpu_timeout(timeout);
    common::device_with(test, &options)
}

fn options() -> RenderOptions {
    RenderOptions::default().with_width(96).with_height(54)
}

/// Prepares the default scene and draws [`FRAMES`] orbiting frames; the first error, as text.
fn draw(ctx: &Arc<Context>) -> Result<(), String> {
    let qdm: Method = "qdm".parse().expect("qdm");
    let scene = default_scene(qdm);
    let hf = default_heightfield();
    let mut renderer =
        Renderer::new(ctx, &scene, Some(&hf), &options()).map_err(|e| format!("{e:#}"))?;
    let start = renderer.default_camera();
    for k in 0..FRAMES {
        let request =
            FrameRequest::new(start.orbited(glam::Vec3::ZERO, (10.0 * k as f32).to_radians()));
        renderer.submit(&request).map_err(|e| format!("{e:#}"))?;
    }
    renderer.finish().map_err(|e| format!("{e:#}"))?;
    Ok(())
}

/// The live objects apart from what the context itself keeps, after the device went idle.
fn settled(ctx: &Context) -> LiveObjects {
    ctx.wait_idle().expect("the device goes idle");
    ctx.alive()
}

/// How many allocations preparing and drawing the scene makes, counted on a healthy context.
fn allocations_of_a_whole_run(ctx: &Arc<Context>) -> u64 {
    let qdm: Method = "qdm".parse().expect("qdm");
    let renderer = Renderer::new(
        ctx,
        &default_scene(qdm),
        Some(&default_heightfield()),
        &options(),
    )
    .expect("prepares");
    let made = ctx.alive().allocations;
    drop(renderer);
    made
}

#[test]
fn an_allocation_failing_during_the_uploads_is_an_out_of_memory_error_and_leaks_nothing() {
    let test =
        "an_allocation_failing_during_the_uploads_is_an_out_of_memory_error_and_leaks_nothing";
    let Some(healthy) = context(test, Faults::default(), None) else {
        return;
    };
    let total = allocations_of_a_whole_run(&healthy);
    drop(healthy);
    assert!(total >= 4, "the renderer allocates: {total}");
    // The first, one in the middle of the uploads, the last.
    for k in [1, total / 2, total] {
        let faults = Faults {
            fail_allocation: Some(k),
            ..Faults::default()
        };
        let ctx = context(test, faults, None).expect("a device, as above");
        let before = settled(&ctx);
        let err = draw(&ctx).expect_err("the allocation fails");
        assert!(
            err.contains("out of device memory"),
            "allocation {k}: {err}"
        );
        assert_eq!(
            settled(&ctx),
            before,
            "allocation {k}: the failed renderer leaves objects"
        );
        common::assert_no_validation_errors(&ctx);
    }
}

#[test]
fn a_device_lost_at_a_submission_with_frames_in_flight_is_an_error_and_leaks_nothing() {
    let test = "a_device_lost_at_a_submission_with_frames_in_flight_is_an_error_and_leaks_nothing";
    for k in [1, 6, 10] {
        let faults = Faults {
            lose_device_at_submission: Some(k),
            ..Faults::default()
        };
        let Some(ctx) = context(test, faults, None) else {
            return;
        };
        let before = settled(&ctx);
        let err = draw(&ctx).expect_err("the device is lost");
        assert!(
            err.contains("vkQueueSubmit") && err.contains("device was lost"),
            "submission {k}: {err}"
        );
        assert_eq!(
            settled(&ctx),
            before,
            "submission {k}: the lost renderer leaves objects"
        );
        common::assert_no_validation_errors(&ctx);
    }
}

#[test]
fn a_submission_that_never_signals_ends_in_the_gpu_timeout() {
    let faults = Faults {
        hang_at_submission: Some(6),
        ..Faults::default()
    };
    let timeout = Some(Duration::from_millis(300));
    let Some(ctx) = context(
        "a_submission_that_never_signals_ends_in_the_gpu_timeout",
        faults,
        timeout,
    ) else {
        return;
    };
    let err = draw(&ctx).expect_err("the fence never signals");
    assert!(
        err.contains("did not finish") && err.contains("0.3 s"),
        "{err}"
    );
    // After a hang the context leaves the device and what the hung work uses to the process
    // exit (destroying them could crash a real driver), so only the verdict is checked.
    assert!(ctx.is_hung());
    common::assert_no_validation_errors(&ctx);
}
