//! The persistent renderer: resources made once and reused by every frame, the pyramid and the AO
//! map built by the first frame only, frames in flight that come back in order, and frames that equal the
//! one-shot render of the same view.

mod common;

use relief::method::Method;
use relief::render::{render, FrameRequest, Pass, RenderOptions, Renderer};
use relief::scene::{default_heightfield, default_scene};

/// The bench's plain frame, small.
fn opts() -> RenderOptions {
    RenderOptions::default().with_size(96, 54)
}

#[test]
fn frames_reuse_every_resource_and_build_the_pyramid_once() {
    let Some(ctx) = common::device("frames_reuse_every_resource") else {
        return;
    };
    let qdm: Method = "qdm".parse().expect("qdm");
    let scene = default_scene(qdm);
    let hf = default_heightfield();
    let mut renderer = Renderer::new(&ctx, &scene, Some(&hf), &opts()).expect("prepares");
    let center = glam::Vec3::ZERO;
    let start = renderer.default_camera();
    let frames = 8u32;
    let mut outputs = Vec::new();
    let mut after_first = None;
    for k in 0..frames {
        let request = FrameRequest::new(start.orbited(center, (45.0 * k as f32).to_radians()))
            .with_read_back(k % 2 == 0);
        outputs.extend(renderer.submit(&request).expect("submits"));
        after_first.get_or_insert_with(|| ctx.created());
    }
    outputs.extend(renderer.finish().expect("finishes"));
    assert_eq!(
        ctx.created(),
        after_first.unwrap(),
        "frames 2..{frames} created Vulkan objects"
    );
    let indices: Vec<u64> = outputs.iter().map(|f| f.index).collect();
    assert_eq!(indices, (0..u64::from(frames)).collect::<Vec<_>>());
    let has = |k: usize, pass| outputs[k].timings.iter().any(|t| t.pass == pass);
    assert!(has(0, Pass::Pyramid), "the first frame builds the pyramid");
    assert!(
        has(0, Pass::AmbientOcclusion),
        "the first frame builds the AO map"
    );
    for k in 1..frames as usize {
        assert!(
            !has(k, Pass::Pyramid),
            "frame {k} rebuilt the static pyramid"
        );
        assert!(
            !has(k, Pass::AmbientOcclusion),
            "frame {k} rebuilt the static AO map"
        );
        assert!(has(k, Pass::Surface), "frame {k} has no surface time");
    }
    for (k, frame) in outputs.iter().enumerate() {
        assert_eq!(frame.rgba.is_some(), k % 2 == 0, "frame {k} read back?");
    }
    // Eight 45-degree steps: frames 0 and 4 look at the slab from opposite sides.
    let (mean, _, _) = common::golden::compare(
        outputs[0].rgba.as_ref().unwrap(),
        outputs[4].rgba.as_ref().unwrap(),
    );
    assert!(
        mean > 2.0,
        "the orbit did not move the camera (mean {mean:.2})"
    );
    let kinds: Vec<&str> = renderer.maps().iter().map(|m| m.kind).collect();
    assert_eq!(kinds, ["max_pyramid", "ao"], "{:?}", renderer.maps());
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn a_frame_of_the_renderer_equals_the_one_shot_render_of_its_view() {
    let Some(ctx) = common::device("frame_equals_one_shot") else {
        return;
    };
    let hf = default_heightfield();
    let relief = default_scene(Method::POM);
    // Without relief every draw uses the plain variant, whose uniforms are the pass's own.
    let mut plain = default_scene(Method::POM);
    plain.materials.iter_mut().for_each(|m| m.relief = None);
    for (name, scene) in [("relief", relief), ("plain", plain)] {
        let one_shot = render(&ctx, &scene, Some(&hf), &opts()).expect("renders");
        let mut renderer = Renderer::new(&ctx, &scene, Some(&hf), &opts()).expect("prepares");
        let camera = renderer.default_camera();
        let away = camera.orbited(glam::Vec3::ZERO, 1.0);
        let mut frames = Vec::new();
        // Another view in between: a stale uniform or descriptor slot would show in frame 3.
        for cam in [camera, away, camera] {
            let request = FrameRequest::new(cam);
            frames.extend(renderer.submit(&request).expect("submits"));
        }
        frames.extend(renderer.finish().expect("finishes"));
        let rgba: Vec<Vec<u8>> = frames
            .into_iter()
            .map(|f| f.rgba.expect("read back"))
            .collect();
        assert_eq!(rgba.len(), 3);
        assert!(
            rgba[0] == one_shot.rgba,
            "{name}: frame 1 differs from the one-shot render"
        );
        assert!(rgba[2] == rgba[0], "{name}: same view, different pixels");
        let (moved, _, _) = common::golden::compare(&rgba[1], &rgba[0]);
        assert!(
            moved > 1.0,
            "{name}: the second view did not differ (mean {moved:.2})"
        );
    }
    common::assert_no_validation_errors(&ctx);
}
