//! Opens the built-in default scene in a window: drag to orbit, keys switch methods, shadows, AO
//! and LOD, and the title reads the GPU times (the keys are listed in `relief::view::controls`).
//!
//! ```sh
//! cargo run --release --example viewer                       # until the window is closed
//! cargo run --release --example viewer -- --frames 30 --screenshot last.png
//! ```
//!
//! `--frames N` closes after N presented frames and `--screenshot` writes the last one as read
//! back from the swapchain: the bounded run the tests use under Xvfb.

use std::path::PathBuf;

use anyhow::Context as _;
use relief::render::RenderOptions;
use relief::scene::{default_heightfield, default_scene, DEFAULT_SCENE_METHOD};
use relief::view::{self, ViewSetup};
use relief::vk::{ContextOptions, PresentMode};

fn main() -> anyhow::Result<()> {
    let (frames, screenshot) = parse_args()?;
    let setup = ViewSetup {
        scene: default_scene(DEFAULT_SCENE_METHOD),
        heights: Some(default_heightfield()),
        // The window's first size; the renderer follows the window when it is resized.
        options: RenderOptions::default().with_width(640).with_height(360),
        context: ContextOptions::default(),
        // A counted run should not wait on the display's refresh; an open-ended one should.
        present: if frames.is_some() {
            PresentMode::Unpaced
        } else {
            PresentMode::Vsync
        },
        frames,
        screenshot,
        resize_at: None,
    };
    // `run` owns the event loop until the window closes or the frames are counted.
    let report = view::run(setup)?;
    println!(
        "{} frame(s) on {}; last readout: {}",
        report.frames, report.device, report.readout
    );
    // The validation layer's findings come back in the report rather than as an error, so that
    // a caller decides whether they fail the run; here they do.
    anyhow::ensure!(
        report.validation_errors == 0,
        "the validation layer reported {} error(s): {:?}",
        report.validation_errors,
        report.validation_messages
    );
    Ok(())
}

/// `[--frames N [--screenshot PNG]]`.
fn parse_args() -> anyhow::Result<(Option<u64>, Option<PathBuf>)> {
    let (mut frames, mut screenshot) = (None, None);
    let mut args = std::env::args().skip(1);
    while let Some(arg) = args.next() {
        let value = args
            .next()
            .with_context(|| format!("{arg} needs a value"))?;
        match arg.as_str() {
            "--frames" => frames = Some(value.parse().context("--frames takes a number")?),
            "--screenshot" => screenshot = Some(PathBuf::from(value)),
            _ => anyhow::bail!("usage: viewer [--frames N [--screenshot PNG]]"),
        }
    }
    anyhow::ensure!(
        screenshot.is_none() || frames.is_some(),
        "--screenshot writes the last frame of a counted run: add --frames N"
    );
    Ok((frames, screenshot))
}
