//! The long soak, ignored by default (`tests/soak.rs` is its CI form): frames of the default
//! scene and of the terrain scene at 480x270, one of each a step, with an orbiting camera, a
//! terrain stroke every few steps, a resize every few hundred and both renderers rebuilt every
//! few hundred more (the viewer's window resizes, offscreen). Every K steps, with the device idle, it samples the process's resident
//! memory and the context's live Vulkan objects and allocated bytes, and after a warm-up fits a
//! line to each: resident memory may grow at most 1 KiB a step, the rest not at all.
//!
//! ```sh
//! RELIEF_VALIDATION=0 RELIEF_SOAK_STEPS=2000 cargo test --release --test long_soak -- --ignored --nocapture
//! ```
//!
//! `RELIEF_SOAK_STEPS` (default 10,000) and `RELIEF_SOAK_EVERY` (default 100) set the length and
//! the sampling; the samples are also written to `target/test-output/soak/long_soak.csv`.

mod common;

use std::fmt::Write as _;
use std::sync::Arc;

use common::soak::{growth, judge, sample, Limits, Sample};
use common::terrain::small_terrain;
use relief::heightfield::{Generator, Heightfield};
use relief::method::Method;
use relief::render::{FrameRequest, RenderOptions, Renderer};
use relief::scene::{
    default_heightfield, default_scene, procedural_layers, rules_splat, terrain_scene, TERRAIN_MESH,
};
use relief::terrain::{BrushKind, Stroke, TerrainEditor};
use relief::vk::Context;

const SIZES: [(u32, u32); 2] = [(480, 270), (432, 243)];
const STROKE_EVERY: u32 = 4;
const RESIZE_EVERY: u32 = 250;
const REBUILD_EVERY: u32 = 400;
/// Resident bytes a step may add on the fitted line: 10 MiB over 10,000 steps.
const RSS_PER_STEP: f64 = 1024.0;

fn setting(name: &str, default: u32) -> u32 {
    std::env::var(name)
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// The two renderers and what rebuilding them needs.
struct Scenes {
    ctx: Arc<Context>,
    hf: Heightfield,
    editor: TerrainEditor,
    size: (u32, u32),
    plain: Renderer,
    terrain: Renderer,
}

impl Scenes {
    fn new(ctx: &Arc<Context>) -> Scenes {
        let elevation = Generator::Fbm.generate(64, 64, 3);
        let editor = TerrainEditor::new(elevation, &small_terrain().grid, TERRAIN_MESH, 0);
        let hf = default_heightfield();
        let (plain, terrain) = Scenes::renderers(ctx, &hf, &editor, SIZES[0]);
        Scenes {
            ctx: ctx.clone(),
            hf,
            editor,
            size: SIZES[0],
            plain,
            terrain,
        }
    }

    fn renderers(
        ctx: &Arc<Context>,
        hf: &Heightfield,
        editor: &TerrainEditor,
        (width, height): (u32, u32),
    ) -> (Renderer, Renderer) {
        let opts = RenderOptions::default()
            .with_width(width)
            .with_height(height);
        let qdm: Method = "qdm".parse().expect("qdm");
        let plain = Renderer::new(ctx, &default_scene(qdm), Some(hf), &opts).expect("prepares");
        let t = small_terrain();
        let elevation = editor.elevation();
        let splat = rules_splat(elevation, 4, &t).expect("splat");
        let scene = terrain_scene(elevation, procedural_layers(64), &splat, &t);
        let terrain = Renderer::new(ctx, &scene, None, &opts).expect("prepares the terrain");
        (plain, terrain)
    }

    fn rebuild(&mut self) {
        let (plain, terrain) = Scenes::renderers(&self.ctx, &self.hf, &self.editor, self.size);
        self.plain = plain;
        self.terrain = terrain;
    }

    fn resize_to(&mut self, size: (u32, u32)) {
        self.size = size;
        for r in [&mut self.plain, &mut self.terrain] {
            r.resize(size.0, size.1).expect("resizes");
        }
    }

    /// Switches to the other size.
    fn resize(&mut self) {
        let other = if self.size == SIZES[0] {
            SIZES[1]
        } else {
            SIZES[0]
        };
        self.resize_to(other);
    }

    /// A raise, then a lower at the same place, so the ground stays within its range.
    fn stroke(&mut self, step: u32) {
        let k = step / STROKE_EVERY;
        let angle = (k / 2) as f32 * 0.7;
        let stroke = Stroke {
            kind: if k % 2 == 0 {
                BrushKind::Raise
            } else {
                BrushKind::Lower
            },
            x: 32.0 + 20.0 * angle.cos(),
            y: 32.0 + 20.0 * angle.sin(),
            radius: 6.0,
            strength: 0.05,
            target: 0.0,
            layer: 0,
        };
        let edit = self.editor.apply(&[stroke]).expect("a checked stroke");
        self.terrain.finish().expect("finishes");
        let meshes: Vec<_> = edit.tiles.iter().map(|(k, m)| (*k, m)).collect();
        self.terrain
            .update_meshes(&meshes)
            .expect("uploads the tiles");
    }

    fn draw(&mut self, step: u32) {
        for r in [&mut self.plain, &mut self.terrain] {
            let request = FrameRequest::new(
                r.default_camera()
                    .orbited(glam::Vec3::ZERO, (0.9 * step as f32).to_radians()),
            );
            r.submit(&request).expect("submits");
        }
    }

    /// Waits for every frame and destroys what was dropped, at the first size, so that every
    /// sample sees the same targets. A frame is drawn first: after a resize the read-back
    /// buffers are made again by the first frame at the new size, not by the resize.
    fn settle(&mut self, step: u32) {
        if self.size != SIZES[0] {
            self.resize_to(SIZES[0]);
        }
        self.draw(step);
        self.plain.finish().expect("finishes");
        self.terrain.finish().expect("finishes");
        self.ctx.wait_idle().expect("idle");
    }
}

fn csv(samples: &[Sample]) -> String {
    let mut out = String::from("step,rss_bytes");
    for (name, _) in samples[0].alive.fields() {
        write!(out, ",{name}").unwrap();
    }
    out.push('\n');
    for s in samples {
        write!(out, "{},{}", s.frame, s.rss).unwrap();
        for (_, v) in s.alive.fields() {
            write!(out, ",{v}").unwrap();
        }
        out.push('\n');
    }
    out
}

#[test]
#[ignore = "runs for hours in debug; see the module docs for the command"]
fn thousands_of_frames_hold_memory_and_objects_flat() {
    let Some(ctx) = common::device("thousands_of_frames_hold_memory_and_objects_flat") else {
        return;
    };
    if let Some(why) = &ctx.info().known_frame_leak {
        eprintln!("SKIPPED: {why}");
        return;
    }
    let steps = setting("RELIEF_SOAK_STEPS", 10_000);
    let every = setting("RELIEF_SOAK_EVERY", 100).max(1);
    // A fifth of the run, at least two rebuilds: pools, caches and the allocator's blocks settle.
    let warm_up = (steps / 5).max(2 * REBUILD_EVERY);
    assert!(
        steps >= warm_up + 3 * every,
        "too short a soak to fit a line"
    );
    let started = std::time::Instant::now();
    let mut scenes = Scenes::new(&ctx);
    let mut samples = Vec::new();
    for step in 1..=steps {
        if step % REBUILD_EVERY == 0 {
            scenes.rebuild();
        }
        if step % RESIZE_EVERY == 0 {
            scenes.resize();
        }
        if step % STROKE_EVERY == 0 {
            scenes.stroke(step);
        }
        scenes.draw(step);
        if step % every == 0 {
            scenes.settle(step);
            let s = sample(&ctx, step);
            eprintln!(
                "step {step:>6} ({:>6.0} s): rss {:>7.1} MiB, {} buffers, {} images, {} sets, {} allocations, {:.1} MiB on the device",
                started.elapsed().as_secs_f64(),
                s.rss as f64 / 1048576.0,
                s.alive.buffers,
                s.alive.images,
                s.alive.descriptor_sets,
                s.alive.allocations,
                s.alive.allocated_bytes as f64 / 1048576.0
            );
            samples.push(s);
        }
    }
    scenes.settle(steps);
    let dir = common::evidence_dir("soak");
    std::fs::write(dir.join("long_soak.csv"), csv(&samples)).expect("writes the samples");
    for (name, per_step) in growth(&samples, warm_up).unwrap_or_default() {
        eprintln!("after {warm_up} warm-up steps: {name} {per_step:+.3} a step");
    }
    let limits = Limits {
        warm_up,
        rss_per_frame: RSS_PER_STEP,
    };
    if let Err(why) = judge(&samples, limits) {
        panic!("{steps} steps of two scenes leak: {why}");
    }
    common::assert_no_validation_errors(&ctx);
}
