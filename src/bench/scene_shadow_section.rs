//! The bench's scene-shadow section: map size x filter against the exact scene reference
//! (error) and GPU time, for a displaced caster (the relief slab) and a plain one (the box), and
//! what the shadow maps add to the default scene's frame.

use std::fmt::Write as _;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::frame_timing::{time_steady_frames, MapRate};
use super::scene_shadows::{measure_scene_shadows, SceneShadowConfig, SceneShadowError};
use crate::render::{RenderOptions, ShadowFilter, ShadowOptions};
use crate::scene::{
    default_heightfield, default_scene, shadow_scene, Scene, ShadowScene, DEFAULT_SCENE_METHOD,
};
use crate::vk::Context;

/// The sun of the section's scenes: low enough for long shadows, with a 1-degree radius so the
/// filters' penumbrae have something to match.
const ELEVATION_DEG: f32 = 20.0;
const RADIUS_DEG: f32 = 1.0;

/// One cell: a caster, a map size and a filter.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SceneShadowCell {
    /// "displaced" (the relief slab) or "plain" (the box).
    pub caster: String,
    /// Texels per side of each cascade.
    pub map_size: u32,
    /// The filter.
    pub filter: ShadowFilter,
    /// Share of receiver pixels whose lit/shadowed verdict matches the exact one (outside the
    /// one-texel band).
    pub hard_agreement: f64,
    /// Mean absolute error of the visible fraction over every receiver pixel (band included).
    pub mean_abs_error: f64,
    /// Share of fully lit receiver pixels reported shadowed.
    pub acne: f64,
    /// Share of fully occluded receiver pixels reported lit.
    pub leaks: f64,
    /// GPU ms of the shadow maps per frame at the timing size (median).
    pub shadow_maps_ms: f64,
    /// GPU ms of the surface pass per frame (median), soft lookups included.
    pub surface_ms: f64,
}

/// The default scene's frame with and without shadow maps.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct DefaultFrameCost {
    /// GPU ms per frame (every pass a steady frame records), maps off.
    pub without_ms: f64,
    /// GPU ms per steady frame with the default maps (PCSS) under a still camera: the maps
    /// rendered by the first frame only, the lookups in every frame.
    pub with_ms: f64,
    /// GPU ms per frame with the maps rendered every frame, as under a moving camera (0 in
    /// files written before the maps were kept between frames).
    #[serde(default)]
    pub moving_ms: f64,
    /// The shadow maps' pass, when a frame renders them.
    pub shadow_maps_ms: f64,
    /// `with_ms / without_ms - 1`.
    pub added: f64,
}

/// One caster's shadows traced by ray query, beside its maps' cells: the same light, probe and
/// reference rays.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct TracedShadowCell {
    /// "displaced" (the relief slab) or "plain" (the box).
    pub caster: String,
    /// Share of receiver pixels whose verdict matches the exact one, every pixel counted (the
    /// band around shadow edges included).
    pub hard_agreement: f64,
    /// Mean absolute error of the visible fraction over every receiver pixel.
    pub mean_abs_error: f64,
    /// Share of fully lit receiver pixels reported shadowed, band included.
    pub acne: f64,
    /// Share of fully occluded receiver pixels reported lit, band included.
    pub leaks: f64,
    /// Rays traced: receivers times the light's samples.
    pub rays: usize,
    /// GPU ms of one dispatch over them (median of three).
    pub trace_ms: f64,
    /// Relief prisms the rays' candidates asked the shader to test.
    pub prisms_tested: u64,
    /// Opaque triangles and relief prisms in the structures.
    pub triangles: usize,
    /// Relief prisms, one box each.
    pub prisms: usize,
    /// Bytes of the acceleration structures.
    pub structure_bytes: u64,
    /// GPU ms of their builds.
    pub build_ms: f64,
}

/// The whole section.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct SceneShadowSection {
    /// Probe image size (error).
    pub probe: [u32; 2],
    /// Timing image size.
    pub timing: [u32; 2],
    /// Frames timed per cell (after one untimed frame).
    pub frames: u32,
    /// Exact reference rays per pixel.
    pub reference_rays: u32,
    /// Every cell.
    pub cells: Vec<SceneShadowCell>,
    /// The default scene's cost.
    pub default_frame: DefaultFrameCost,
    /// Each caster's shadows by ray query (empty in files written before them, or on a device
    /// without ray queries: then `traced_skipped` says why).
    #[serde(default)]
    pub traced: Vec<TracedShadowCell>,
    /// Why the traced cells are missing, when they are.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub traced_skipped: Option<String>,
}

/// Median GPU ms of the default scene's steady frames (its frame heights); returns (shadow
/// maps, surface, whole steady frame).
fn time_frames(
    ctx: &Arc<Context>,
    scene: &Scene,
    opts: &RenderOptions,
    frames: u32,
    maps: MapRate,
) -> Result<(f64, f64, f64), SceneShadowError> {
    let t = time_steady_frames(ctx, scene, Some(&default_heightfield()), opts, frames, maps)?;
    Ok((t.shadow_maps_ms, t.surface_ms, t.total_ms))
}

/// The sizes and counts a run takes: smaller and fewer when quick.
#[derive(Clone, Copy)]
struct SectionSizes {
    /// Probe image size (error).
    probe: [u32; 2],
    /// Timing image size.
    timing: [u32; 2],
    /// Frames timed per cell.
    frames: u32,
    /// The map sizes measured.
    sizes: &'static [u32],
    /// Exact reference rays per side of a pixel.
    samples: u32,
}

impl SectionSizes {
    /// The sizes of a run, `quick` or not.
    fn of(quick: bool) -> SectionSizes {
        let (probe, timing, frames, sizes, samples): ([u32; 2], [u32; 2], u32, &[u32], u32) =
            if quick {
                ([120, 68], [480, 270], 3, &[512, 1024], 4)
            } else {
                ([240, 135], [960, 540], 8, &[512, 1024, 2048], 6)
            };
        SectionSizes {
            probe,
            timing,
            frames,
            sizes,
            samples,
        }
    }

    /// The section's probe of `kind`'s scene: its light, the probe size and the reference's
    /// rays, with default maps, untraced and against the relief's own reference.
    fn probe_config(&self, kind: ShadowScene) -> SceneShadowConfig {
        SceneShadowConfig {
            scene: Some(kind),
            elevation_deg: ELEVATION_DEG,
            radius_deg: Some(RADIUS_DEG),
            width: self.probe[0],
            height: self.probe[1],
            samples_per_side: self.samples,
            ..SceneShadowConfig::default()
        }
    }
}

/// Runs the section; `quick` measures fewer sizes on smaller images.
pub fn run_scene_shadow_section(
    ctx: &Arc<Context>,
    quick: bool,
    mut progress: impl FnMut(&str),
) -> Result<SceneShadowSection, SceneShadowError> {
    let run = SectionSizes::of(quick);
    let mut cells = Vec::new();
    let mut traced = Vec::new();
    let traced_skipped = (!ctx.info().ray_query)
        .then(|| format!("{} has no ray queries (VK_KHR_ray_query)", ctx.info().name));
    for (caster, kind) in [
        ("displaced", ShadowScene::SlabOverPlane),
        ("plain", ShadowScene::BoxOverPlane),
    ] {
        if traced_skipped.is_none() {
            progress(&format!(
                "scene shadows: {caster} caster, traced by ray query"
            ));
            traced.extend(traced_cell(ctx, &run, caster, kind)?);
        }
        for &map_size in run.sizes {
            for filter in ShadowFilter::ALL {
                progress(&format!(
                    "scene shadows: {caster} caster, {map_size}^2, {filter}"
                ));
                cells.push(map_cell(ctx, &run, (caster, kind), (map_size, filter))?);
            }
        }
    }
    progress("scene shadows: the default scene's frame");
    let default_frame = default_frame_cost(ctx, run.timing, run.frames)?;
    Ok(SceneShadowSection {
        probe: run.probe,
        timing: run.timing,
        frames: run.frames,
        reference_rays: run.samples * run.samples,
        cells,
        default_frame,
        traced,
        traced_skipped,
    })
}

/// The shadows of `kind`'s scene traced by ray query against the exact reference, as
/// `caster`'s cell (none when the measurement traced nothing).
fn traced_cell(
    ctx: &Arc<Context>,
    run: &SectionSizes,
    caster: &str,
    kind: ShadowScene,
) -> Result<Option<TracedShadowCell>, SceneShadowError> {
    let config = SceneShadowConfig {
        traced: true,
        ..run.probe_config(kind)
    };
    let measured = measure_scene_shadows(ctx, &config)?;
    Ok(measured.traced.map(|t| {
        let a = &t.everywhere;
        TracedShadowCell {
            caster: caster.to_owned(),
            hard_agreement: a.hard_agreement,
            mean_abs_error: a.mean_abs_error,
            acne: a.acne.share,
            leaks: a.leaks.share,
            rays: t.rays,
            trace_ms: t.trace_ms,
            prisms_tested: t.prisms_tested,
            triangles: t.structures.triangles,
            prisms: t.structures.prisms,
            structure_bytes: t.structures.structure_bytes,
            build_ms: t.structures.build_ms,
        }
    }))
}

/// The cell of `caster`'s scene (`kind`) with maps of `map_size` filtered by `filter`: their
/// error against the exact reference at the probe size, and their GPU time at the timing size.
fn map_cell(
    ctx: &Arc<Context>,
    run: &SectionSizes,
    (caster, kind): (&str, ShadowScene),
    (map_size, filter): (u32, ShadowFilter),
) -> Result<SceneShadowCell, SceneShadowError> {
    let shadows = ShadowOptions {
        map_size,
        filter: Some(filter),
        ..ShadowOptions::DEFAULT
    };
    let config = SceneShadowConfig {
        shadows,
        ..run.probe_config(kind)
    };
    let measured = measure_scene_shadows(ctx, &config)?;
    let opts = RenderOptions {
        width: run.timing[0],
        height: run.timing[1],
        address: kind.address(),
        shadows,
        ..RenderOptions::default()
    };
    let scene = shadow_scene(kind, ELEVATION_DEG, RADIUS_DEG);
    // Every frame renders its maps, as under a moving camera: their cost is the cell's.
    let (maps_ms, surface_ms, _) =
        time_frames(ctx, &scene, &opts, run.frames, MapRate::EveryFrame)?;
    let a = &measured.agreement;
    Ok(SceneShadowCell {
        caster: caster.to_owned(),
        map_size,
        filter,
        hard_agreement: a.hard_agreement,
        mean_abs_error: measured.everywhere.mean_abs_error,
        acne: a.acne.share,
        leaks: a.leaks.share,
        shadow_maps_ms: maps_ms,
        surface_ms,
    })
}

/// The default scene's frame at `timing` without maps, with them under a still camera, and
/// with them rendered every frame.
fn default_frame_cost(
    ctx: &Arc<Context>,
    timing: [u32; 2],
    frames: u32,
) -> Result<DefaultFrameCost, SceneShadowError> {
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let opts = |shadows| RenderOptions {
        width: timing[0],
        height: timing[1],
        shadows,
        ..RenderOptions::default()
    };
    let still = MapRate::AsNeeded;
    let (_, _, without_ms) = time_frames(ctx, &scene, &opts(ShadowOptions::OFF), frames, still)?;
    let (_, _, with_ms) = time_frames(ctx, &scene, &opts(ShadowOptions::DEFAULT), frames, still)?;
    let (shadow_maps_ms, _, moving_ms) = time_frames(
        ctx,
        &scene,
        &opts(ShadowOptions::DEFAULT),
        frames,
        MapRate::EveryFrame,
    )?;
    Ok(DefaultFrameCost {
        without_ms,
        with_ms,
        moving_ms,
        shadow_maps_ms,
        added: with_ms / without_ms.max(1e-9) - 1.0,
    })
}

/// The section's tables in `report.md`.
pub fn report(md: &mut String, s: &SceneShadowSection) {
    let _ = writeln!(md, "\n## Scene shadows\n");
    let d = &s.default_frame;
    let _ = writeln!(
        md,
        "Default scene at {}x{}: {:.3} GPU ms per frame without shadow maps, {:.3} with the \
         default maps under a still camera (rendered by the first frame, read by every frame): \
         **{:+.1}%**; {:.3} when every frame renders them, as under a moving camera ({:.3} of \
         them the maps' pass).\n",
        s.timing[0],
        s.timing[1],
        d.without_ms,
        d.with_ms,
        100.0 * d.added,
        d.moving_ms,
        d.shadow_maps_ms
    );
    let _ = writeln!(
        md,
        "A sun at {ELEVATION_DEG} degrees of {RADIUS_DEG} degree angular radius over a plane: the \
         displaced caster is a floating slab of relief bricks (QDM), the plain one a box. Error: \
         relief's visible fraction against the exact scene reference ({} rays per pixel) at \
         {}x{}; agreement, acne and leaks outside a band of one shadow-map texel around the exact \
         shadow edges. Time: median of {} frames at {}x{}, each rendering its maps.\n",
        s.reference_rays, s.probe[0], s.probe[1], s.frames, s.timing[0], s.timing[1]
    );
    let _ = writeln!(
        md,
        "| caster | map | filter | agreement | mean abs error | acne | leaks | maps ms | surface ms |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|");
    for c in &s.cells {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.2}% | {:.4} | {:.3}% | {:.3}% | {:.3} | {:.3} |",
            c.caster,
            c.map_size,
            c.filter,
            100.0 * c.hard_agreement,
            c.mean_abs_error,
            100.0 * c.acne,
            100.0 * c.leaks,
            c.shadow_maps_ms,
            c.surface_ms
        );
    }
    traced_report(md, s);
}

/// The traced cells' table, or why there is none.
fn traced_report(md: &mut String, s: &SceneShadowSection) {
    if let Some(why) = &s.traced_skipped {
        let _ = writeln!(md, "\nNo shadows traced by ray query: {why}.");
        return;
    }
    if s.traced.is_empty() {
        return;
    }
    let _ = writeln!(
        md,
        "\nThe same light traced by ray query (docs/ray-traced.md): the \
         reference's own {} rays per pixel from the same receivers through the scene's \
         acceleration structures, relief prisms resolved by the exact height-field walk. Every \
         receiver pixel counts, the band included. GPU ms: one dispatch over every ray, median \
         of three.\n",
        s.reference_rays
    );
    let _ = writeln!(
        md,
        "| caster | agreement, band included | mean abs error | acne | leaks | rays | rays per ms | prism tests | structures | build ms |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|---|---|---|---|");
    for c in &s.traced {
        let _ = writeln!(
            md,
            "| {} | {:.3}% | {:.4} | {:.3}% | {:.3}% | {} | {:.0} | {} | {} triangles, {} prisms, {:.1} KiB | {:.3} |",
            c.caster,
            100.0 * c.hard_agreement,
            c.mean_abs_error,
            100.0 * c.acne,
            100.0 * c.leaks,
            c.rays,
            c.rays as f64 / c.trace_ms.max(1e-9),
            c.prisms_tested,
            c.triangles,
            c.prisms,
            c.structure_bytes as f64 / 1024.0,
            c.build_ms
        );
    }
}
