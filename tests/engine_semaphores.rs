//! A frame ordered by an engine's own semaphores (`Renderer::submit_synced` with
//! `vk::Semaphore::borrowed`): the engine's submission signals a semaphore the frame waits on,
//! the frame signals one the engine's next submission waits on, and that submission copies the
//! frame's colour target into the engine's image. The copy holds the frame the renderer draws
//! for the same camera, byte for byte, and the validation layer (which checks every wait
//! against a signal) reports nothing.

mod common;

use glam::Vec3;
use relief::heightfield::Generator;
use relief::method::Method;
use relief::render::{FrameRequest, RenderOptions, Renderer};
use relief::scene::{quad_mesh, Camera, Material, Relief, Scene};
use relief::vk::raw as vk;
use relief::vk::{
    read_mip, transition_images, CommandSlot, Image, ImageDesc, ImageTransition, Recording,
    Semaphore, SubmitSync,
};

const WIDTH: u32 = 96;
const HEIGHT: u32 = 64;

fn scene() -> Scene {
    Scene {
        meshes: vec![quad_mesh("quad", 2.0, 2.0, 1.0, 0)],
        materials: vec![Material {
            name: "quad".into(),
            relief: Some(Relief::new(0.06, Method::QDM)),
            ..Material::default()
        }],
        camera: Some(Camera::look_at(
            Vec3::new(0.2, 1.0, 1.8),
            Vec3::ZERO,
            45f32.to_radians(),
            0.05,
            50.0,
        )),
        ..Scene::default()
    }
}

/// The engine's raw binary semaphore.
fn engine_semaphore(device: &ash::Device) -> vk::Semaphore {
    // SAFETY: a valid device; the test destroys the semaphore once the device is idle.
    unsafe { device.create_semaphore(&vk::SemaphoreCreateInfo::default(), None) }
        .expect("the engine makes a semaphore")
}

/// The engine's copy: the renderer's colour target (left by the frame in the colour attachment
/// layout, and given back in it) blitted into the engine's image, left as a copy source.
fn record_copy(rec: &Recording, frame: &Image, engine: &Image) {
    use vk::ImageLayout as L;
    let blit = vk::PipelineStageFlags2::BLIT;
    let written = (
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
    );
    let nothing = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
    let read = (blit, vk::AccessFlags2::TRANSFER_READ);
    let write = (blit, vk::AccessFlags2::TRANSFER_WRITE);
    transition_images(
        rec,
        &[
            ImageTransition::color(
                frame,
                (L::COLOR_ATTACHMENT_OPTIMAL, L::TRANSFER_SRC_OPTIMAL),
                written,
                read,
            ),
            ImageTransition::color(
                engine,
                (L::UNDEFINED, L::TRANSFER_DST_OPTIMAL),
                nothing,
                write,
            ),
        ],
    );
    rec.blit_whole(frame, engine);
    let next_frame = (
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
    );
    let copy_out = (
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ,
    );
    transition_images(
        rec,
        &[
            ImageTransition::color(
                frame,
                (L::TRANSFER_SRC_OPTIMAL, L::COLOR_ATTACHMENT_OPTIMAL),
                read,
                next_frame,
            ),
            ImageTransition::color(
                engine,
                (L::TRANSFER_DST_OPTIMAL, L::TRANSFER_SRC_OPTIMAL),
                write,
                copy_out,
            ),
        ],
    );
}

#[test]
fn a_frame_waits_on_and_signals_the_engine_s_semaphores() {
    let test = "a_frame_waits_on_and_signals_the_engine_s_semaphores";
    let Some(ctx) = common::device(test) else {
        return;
    };
    let heights = Generator::Fbm.generate(64, 64, 5);
    let scene = scene();
    let opts = RenderOptions::default()
        .with_size(WIDTH, HEIGHT)
        .with_msaa(1);
    let mut renderer = Renderer::new(&ctx, &scene, Some(&heights), &opts).expect("renderer");
    let camera = renderer.default_camera();

    let device = ctx.device().clone();
    let (before_raw, after_raw) = (engine_semaphore(&device), engine_semaphore(&device));
    // SAFETY: both are binary semaphores of ctx's device, destroyed below only once the device
    // is idle; each wait below follows the signal submitted before it.
    let (before, after) = unsafe {
        (
            Semaphore::borrowed(&ctx, before_raw),
            Semaphore::borrowed(&ctx, after_raw),
        )
    };
    let engine_image = Image::new(
        &ctx,
        ImageDesc {
            width: WIDTH,
            height: HEIGHT,
            format: vk::Format::R8G8B8A8_SRGB,
            mip_levels: 1,
            // Sampled: what the engine does with the frame next.
            usage: vk::ImageUsageFlags::TRANSFER_DST
                | vk::ImageUsageFlags::TRANSFER_SRC
                | vk::ImageUsageFlags::SAMPLED,
            aspect: vk::ImageAspectFlags::COLOR,
        },
        "engine image",
    )
    .expect("the engine's image");
    let mut engine = CommandSlot::new(&ctx, "engine commands").expect("engine command slot");

    // The engine's work before the frame: it signals `before`.
    let signal_before = SubmitSync {
        wait: None,
        signal: Some(&before),
    };
    engine
        .submit_synced(signal_before, |_| Ok(()))
        .expect("engine work before");
    let frame_sync = SubmitSync {
        wait: Some((&before, vk::PipelineStageFlags::TOP_OF_PIPE)),
        signal: Some(&after),
    };
    let request = FrameRequest::new(camera).with_read_back(false);
    renderer
        .submit_synced(&request, frame_sync)
        .expect("the frame submits");
    // The engine's copy waits on `after`, which the frame signals.
    let wait_after = SubmitSync {
        wait: Some((&after, vk::PipelineStageFlags::TRANSFER)),
        signal: None,
    };
    engine
        .submit_synced(wait_after, |rec| {
            record_copy(rec, renderer.color_target(), &engine_image);
            Ok(())
        })
        .expect("the engine's copy submits");
    engine.wait().expect("the engine's copy finishes");
    let copied = read_mip(
        &ctx,
        &engine_image,
        0,
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    )
    .expect("the engine's image reads back");
    renderer.finish().expect("the frame retires");

    let drawn = renderer
        .draw(&FrameRequest::new(camera))
        .expect("the same frame again");
    let rgba = drawn.rgba.expect("read back");
    assert_eq!(copied.len(), rgba.len());
    let differing = copied.iter().zip(&rgba).filter(|(a, b)| a != b).count();
    assert_eq!(
        differing, 0,
        "{differing} bytes of the engine's copy differ from the frame"
    );
    assert!(
        rgba.chunks_exact(4).any(|p| p[..3] != rgba[..3]),
        "the frame shows something"
    );

    drop(renderer);
    drop((before, after));
    ctx.wait_idle().expect("idle");
    // SAFETY: the device is idle, so no submission uses the engine's semaphores any more.
    unsafe {
        device.destroy_semaphore(before_raw, None);
        device.destroy_semaphore(after_raw, None);
    }
    common::assert_no_validation_errors(&ctx);
}
