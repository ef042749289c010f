//! `relief view`: the scene in a window, with the render flags; `--frames N --screenshot PNG`
//! runs N frames through the swapchain and writes the last one, for headless checks.

use std::path::PathBuf;

use anyhow::Context as _;
use clap::Args;
use relief::heightfield::MAX_SIDE;
use relief::view::{self, ViewError, ViewSetup};
use relief::vk::{ContextOptions, PresentMode};

use super::scene_args::SceneArgs;

#[derive(Args)]
pub struct ViewArgs {
    #[command(flatten)]
    scene: SceneArgs,
    /// Present as fast as frames are drawn instead of waiting for the display (vsync is on by default).
    #[arg(long)]
    no_vsync: bool,
    /// Close after this many presented frames.
    #[arg(long, value_name = "N", value_parser = clap::value_parser!(u64).range(1..))]
    frames: Option<u64>,
    /// With --frames: write the last frame, as read back from the swapchain, to this PNG.
    #[arg(long, value_name = "PNG", requires = "frames")]
    screenshot: Option<PathBuf>,
    /// Ask the window for another size after N frames (WxH), as a user dragging its border would;
    /// frames are counted again once it has that size.
    #[arg(long, value_name = "N:WxH", value_parser = parse_resize)]
    resize_at: Option<(u64, (u32, u32))>,
}

fn parse_resize(text: &str) -> Result<(u64, (u32, u32)), String> {
    let bad = || format!("expected N:WxH (e.g. 10:640x360), got {text:?}");
    let (at, size) = text.split_once(':').ok_or_else(bad)?;
    let (w, h) = super::parse_wxh(size).ok_or_else(bad)?;
    let at: u64 = at.parse().map_err(|_| bad())?;
    if !super::within_max_side(w, h) {
        return Err(format!(
            "the size must be within 1..={MAX_SIDE} each way, got {w}x{h}"
        ));
    }
    Ok((at, (w, h)))
}

pub fn run(args: &ViewArgs) -> anyhow::Result<()> {
    let loaded = args.scene.load()?;
    if loaded.edits.is_some() {
        anyhow::bail!("--edits replays strokes over a frame sequence: use it with relief render");
    }
    let setup = ViewSetup {
        scene: loaded.scene,
        heights: loaded.heights,
        options: args
            .scene
            .render_options(args.scene.width, args.scene.height),
        context: ContextOptions::default().with_device_filter(args.scene.device.clone()),
        present: if args.no_vsync {
            PresentMode::Unpaced
        } else {
            PresentMode::Vsync
        },
        frames: args.frames,
        screenshot: args.screenshot.clone(),
        resize_at: args.resize_at,
    };
    let report = match view::run(setup) {
        Err(e @ ViewError::NoDisplay(_)) => anyhow::bail!("{e}"),
        other => other.context("relief view")?,
    };
    eprintln!(
        "{} frame(s) on {}; last readout: {}",
        report.frames, report.device, report.readout
    );
    if report.validation_errors > 0 {
        anyhow::bail!(
            "the validation layer reported {} error(s); first: {}",
            report.validation_errors,
            report
                .validation_messages
                .first()
                .map_or("", String::as_str)
        );
    }
    Ok(())
}
