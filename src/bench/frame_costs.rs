//! The bench's frame-cost section: what the frame's architecture makes each feature cost, as
//! ratios measured in one run. The default look (`relief render`'s: 4x MSAA, sky light and
//! background, PCSS shadow maps, PBR Neutral) against the plain frame (one sample, flat ambient
//! light, no tone curve, no shadow maps) as a chain of steps that multiply out; the look at
//! three sizes; hidden relief (stacks of eight relief quads, one behind the other, against one
//! quad, in both draw orders); the shadow-map pass of a still view's steady frames against
//! the rest of its frame; and the cost curve over relief objects on screen (objects_curve.rs).

use std::fmt::Write as _;
use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::frame_costs_report::{write_chains, write_resolution_curves, write_rows, write_stacks};
use super::frame_costs_timing::SectionRun;
use super::frame_timing::SteadyFrames;
use super::objects_curve::{run_objects_curve, ObjectsRow};
use crate::environment::{Background, EnvironmentSource};
use crate::heightfield::{Generator, Heightfield};
use crate::method::Method;
use crate::render::{
    FrameTimeline, Lighting, RenderError, RenderOptions, ShadowFilter, ShadowOptions, ToneMapping,
};
use crate::scene::{
    default_heightfield, default_scene, relief_stack_scene, Scene, DEFAULT_SCENE_METHOD,
};
use crate::vk::Context;

/// One frame timed.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FrameCostRow {
    /// What is drawn, and how.
    pub frame: String,
    /// Frame size.
    pub size: [u32; 2],
    /// GPU ms per steady frame, every pass (median).
    pub gpu_ms: f64,
    /// Of that, the shadow maps' pass.
    pub shadow_maps_ms: f64,
    /// Fragment shader invocations of a steady frame, every pass, as the device counts them;
    /// absent where it cannot (and in files written before relief counted them).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fragment_invocations: Option<u64>,
}

/// One step of the chain from the plain frame to the default look: `ratio` is `to` over `from`.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct ChainStep {
    /// What the step adds.
    pub step: String,
    /// The row measured without it.
    pub from: String,
    /// The row measured with it.
    pub to: String,
    /// `to`'s GPU ms over `from`'s.
    pub ratio: f64,
}

/// One stack of relief quads against the single quad, with the occluder pass (the default) and
/// without it (the forward reference, `--occluders off`).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct StackRow {
    /// World units between neighbouring quads (the relief is 0.3 units deep).
    pub spacing: f32,
    /// GPU ms of the single quad (median).
    pub one_ms: f64,
    /// GPU ms of eight quads drawn nearest first.
    pub nearest_first_ms: f64,
    /// GPU ms of eight quads drawn farthest first.
    pub farthest_first_ms: f64,
    /// The same three without the occluder pass.
    #[serde(default)]
    pub forward: Option<[f64; 3]>,
    /// Of the three with it, the occluder pass's GPU ms.
    #[serde(default)]
    pub occluders_ms: [f64; 3],
}

/// The whole section.
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct FrameCostSection {
    /// Frames timed per row (after one untimed frame), in interleaved rounds.
    pub frames: u32,
    /// Every frame of the default scene timed, plain and looks.
    pub rows: Vec<FrameCostRow>,
    /// The chain from plain to the default look, at the main size.
    pub chain: Vec<ChainStep>,
    /// The default look over the plain frame, at the main size (the chain's product).
    pub look_over_plain: f64,
    /// Deferred lighting against forward, frame for frame at one sample (the lighting pass
    /// lights one sample per pixel): `ratio` is the deferred frame over the forward one; and,
    /// on a device with ray queries, the deferred look with traced shadows over its PCSS maps.
    #[serde(default)]
    pub deferred: Vec<ChainStep>,
    /// The plain frame over the same without the occluder pass, on the default scene (where
    /// nothing relief draws is hidden, so the pass only costs).
    #[serde(default)]
    pub occluder_cost: f64,
    /// The stacks of eight quads, plain frame.
    pub stacks: Vec<StackRow>,
    /// Size of the stack frames.
    pub stack_size: [u32; 2],
    /// On the one-quad scene with the default look: the steady frames' shadow-map pass over the
    /// rest of their frame.
    pub still_shadow_share: f64,
    /// The cost curve over relief quads on screen, plain frame at `stack_size` (absent from
    /// files written before it).
    #[serde(default)]
    pub objects: Vec<ObjectsRow>,
    /// Every renderer's frames as they ran, labelled by what it drew (`relief bench
    /// --timeline`); not kept in results.json.
    #[serde(skip)]
    pub timelines: Vec<(String, Vec<FrameTimeline>)>,
}

/// The plain frame: one sample, flat ambient light, no tone curve, no shadow maps.
pub(super) fn plain(size: [u32; 2]) -> RenderOptions {
    RenderOptions {
        width: size[0],
        height: size[1],
        msaa: 1,
        environment: EnvironmentSource::Flat,
        background: Background::Colour,
        tone_mapping: ToneMapping::NONE,
        shadows: ShadowOptions::OFF,
        ..RenderOptions::default()
    }
}

/// `relief render`'s default look.
pub(super) fn look(size: [u32; 2]) -> RenderOptions {
    RenderOptions::finished(size[0], size[1])
}

/// The looks of the chain at `size`, by name, in the chain's order: plain, then sky light,
/// background and tone curve, then 4x MSAA, then the shadow maps.
fn chain_looks(size: [u32; 2]) -> Vec<(&'static str, RenderOptions)> {
    let one_sample_no_maps = RenderOptions {
        msaa: 1,
        shadows: ShadowOptions::OFF,
        ..look(size)
    };
    let no_maps = RenderOptions {
        shadows: ShadowOptions::OFF,
        ..look(size)
    };
    let hard = RenderOptions {
        shadows: ShadowOptions {
            filter: Some(ShadowFilter::Hard),
            ..ShadowOptions::DEFAULT
        },
        ..look(size)
    };
    let one_sample = RenderOptions {
        msaa: 1,
        ..look(size)
    };
    let forward = RenderOptions {
        occluders: false,
        ..plain(size)
    };
    let deferred = |opts: &RenderOptions| RenderOptions {
        lighting: Lighting::Deferred,
        ..opts.clone()
    };
    vec![
        ("plain, deferred", deferred(&plain(size))),
        (
            "look, 1 sample, no shadow maps, deferred",
            deferred(&one_sample_no_maps),
        ),
        ("look, 1 sample, deferred", deferred(&one_sample)),
        ("plain", plain(size)),
        ("plain, occluders off", forward),
        ("look, 1 sample, no shadow maps", one_sample_no_maps),
        ("look, no shadow maps", no_maps),
        ("look", look(size)),
        ("look, hard shadow-map filter", hard),
        ("look, 1 sample", one_sample),
    ]
}

/// The row of the deferred look whose shadows are traced by ray query.
const TRACED_LOOK: &str = "look, 1 sample, deferred, traced shadows";

/// Quads in a stack.
pub(super) const STACK_QUADS: usize = 8;

/// One 256^2 bumpy field for every quad of the stacks.
fn stack_heights() -> Heightfield {
    Generator::Fbm.generate(256, 256, 7)
}

/// The bench's stack: QDM quads.
pub(super) fn stack_scene(quads: usize, spacing: f32, nearest_first: bool) -> Scene {
    relief_stack_scene(quads, spacing, nearest_first, Method::QDM)
}

pub(super) fn row(frame: &str, opts: &RenderOptions, t: &SteadyFrames) -> FrameCostRow {
    FrameCostRow {
        frame: frame.to_owned(),
        size: [opts.width, opts.height],
        gpu_ms: t.total_ms,
        shadow_maps_ms: t.shadow_maps_ms,
        fragment_invocations: t.fragment_invocations,
    }
}

/// The sizes and counts a run takes: smaller and fewer when quick.
struct SectionSizes {
    /// The size of the chain's frames.
    main: [u32; 2],
    /// The other sizes the plain frame and the look are timed at.
    sizes: Vec<[u32; 2]>,
    /// The size of the stack and objects frames.
    stack_size: [u32; 2],
    /// Frames timed per row.
    frames: u32,
    /// Relief quads on screen along the objects curve.
    quads: &'static [u32],
}

impl SectionSizes {
    /// The sizes of a run, `quick` or not.
    fn of(quick: bool) -> SectionSizes {
        let (main, sizes, stack_size, frames): ([u32; 2], Vec<[u32; 2]>, [u32; 2], u32) = if quick {
            ([320, 180], vec![[160, 90], [480, 270]], [240, 135], 3)
        } else {
            ([960, 540], vec![[480, 270], [1920, 1080]], [480, 270], 8)
        };
        let quads: &[u32] = if quick {
            &[1, 4, 16]
        } else {
            &[1, 2, 4, 8, 16]
        };
        SectionSizes {
            main,
            sizes,
            stack_size,
            frames,
            quads,
        }
    }
}

/// Runs the section; `quick` times fewer frames on smaller images.
pub fn run_frame_cost_section(
    ctx: &Arc<Context>,
    quick: bool,
    mut progress: impl FnMut(&str),
) -> Result<FrameCostSection, RenderError> {
    let SectionSizes {
        main,
        sizes,
        stack_size,
        frames,
        quads,
    } = SectionSizes::of(quick);
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let heights = default_heightfield();
    let mut run = SectionRun {
        ctx,
        frames,
        timelines: Vec::new(),
    };
    progress("frame costs: the default scene, plain and looks, frames in turn");
    let looks = main_looks(ctx, main);
    let mut rows = run.time_looks(&scene, &heights, &looks)?;
    let chain = chain_steps(&rows, main);
    let look_over_plain = main_ms(&rows, main, "look") / main_ms(&rows, main, "plain");
    let deferred = deferred_steps(&rows, main);
    let occluder_cost =
        main_ms(&rows, main, "plain") / main_ms(&rows, main, "plain, occluders off");
    for size in sizes {
        progress(&format!(
            "frame costs: plain and look at {}x{}",
            size[0], size[1]
        ));
        rows.extend(run.time_plain_and_look(&scene, &heights, size)?);
    }
    let stack_heights = stack_heights();
    let mut stacks = Vec::new();
    for spacing in [0.25f32, 1.0] {
        progress(&format!(
            "frame costs: one quad and eight {spacing} apart, both orders"
        ));
        stacks.push(run.time_stack(&stack_heights, stack_size, spacing)?);
    }
    progress("frame costs: the one-quad scene's steady shadow maps");
    let still_shadow_share = run.still_shadow_share(&stack_heights, stack_size)?;
    progress("frame costs: 1 to 16 relief quads on screen, frames in turn");
    let (objects, timed) =
        run_objects_curve(ctx, &stack_heights, &plain(stack_size), quads, frames)?;
    for (r, t) in objects.iter().zip(&timed) {
        run.keep(format!("{} relief quads on screen", r.quads), t);
    }
    Ok(FrameCostSection {
        frames,
        rows,
        chain,
        look_over_plain,
        deferred,
        occluder_cost,
        stacks,
        stack_size,
        still_shadow_share,
        objects,
        timelines: run.timelines,
    })
}

/// The chain's looks at `main`, and where the device has ray queries, the deferred look with
/// its shadows traced, not mapped.
fn main_looks(ctx: &Arc<Context>, main: [u32; 2]) -> Vec<(&'static str, RenderOptions)> {
    let mut looks = chain_looks(main);
    if ctx.info().ray_query {
        let traced = RenderOptions {
            msaa: 1,
            lighting: Lighting::Deferred,
            traced_shadows: true,
            ..look(main)
        };
        looks.push((TRACED_LOOK, traced));
    }
    looks
}

/// The GPU ms of row `name` at size `main` (NaN when it was not timed).
fn main_ms(rows: &[FrameCostRow], main: [u32; 2], name: &str) -> f64 {
    rows.iter()
        .find(|r| r.frame == name && r.size == main)
        .map_or(f64::NAN, |r| r.gpu_ms)
}

/// The step from row `from` to row `to` at size `main`.
fn ratio_step(
    rows: &[FrameCostRow],
    main: [u32; 2],
    step: &str,
    from: &str,
    to: &str,
) -> ChainStep {
    ChainStep {
        step: step.to_owned(),
        from: from.to_owned(),
        to: to.to_owned(),
        ratio: main_ms(rows, main, to) / main_ms(rows, main, from),
    }
}

/// The chain from the plain frame to the default look at `main`.
fn chain_steps(rows: &[FrameCostRow], main: [u32; 2]) -> Vec<ChainStep> {
    vec![
        ratio_step(
            rows,
            main,
            "sky light, background, tone curve",
            "plain",
            "look, 1 sample, no shadow maps",
        ),
        ratio_step(
            rows,
            main,
            "4x MSAA",
            "look, 1 sample, no shadow maps",
            "look, no shadow maps",
        ),
        ratio_step(
            rows,
            main,
            "PCSS shadow maps",
            "look, no shadow maps",
            "look",
        ),
    ]
}

/// Deferred lighting against forward, frame for frame at `main`, and the traced shadows against
/// the maps where they were timed.
fn deferred_steps(rows: &[FrameCostRow], main: [u32; 2]) -> Vec<ChainStep> {
    let mut deferred: Vec<ChainStep> =
        ["plain", "look, 1 sample, no shadow maps", "look, 1 sample"]
            .iter()
            .map(|&frame| {
                let lit = format!("{frame}, deferred");
                ratio_step(
                    rows,
                    main,
                    &format!("deferred lighting, {frame}"),
                    frame,
                    &lit,
                )
            })
            .collect();
    if rows.iter().any(|r| r.frame == TRACED_LOOK) {
        let maps = "look, 1 sample, deferred";
        deferred.push(ratio_step(
            rows,
            main,
            "traced shadows against PCSS maps",
            maps,
            TRACED_LOOK,
        ));
    }
    deferred
}

/// The section's tables in `report.md`.
pub fn report(md: &mut String, s: &FrameCostSection) {
    let _ = writeln!(md, "\n## Frame costs\n");
    write_rows(md, s);
    write_resolution_curves(md, s);
    write_chains(md, s);
    write_stacks(md, s);
    let _ = writeln!(
        md,
        "\nA still view's steady frames (the one-quad scene, default look): the shadow-map pass \
         costs **{:.1}%** of the rest of the frame.",
        100.0 * s.still_shadow_share
    );
    super::objects_curve::report(md, &s.objects, s.stack_size);
}
