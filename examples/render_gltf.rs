//! Renders a glTF file offscreen to a PNG through the `Renderer` API.
//!
//! ```sh
//! cargo run --release --example render_gltf -- [SCENE.gltf] [OUT.png] [--size WxH]
//! ```
//!
//! With no scene it draws the built-in default scene, so it runs with no outside data. A glTF
//! scene's materials all get relief from a generated brick field, as `relief render --heightmap`
//! would give them.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use relief::heightfield::{Generator, Heightfield};
use relief::method::Method;
use relief::render::{FrameRequest, RenderOptions, Renderer};
use relief::scene::{
    default_heightfield, default_scene, load_gltf, Scene, SceneOptions, DEFAULT_SCENE_METHOD,
};
use relief::vk::{Context, ContextOptions};

fn main() -> anyhow::Result<()> {
    let (scene_path, out, (width, height)) = parse_args()?;
    let (scene, heights) = match &scene_path {
        Some(path) => gltf_with_relief(path)?,
        None => (default_scene(DEFAULT_SCENE_METHOD), default_heightfield()),
    };

    let ctx = Context::new(&ContextOptions::default())?;
    let opts = RenderOptions::default()
        .with_width(width)
        .with_height(height);
    // Building the renderer uploads the meshes and builds every map the scene's methods read;
    // each frame after that only records and submits.
    let mut renderer = Renderer::new(&ctx, &scene, Some(&heights), &opts)?;
    let request = FrameRequest::new(renderer.default_camera());
    // `draw` waits for its own frame: the simplest call for one image (`submit` overlaps frames).
    let frame = renderer.draw(&request)?;
    // sRGB RGBA8, rows top to bottom: what a PNG holds, byte for byte.
    let rgba = frame.rgba.context("the frame was asked to be read back")?;
    let png = image::RgbaImage::from_raw(frame.width, frame.height, rgba).context("frame size")?;
    png.save(&out)
        .with_context(|| format!("writing {}", out.display()))?;

    for t in &frame.timings {
        println!("{:>12}: {:.3} GPU ms", t.pass, t.gpu_ms);
    }
    println!("wrote {}x{} {}", frame.width, frame.height, out.display());
    // Debug builds load the Khronos validation layer (RELIEF_VALIDATION=0 turns it off): what it
    // finds is a bug, so it fails the run.
    ctx.messages().ensure_none()?;
    Ok(())
}

/// A glTF scene with relief on every material, over a 256x256 brick field.
fn gltf_with_relief(path: &Path) -> anyhow::Result<(Scene, Heightfield)> {
    let mut scene = load_gltf(path, &SceneOptions::default())
        .with_context(|| format!("loading {}", path.display()))?;
    // Depth in uv units of the height map: 0.05 is deep enough to see, shallow enough to stay
    // plausible on any scale of uv mapping.
    scene.apply_relief(0.05, Method::POM, None);
    Ok((scene, Generator::Bricks.generate(256, 256, 1)))
}

/// `[SCENE] [OUT.png] [--size WxH]` in any order: a `.png` path is the output (default
/// `frame.png`), any other the scene; the size defaults to 640x360.
fn parse_args() -> anyhow::Result<(Option<PathBuf>, PathBuf, (u32, u32))> {
    let (mut scene, mut out, mut size) = (None, PathBuf::from("frame.png"), (640, 360));
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let path = PathBuf::from(&arg);
        if arg == "--size" {
            let text = args.next().context("--size needs WxH")?;
            let (w, h) = text.split_once('x').context("--size is WxH")?;
            size = (w.parse()?, h.parse()?);
        } else if path
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("png"))
        {
            out = path;
        } else {
            scene = Some(path);
        }
    }
    Ok((scene, out, size))
}
