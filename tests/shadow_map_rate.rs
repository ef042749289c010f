//! Shadow maps at their own rate: a frame renders the atlas only when a view moved or the casters
//! changed, and a frame that reads the maps an earlier frame left is the image a fresh renderer
//! draws of the same view, bit for bit.

mod common;

use relief::method::Method;
use relief::render::{FrameOutput, FrameRequest, Pass, RenderOptions, Renderer};
use relief::scene::{default_heightfield, default_scene, Camera, Scene};

fn opts() -> RenderOptions {
    RenderOptions::default().with_width(96).with_height(54)
}

fn scene() -> Scene {
    default_scene("qdm".parse::<Method>().expect("qdm"))
}

fn renders_maps(frame: &FrameOutput) -> bool {
    frame.timings.iter().any(|t| t.pass == Pass::ShadowMaps)
}

/// The image a new renderer draws of `camera`: its maps rendered for this view alone.
fn fresh_image(ctx: &std::sync::Arc<relief::vk::Context>, camera: Camera) -> Vec<u8> {
    let hf = default_heightfield();
    let mut renderer = Renderer::new(ctx, &scene(), Some(&hf), &opts()).expect("prepares");
    let frame = renderer.draw(&FrameRequest::new(camera)).expect("draws");
    assert!(renders_maps(&frame), "a first frame renders its maps");
    frame.rgba.expect("read back")
}

fn draw_all(renderer: &mut Renderer, cameras: &[Camera]) -> Vec<FrameOutput> {
    let mut frames = Vec::new();
    for &camera in cameras {
        let request = FrameRequest::new(camera);
        frames.extend(renderer.submit(&request).expect("submits"));
    }
    frames.extend(renderer.finish().expect("finishes"));
    frames
}

#[test]
fn a_still_sequence_renders_its_shadow_maps_once() {
    let Some(ctx) = common::device("a_still_sequence_renders_its_shadow_maps_once") else {
        return;
    };
    let hf = default_heightfield();
    let mut renderer = Renderer::new(&ctx, &scene(), Some(&hf), &opts()).expect("prepares");
    assert!(
        !renderer.plan().shadow_maps.is_empty(),
        "the default scene's sun has a map"
    );
    let camera = renderer.default_camera();
    let frames = draw_all(&mut renderer, &[camera; 5]);
    let rendered: Vec<bool> = frames.iter().map(renders_maps).collect();
    assert_eq!(rendered, [true, false, false, false, false]);
    let first = frames[0].rgba.as_ref().expect("read back");
    for (k, frame) in frames.iter().enumerate().skip(1) {
        assert!(
            frame.rgba.as_ref() == Some(first),
            "frame {k}, drawn over the first frame's maps, differs from it"
        );
    }
    assert!(
        frames[4].rgba.as_ref() == Some(&fresh_image(&ctx, camera)),
        "a frame over kept maps differs from a fresh render of the same view"
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn moved_views_and_changed_casters_render_the_maps_again() {
    let Some(ctx) = common::device("moved_views_and_changed_casters_render_the_maps_again") else {
        return;
    };
    let scene = scene();
    let hf = default_heightfield();
    let mut renderer = Renderer::new(&ctx, &scene, Some(&hf), &opts()).expect("prepares");
    let start = renderer.default_camera();
    // The sun's cascade is fitted to the camera's frustum: turning the camera moves it.
    let turned = start.orbited(glam::Vec3::ZERO, 40f32.to_radians());
    let frames = draw_all(&mut renderer, &[start, turned, turned]);
    let rendered: Vec<bool> = frames.iter().map(renders_maps).collect();
    assert_eq!(rendered, [true, true, false]);
    assert!(
        frames[2].rgba == Some(fresh_image(&ctx, turned)),
        "after the camera turned, the frame differs from a fresh render of its view"
    );
    // The same vertices uploaded again: the renderer cannot tell, so it renders the maps again.
    renderer
        .update_meshes(&[(0, &scene.meshes[0])])
        .expect("updates");
    let frames = draw_all(&mut renderer, &[turned, turned]);
    let rendered: Vec<bool> = frames.iter().map(renders_maps).collect();
    assert_eq!(rendered, [true, false]);
    common::assert_no_validation_errors(&ctx);
}
