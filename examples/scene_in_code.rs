//! Builds a scene in Rust, with no file: a box whose one material is displaced over a generated
//! fractal height field, lit by a low sun, rendered offscreen to a PNG.
//!
//! ```sh
//! cargo run --release --example scene_in_code -- [OUT.png] [--size WxH]
//! ```

use std::path::PathBuf;

use anyhow::Context as _;
use glam::Vec3;
use relief::heightfield::Generator;
use relief::method::Method;
use relief::render::{FrameRequest, RenderOptions, Renderer};
use relief::scene::{box_mesh, Camera, Light, Material, Relief, Scene, ShadowMode, ShadowSettings};
use relief::vk::{Context, ContextOptions};

fn main() -> anyhow::Result<()> {
    let (out, (width, height)) = parse_args()?;

    // Fractal noise fills [0, 1] and tiles, so every face of the box shows relief without a seam.
    let heights = Generator::Fbm.generate(256, 256, 7);
    let relief = Relief {
        // Soft shadows make the relief read as depth, not as a painted texture.
        shadows: ShadowSettings::new(ShadowMode::Cone),
        // Deep enough for the silhouette of the bumps to show at a grazing view.
        ..Relief::new(0.08, Method::QDM)
    };
    let stone = Material {
        name: "stone".into(),
        base_color: [0.55, 0.5, 0.45, 1.0],
        roughness: 0.8,
        relief: Some(relief),
        ..Material::default()
    };
    let scene = Scene {
        meshes: vec![box_mesh("block", Vec3::new(1.0, 0.5, 1.0), 0)], // material 0: `stone`
        materials: vec![stone],
        camera: Some(Camera::look_at(
            Vec3::new(2.2, 1.8, 2.6),
            Vec3::ZERO,
            45f32.to_radians(),
            0.05,
            50.0,
        )),
        lights: vec![Light {
            casts_shadows: true,
            direction: -Vec3::new(-0.5, 0.5, 0.7).normalize(),
            ..Light::default_light()
        }],
        images: Vec::new(),
        camera_path: None,
    };

    let ctx = Context::new(&ContextOptions::default())?;
    let opts = RenderOptions::default()
        .with_width(width)
        .with_height(height);
    // The frame's height map displaces every material whose relief reads it (`Relief::new`'s).
    let mut renderer = Renderer::new(&ctx, &scene, Some(&heights), &opts)?;
    let frame = renderer.draw(&FrameRequest::new(renderer.default_camera()))?;
    // sRGB RGBA8, rows top to bottom: what a PNG holds, byte for byte.
    let rgba = frame.rgba.context("the frame was asked to be read back")?;
    let png = image::RgbaImage::from_raw(frame.width, frame.height, rgba).context("frame size")?;
    png.save(&out)
        .with_context(|| format!("writing {}", out.display()))?;
    println!("wrote {}x{} {}", frame.width, frame.height, out.display());
    // Debug builds load the Khronos validation layer (RELIEF_VALIDATION=0 turns it off): what it
    // finds is a bug, so it fails the run.
    ctx.messages().ensure_none()?;
    Ok(())
}

/// `[OUT.png] [--size WxH]`: the output defaults to `scene.png` at 640x360.
fn parse_args() -> anyhow::Result<(PathBuf, (u32, u32))> {
    let (mut out, mut size) = (PathBuf::from("scene.png"), (640, 360));
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        if arg == "--size" {
            let text = args.next().context("--size needs WxH")?;
            let (w, h) = text.split_once('x').context("--size is WxH")?;
            size = (w.parse()?, h.parse()?);
        } else {
            out = PathBuf::from(arg);
        }
    }
    Ok((out, size))
}
