//! Drawing `relief render`'s frames: one, or a sequence along a camera path (`--orbit`, or the
//! glTF file's camera animation sampled evenly from its start to its end), written as PNGs (numbered for a sequence) or only timed
//! (`--no-write`), with per-pass GPU times: the first frame apart (it builds the pyramids and
//! pays first-use compilation), min / median / p95 over the rest.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use anyhow::Context as _;
use clap::Args;
use glam::Vec3;
use relief::render::{
    explain, sequence_stats, timeline_trace, FrameOutput, FrameRequest, FrameTimeline, PassTiming,
    Renderer, SequenceStats, TraceHeader, TracedFrame, WorkSummary,
};
use relief::scene::{Camera, Scene};
use relief::vk::{Context, LiveObjects, ObjectCounts};
use serde::Serialize;
use serde_json::json;

use super::frame_files::{frame_path, write_whole, FileArgs, FrameView};
use super::frame_progress::FrameProgress;
use super::frame_range::FrameRange;
use super::render::RenderArgs;
use super::scene_args::LoadedScene;
use super::terrain_edits::{EditRecord, TerrainEdits};

/// The frame-sequence flags of `relief render`.
#[derive(Args, Debug, Clone)]
pub struct FrameArgs {
    /// How many frames to draw.
    #[arg(long, default_value_t = 1, value_parser = clap::value_parser!(u32).range(1..=1_000_000))]
    pub frames: u32,
    /// Turn the camera this many degrees about the vertical axis through the scene's centre over
    /// the sequence (frame k at DEGREES * k / N). Without it a sequence follows the glTF file's
    /// camera animation when it has one, and otherwise keeps the camera still.
    #[arg(long, value_name = "DEGREES", allow_hyphen_values = true)]
    pub orbit: Option<f32>,
    /// Draw and time the frames without reading them back or writing files.
    #[arg(long)]
    pub no_write: bool,
    /// Draw only frames A to B of the sequence (numbered from 1 like the files, both ends
    /// included), with the camera, file names and pixels the whole sequence gives them; with
    /// --edits the earlier frames' strokes are applied first.
    #[arg(long, value_name = "A..B")]
    pub frame_range: Option<FrameRange>,
    /// Count the relief fragments each frame traces and their steps, per pixel (the surface
    /// shader's own counters, compiled out otherwise); the table and --json report the last
    /// frame's totals.
    #[arg(long)]
    pub count_work: bool,
}

/// Where the camera is in each frame.
enum CameraPath {
    Still(Camera),
    /// The file's animation of its camera, frame k at start + duration * k / (N - 1).
    Animated(relief::scene::CameraPath),
    Orbit {
        start: Camera,
        center: Vec3,
        degrees: f32,
    },
}

impl CameraPath {
    fn choose(args: &FrameArgs, renderer: &Renderer, scene: &Scene) -> anyhow::Result<CameraPath> {
        let start = renderer.default_camera();
        let Some(degrees) = args.orbit else {
            return Ok(match &scene.camera_path {
                Some(path) if args.frames > 1 => CameraPath::Animated(path.clone()),
                _ => CameraPath::Still(start),
            });
        };
        if !degrees.is_finite() {
            anyhow::bail!("--orbit must be a finite number of degrees, got {degrees}");
        }
        let center = scene
            .bounds()
            .map_or(Vec3::ZERO, |(lo, hi)| (lo + hi) * 0.5);
        Ok(CameraPath::Orbit {
            start,
            center,
            degrees,
        })
    }

    fn at(&self, frame: u32, frames: u32) -> Camera {
        match *self {
            CameraPath::Still(camera) => camera,
            CameraPath::Animated(ref path) => {
                let along = frame as f32 / (frames.max(2) - 1) as f32;
                path.sample(path.start() + (path.duration() - path.start()) * along)
            }
            CameraPath::Orbit {
                start,
                center,
                degrees,
            } => {
                let turn = degrees * frame as f32 / frames as f32;
                start.orbited(center, turn.to_radians())
            }
        }
    }
}

/// Where pipelines came from: the cache file (if any), whether it seeded this run, and what the
/// renderer created while it was made (pipelines and the CPU time they took).
pub struct CacheReport {
    pub path: Option<PathBuf>,
    pub seeded: bool,
    pub pipelines: ObjectCounts,
}

impl CacheReport {
    fn json(&self) -> serde_json::Value {
        let p = &self.pipelines;
        json!({
            "path": self.path,
            "seeded": self.seeded,
            "pipelines": p.graphics_pipelines + p.compute_pipelines,
            "create_ms": p.pipeline_create_us as f64 / 1e3,
        })
    }

    fn line(&self) -> String {
        let p = &self.pipelines;
        let cache = match (&self.path, self.seeded) {
            (None, _) => "no cache file".to_owned(),
            (Some(path), true) => format!("seeded from {}", path.display()),
            (Some(path), false) => format!("cache {} was empty or new", path.display()),
        };
        format!(
            "pipelines: {} graphics + {} compute created in {:.1} ms ({cache})",
            p.graphics_pipelines,
            p.compute_pipelines,
            p.pipeline_create_us as f64 / 1e3
        )
    }
}

/// What a sequence left behind.
struct Drawn {
    /// Frames in the sequence (more than --frames when --edits has more lists).
    frames: u32,
    /// The 0-based frames drawn and kept: the whole sequence, or --frame-range's part of it.
    kept: std::ops::Range<u32>,
    /// Frames of `kept` not drawn because `--resume` found their files written.
    skipped: u32,
    timings: Vec<Vec<PassTiming>>,
    /// Each kept frame's timeline with its 0-based number, when --timeline asked for them.
    timelines: Vec<(u32, FrameTimeline)>,
    /// The last kept frame's work counts, when counted.
    work: Option<WorkSummary>,
    edits: Vec<EditRecord>,
    /// Objects created from the end of the first frame's submission to the end of the last.
    created_after_first: ObjectCounts,
    /// Objects alive after the first frame's submission, and after the last frame retired.
    alive: [LiveObjects; 2],
}

/// Draws every frame of the range, writing each as it retires. Frames before the range are
/// skipped, except that with edits those followed by a stroke list the range needs are drawn
/// unread, so the strokes land between frames exactly as in the whole sequence.
fn draw_all(
    args: &RenderArgs,
    files: &FileArgs,
    ctx: &Context,
    renderer: &mut Renderer,
    path: &CameraPath,
    scene: &Scene,
    mut edits: Option<&mut TerrainEdits>,
) -> anyhow::Result<Drawn> {
    let lists = edits.as_ref().map_or(0, |e| e.frames_needed() - 1);
    let (frames, kept) = sequence_frames(args, lists)?;
    // Frames whose files --resume finds written are not drawn, unless a later frame's strokes
    // need them drawn first (then they are drawn unread).
    let written: Vec<bool> = kept
        .clone()
        .map(|k| files.resume && files.written(k, frames))
        .collect();
    let wanted = |k: u32| kept.contains(&k) && !written[(k - kept.start) as usize];
    let skipped = written.iter().filter(|&&w| w).count() as u32;
    let mut progress = FrameProgress::new(kept.len() as u32, args.json || args.explain);
    (0..skipped).for_each(|_| progress.advance());
    let mut records = Vec::new();
    let read_back = !args.frames.no_write;
    let mesh_materials: Vec<usize> = scene.meshes.iter().map(|m| m.material).collect();
    let tone = renderer.plan().tone_mapping;
    let mut timings = Vec::with_capacity(kept.len());
    let mut timelines = Vec::new();
    let mut work = None;
    // The sequence frame of each submission, by the renderer's frame index.
    let mut submitted: Vec<u32> = Vec::with_capacity(kept.len());
    let mut keep = |frame: FrameOutput, submitted: &[u32]| -> anyhow::Result<()> {
        let k = submitted[frame.index as usize];
        if wanted(k) {
            if read_back {
                let view = FrameView {
                    camera: path.at(k, frames),
                    tone,
                    mesh_materials: &mesh_materials,
                };
                files.write(&frame, k, frames, &view)?;
            }
            if files.timeline.is_some() {
                timelines.push((k, frame.timeline));
            }
            if let Some(counts) = &frame.work {
                work = Some(counts.summary());
            }
            timings.push(frame.timings);
            progress.advance();
        }
        Ok(())
    };
    let mut after_first = None;
    for k in 0..kept.end {
        if let Some(edits) = edits.as_deref_mut() {
            let (retired, record) = edits.before_frame(k, renderer)?;
            for frame in retired {
                keep(frame, &submitted)?;
            }
            records.extend(record);
        }
        if !wanted(k) && k >= lists {
            continue;
        }
        let request = FrameRequest::new(path.at(k, frames)).with_read_back(read_back && wanted(k));
        // Motion is measured from the sequence's previous frame, drawn or not.
        renderer.set_motion_origin(path.at(k.saturating_sub(1), frames));
        submitted.push(k);
        let retired = renderer
            .submit(&request)
            .with_context(|| format!("drawing frame {}", k + 1))?;
        after_first.get_or_insert_with(|| (ctx.created(), ctx.alive()));
        if let Some(frame) = retired {
            keep(frame, &submitted)?;
        }
    }
    for frame in renderer.finish().context("finishing the frames")? {
        keep(frame, &submitted)?;
    }
    progress.finish();
    let (after_first, alive_after_first) =
        after_first.unwrap_or_else(|| (ctx.created(), ctx.alive()));
    Ok(Drawn {
        frames,
        kept,
        skipped,
        timings,
        timelines,
        work,
        edits: records,
        created_after_first: ctx.created() - after_first,
        alive: [alive_after_first, ctx.alive()],
    })
}

/// The frames in the sequence (at least one more than the edits' `lists` of strokes) and the
/// 0-based frames of it to draw and keep.
fn sequence_frames(args: &RenderArgs, lists: u32) -> anyhow::Result<(u32, std::ops::Range<u32>)> {
    let frames = args.frames.frames.max(lists + 1);
    let kept = match args.frames.frame_range {
        Some(range) => range.within(frames)?,
        None => 0..frames,
    };
    Ok((frames, kept))
}

/// Draws the frames `args` asks for and reports them.
pub fn run_frames(
    args: &RenderArgs,
    files: &FileArgs,
    ctx: &Arc<Context>,
    renderer: &mut Renderer,
    loaded: &mut LoadedScene,
    before: ObjectCounts,
    cache: &CacheReport,
) -> anyhow::Result<SceneSummary> {
    let path = CameraPath::choose(&args.frames, renderer, &loaded.scene)?;
    let edited = loaded.edits.is_some();
    let drawn = draw_all(
        args,
        files,
        ctx,
        renderer,
        &path,
        &loaded.scene,
        loaded.edits.as_mut(),
    )?;
    let source = loaded.source.as_str();
    if let Some(path) = &files.timeline {
        write_timeline(path, ctx, source, &drawn.timelines)?;
    }
    let stats = sequence_stats(&drawn.timings);
    let summary = SceneSummary::of(&drawn, &stats, args.frames.no_write);
    if args.explain {
        let created = ctx.created() - before;
        let mut value = explain(
            renderer.plan(),
            renderer.maps(),
            renderer.cells(),
            renderer.shells(),
            &created,
        );
        value["device"] = json!(ctx.info());
        value["ray_queries"] = ray_query_note(ctx, renderer.plan().traced_shadows);
        value["graph"] = json!(renderer.graph());
        if edited {
            value["edits"] = edits_json(renderer, &drawn.edits);
        }
        println!("{value}");
        return Ok(summary);
    }
    let methods = methods_drawn(renderer);
    if args.json {
        let value = json!({
            "device": ctx.info(),
            "out": (!args.frames.no_write).then_some(&files.out),
            "width": renderer.size().0,
            "height": renderer.size().1,
            "methods": methods,
            "heightmap": source,
            "upload_ms": renderer.upload_ms(),
            "passes": stats.first,
            "maps": renderer.maps(),
            "cells": renderer.cells(),
            "frames": stats.frames,
            "frame_range": args.frames.frame_range.map(|_| [drawn.kept.start + 1, drawn.kept.end]),
            "steady": stats.steady,
            "created_after_first_frame": drawn.created_after_first,
            "alive": {
                "after_first_frame": drawn.alive[0],
                "after_last_frame": drawn.alive[1],
            },
            "edits": edited.then(|| edits_json(renderer, &drawn.edits)),
            "pipeline_cache": cache.json(),
            "work": drawn.work,
            "written": summary.written,
            "skipped_written": summary.skipped,
        });
        println!("{value}");
        return Ok(summary);
    }
    print_table(&stats);
    if let Some(w) = &drawn.work {
        println!(
            "work (last frame): {} relief fragment(s) traced at {} pixel(s), {:.3} per pixel (at most {} at one), {} steps, {:.2} per traced pixel, {} texel fetches, {:.2} per traced pixel",
            w.traced_fragments,
            w.traced_pixels,
            w.fragments_per_traced_pixel,
            w.most_fragments_at_a_pixel,
            w.steps,
            w.steps_per_traced_pixel,
            w.fetches,
            w.fetches_per_traced_pixel
        );
    }
    report_files(args, files, renderer, &methods, source, &drawn);
    eprintln!("{}", cache.line());
    Ok(summary)
}

/// Writes the kept frames' timelines to `path` as trace-event JSON.
fn write_timeline(
    path: &Path,
    ctx: &Context,
    source: &str,
    timelines: &[(u32, FrameTimeline)],
) -> anyhow::Result<()> {
    let header = TraceHeader {
        title: format!("relief render {source}"),
        device: ctx.describe(),
        other: json!({
            "command": std::env::args().collect::<Vec<_>>().join(" "),
            "relief": env!("CARGO_PKG_VERSION"),
            "commit": env!("RELIEF_GIT_COMMIT"),
        }),
    };
    // Frame numbers from 1, as in the files' names.
    let numbered: Vec<TracedFrame> = timelines
        .iter()
        .map(|(k, timeline)| TracedFrame {
            label: "",
            number: k + 1,
            timeline,
        })
        .collect();
    let trace = timeline_trace(&header, &numbered);
    let bytes = serde_json::to_vec(&trace).context("encoding the timeline")?;
    write_whole(path, &bytes).with_context(|| format!("writing the timeline {}", path.display()))
}

/// What one scene's sequence came to, for a batch's summary.
#[derive(Debug, Clone, Serialize)]
pub struct SceneSummary {
    /// Frames of the sequence asked for (--frame-range's part of it).
    pub frames: u32,
    /// Frames drawn and written.
    pub written: u32,
    /// Frames `--resume` found written and did not draw.
    pub skipped: u32,
    /// GPU milliseconds per frame: the sum of the passes' medians over the frames after the
    /// first, or the first frame's sum when it was the only one drawn.
    pub gpu_ms_per_frame: f64,
}

impl SceneSummary {
    fn of(drawn: &Drawn, stats: &SequenceStats, no_write: bool) -> SceneSummary {
        let gpu_ms_per_frame = if stats.steady.is_empty() {
            stats.first.iter().map(|t| t.gpu_ms).sum()
        } else {
            stats.steady.iter().map(|s| s.median_ms).sum()
        };
        let frames = drawn.kept.len() as u32;
        SceneSummary {
            frames,
            written: if no_write { 0 } else { frames - drawn.skipped },
            skipped: drawn.skipped,
            gpu_ms_per_frame,
        }
    }
}

/// The edits of a sequence: the maps every frame kept (built once, before the first) and what
/// each frame's strokes rebuilt.
fn edits_json(renderer: &Renderer, records: &[EditRecord]) -> serde_json::Value {
    let kept: Vec<String> = renderer
        .maps()
        .iter()
        .map(|m| format!("{} of {}", m.kind, m.source))
        .collect();
    json!({
        "maps_built_once": kept,
        "frames": records,
    })
}

fn print_table(stats: &SequenceStats) {
    if stats.steady.is_empty() {
        println!("{:<10} {:>9}", "pass", "gpu_ms");
        for t in &stats.first {
            println!("{:<10} {:>9.3}", t.pass.name(), t.gpu_ms);
        }
        return;
    }
    println!(
        "{:<10} {:>9} {:>9} {:>9} {:>9} {:>12} {:>12}   (first frame apart; min/median/p95 over frames 2..{}; invocations: median)",
        "pass", "first_ms", "min_ms", "median_ms", "p95_ms", "fragments", "compute", stats.frames
    );
    let mut passes: Vec<_> = stats.first.iter().map(|t| t.pass).collect();
    passes.extend(stats.steady.iter().map(|s| s.pass));
    passes.sort_unstable();
    passes.dedup();
    for pass in passes {
        let first = stats.first.iter().find(|t| t.pass == pass);
        let cell = |v: Option<f64>| v.map_or(format!("{:>9}", "-"), |v| format!("{v:>9.3}"));
        let steady = stats.steady.iter().find(|s| s.pass == pass);
        let counts = steady.and_then(|s| s.counts);
        let count = |v: Option<u64>| v.map_or(format!("{:>12}", "-"), |v| format!("{v:>12}"));
        println!(
            "{:<10} {} {} {} {} {} {}",
            pass.name(),
            cell(first.map(|t| t.gpu_ms)),
            cell(steady.map(|s| s.min_ms)),
            cell(steady.map(|s| s.median_ms)),
            cell(steady.map(|s| s.p95_ms)),
            count(counts.map(|c| c.fragment_invocations)),
            count(counts.map(|c| c.compute_invocations)),
        );
    }
}

/// Reports on stderr what the sequence `d` wrote, what stayed alive, the cells built, each
/// frame's edits, and the objects created after the first frame.
fn report_files(
    args: &RenderArgs,
    files: &FileArgs,
    renderer: &Renderer,
    methods: &str,
    source: &str,
    d: &Drawn,
) {
    let (w, h) = renderer.size();
    let what = what_was_written(args, files, d);
    eprintln!("{what} ({w}x{h}, relief: {methods}, heights: {source})");
    if d.kept.len() > 1 {
        print_alive(&d.alive);
    }
    for c in renderer.cells() {
        eprintln!(
            "cells {:?}: {n}^3 grid ({}), {} grey cells, {} domain faces at {r}^2, {:.1} MiB of maps, built on the cpu in {:.0} ms",
            c.name,
            c.grid_stop,
            c.grey_cells,
            c.domain_faces,
            (c.distance_bytes + c.attribute_bytes) as f64 / f64::from(1u32 << 20),
            c.build_ms,
            n = c.grid,
            r = c.resolution,
        );
    }
    for e in &d.edits {
        eprintln!("frame {}: {}", e.frame, edit_parts(e).join("; "));
    }
    if d.frames > 1 {
        let same = d.created_after_first == ObjectCounts::default();
        eprintln!(
            "objects created after the first frame: {}",
            if same {
                "none".to_owned()
            } else {
                format!("{:?}", d.created_after_first)
            }
        );
    }
}

/// What the sequence `d` wrote (or drew unwritten), and what `--resume` found written.
fn what_was_written(args: &RenderArgs, files: &FileArgs, d: &Drawn) -> String {
    let frames = d.frames;
    let (first, last) = (d.kept.start, d.kept.end - 1);
    let what = if args.frames.no_write {
        format!("drew {} frame(s), wrote none (--no-write)", d.kept.len())
    } else if frames == 1 {
        format!("wrote {}", files.out.display())
    } else {
        format!(
            "wrote {} .. {}",
            frame_path(&files.out, first, frames).display(),
            frame_path(&files.out, last, frames).display()
        )
    };
    if d.skipped > 0 {
        return format!(
            "{what}: {} frame(s) drawn, {} already written (--resume)",
            d.kept.len() as u32 - d.skipped,
            d.skipped
        );
    }
    what
}

/// Prints the objects alive after the first frame and after the last.
fn print_alive([first, last]: &[LiveObjects; 2]) {
    let mib = |b: u64| b as f64 / f64::from(1u32 << 20);
    eprintln!(
        "alive after the first frame / the last: {} / {} buffers, {} / {} images, {} / {} \
         descriptor sets, {} / {} pipelines, {:.1} / {:.1} MiB of device memory",
        first.buffers,
        last.buffers,
        first.images,
        last.images,
        first.descriptor_sets,
        last.descriptor_sets,
        first.pipelines,
        last.pipelines,
        mib(first.allocated_bytes),
        mib(last.allocated_bytes)
    );
}

/// What one frame's strokes did: the elevation strokes' rebuild, the reweighing and the paint.
fn edit_parts(e: &EditRecord) -> Vec<String> {
    let painted = e.paint.as_ref().map_or(0, |p| p.strokes);
    let mut parts = Vec::new();
    if e.strokes > painted {
        parts.push(format!(
            "{} elevation stroke(s) over {} texels rebuilt {} of {} tiles in {:.1} ms (+{:.1} ms uploading them)",
            e.strokes - painted,
            e.texels,
            e.tiles_rebuilt.len(),
            e.tiles_total,
            e.rebuild_ms,
            e.upload_ms
        ));
    }
    let rebuilt = |p: &relief::render::PaintReport| {
        format!(
            "{} splat texels re-blended {} texels of the field ({} with the pyramid levels above) and {} AO texels in {:.2} ms on the gpu",
            p.splat_texels,
            p.blended_texels.first().copied().unwrap_or(0),
            p.blended_texels.iter().sum::<u64>(),
            p.ao_texels,
            p.gpu_ms
        )
    };
    if let Some(r) = &e.reweighed {
        parts.push(format!(
            "the rules weighing the moved ground over {}",
            rebuilt(r)
        ));
    }
    match &e.paint {
        Some(p) => parts.push(format!("{} paint stroke(s) over {}", p.strokes, rebuilt(p))),
        None if e.reweighed.is_none() => parts.push("the layered maps were kept".into()),
        None => {}
    }
    parts
}

/// The relief methods the renderer draws with, or "none".
fn methods_drawn(renderer: &Renderer) -> String {
    let mut ids: Vec<&str> = renderer
        .plan()
        .pipelines
        .iter()
        .filter_map(|p| p.method.map(|m| m.id()))
        .collect();
    ids.sort_unstable();
    ids.dedup();
    if ids.is_empty() {
        "none".into()
    } else {
        ids.join(", ")
    }
}

/// What `--explain` says of ray queries: whether the frame's shadows are traced with them
/// (`traced`: `--traced-shadows`), else that it rasterises and which commands trace.
fn ray_query_note(ctx: &relief::vk::Context, traced: bool) -> serde_json::Value {
    let available = ctx.info().ray_query;
    json!({
        "available": available,
        "used_by_frame": traced,
        "why": if traced {
            "--traced-shadows: the lighting pass casts every shadow-casting light's rays through \
             the scene's acceleration structures; the surfaces come from the raster passes"
        } else if available {
            "the frame's shadows come from shadow maps and its surfaces from the raster passes; \
             `relief shadows --traced` and `relief occlusion` trace by ray query"
        } else {
            "the device has no VK_KHR_ray_query and VK_KHR_acceleration_structure (or \
             RELIEF_RAY_QUERIES=0): the raster paths draw everything"
        },
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use relief::scene::{Interpolation, Keyed, NodeMotion, Projection, Track};

    #[test]
    fn an_animated_camera_is_sampled_evenly_from_its_first_key_to_its_last() {
        let track = Track::new(
            Interpolation::Linear,
            vec![1.0, 3.0],
            vec![Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0)],
        )
        .expect("a valid track");
        let node = NodeMotion::Animated {
            translation: Keyed::Track(track),
            rotation: Keyed::Rest(glam::Quat::IDENTITY),
            scale: Keyed::Rest(Vec3::ONE),
        };
        let projection = Projection::Perspective {
            yfov: 0.8,
            aspect: None,
            znear: 0.1,
            zfar: 10.0,
        };
        let path = CameraPath::Animated(relief::scene::CameraPath::new(vec![node], projection));
        for (frame, x) in [(0, 0.0), (1, 2.0), (2, 4.0)] {
            let eye = path.at(frame, 3).eye();
            assert!(
                (eye - Vec3::new(x, 0.0, 0.0)).length() < 1e-5,
                "frame {frame}: {eye}"
            );
        }
    }

    #[test]
    fn an_orbit_turns_by_its_share_of_the_degrees_each_frame() {
        let start = Camera::look_at(Vec3::new(0.0, 1.0, 4.0), Vec3::ZERO, 0.8, 0.1, 10.0);
        let path = CameraPath::Orbit {
            start,
            center: Vec3::ZERO,
            degrees: 360.0,
        };
        assert!((path.at(0, 4).eye() - start.eye()).length() < 1e-5);
        let quarter = path.at(1, 4).eye();
        assert!(
            (quarter - Vec3::new(4.0, 1.0, 0.0)).length() < 1e-4,
            "{quarter}"
        );
    }
}
