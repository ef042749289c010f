//! relief's methods without relief's renderer: a relief quad drawn by the example's own raw-`ash`
//! pipeline, whose shaders include only the shader library (`relief::shader_library`), over a
//! height image built by the library's CPU map builder. It also writes the library's files into
//! a folder, the way an engine would hand them to its own shader compiler.
//!
//! ```sh
//! cargo run --release --example shader_library -- [OUT.png] [--size WxH] [--glsl DIR] [--reverse-z]
//! ```

mod quad;

use std::path::PathBuf;

use anyhow::Context as _;
use glam::Vec3;
use relief::heightfield::Generator;
use relief::vk::{Context, ContextOptions};

fn main() -> anyhow::Result<()> {
    let args = Args::parse()?;
    if let Some(dir) = &args.glsl {
        let written = relief::shader_library::write_to(dir)
            .with_context(|| format!("writing the shader library into {}", dir.display()))?;
        println!(
            "wrote {} library files into {}",
            written.len(),
            dir.display()
        );
    }
    let ctx = Context::new(&ContextOptions::default())?;
    let heights = Generator::Fbm.generate(256, 256, 7);
    let view = quad::QuadView {
        eye: Vec3::new(0.0, 1.1, 2.2),
        target: Vec3::ZERO,
        yfov: 45f32.to_radians(),
        half: 1.0,
        depth_scale: 0.08,
        width: args.width,
        height: args.height,
        reverse_z: args.reverse_z,
    };
    let images = quad::draw_quad(&ctx, &heights, &view)?;
    let png =
        image::RgbaImage::from_raw(args.width, args.height, images.rgba).context("frame size")?;
    png.save(&args.out)
        .with_context(|| format!("writing {}", args.out.display()))?;
    // The depth attachment holds the displaced depth, in the view's convention.
    let far = if view.reverse_z { 0.0 } else { 1.0 };
    let drawn = images.depth.iter().filter(|&&d| d != far);
    let (lo, hi) = drawn.fold((f32::MAX, f32::MIN), |(lo, hi), &d| (lo.min(d), hi.max(d)));
    println!(
        "depth attachment ({}): {lo:.6} to {hi:.6} where the quad is",
        if view.reverse_z {
            "reversed"
        } else {
            "standard"
        }
    );
    let steps: f32 = images.hits.iter().map(|h| h[2]).sum();
    let covered = images.hits.iter().filter(|h| h[3] > 0.0).count().max(1);
    println!(
        "wrote {}x{} {} (QDM, {:.1} steps per covered pixel)",
        args.width,
        args.height,
        args.out.display(),
        steps / covered as f32
    );
    // Debug builds load the Khronos validation layer when it is installed: what it finds is a bug.
    ctx.messages().ensure_none()?;
    Ok(())
}

/// `[OUT.png] [--size WxH] [--glsl DIR] [--reverse-z]`: the output defaults to
/// `library_quad.png` at 480x270; `--reverse-z` draws with depth reversed (1 near, 0 far).
struct Args {
    out: PathBuf,
    width: u32,
    height: u32,
    glsl: Option<PathBuf>,
    reverse_z: bool,
}

impl Args {
    fn parse() -> anyhow::Result<Args> {
        let mut args = Args {
            out: PathBuf::from("library_quad.png"),
            width: 480,
            height: 270,
            glsl: None,
            reverse_z: false,
        };
        let mut words = std::env::args().skip(1);
        while let Some(word) = words.next() {
            match word.as_str() {
                "--size" => {
                    let text = words.next().context("--size needs WxH")?;
                    let (w, h) = text.split_once('x').context("--size is WxH")?;
                    (args.width, args.height) = (w.parse()?, h.parse()?);
                }
                "--reverse-z" => args.reverse_z = true,
                "--glsl" => args.glsl = Some(words.next().context("--glsl needs a folder")?.into()),
                _ => args.out = PathBuf::from(word),
            }
        }
        Ok(args)
    }
}
