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

use super::cost_curve::fitted_exponent;
use super::frame_timing::{
    time_interleaved, time_setups_interleaved, FrameSetup, MapRate, SteadyFrames,
};
use super::objects_curve::{run_objects_curve, ObjectsRow};
use crate::environment::{Background, EnvironmentSource};
use crate::heightfield::{Generator, Heightfield};
use crate::method::Method;
use crate::render::{
    FrameTimeline, Lighting, RenderError, RenderOptions, ShadowFilter, ShadowOptions, ToneMapping,
};
use crate::scene::{
    default_heightfield, default_scene, relief_stack_scene, Scene, DEFAULT_SCENE_METHOD,
    STACK_QUAD_SIDE,
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
fn plain(size: [u32; 2]) -> RenderOptions {
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
fn look(size: [u32; 2]) -> RenderOptions {
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
const STACK_QUADS: usize = 8;

/// One 256^2 bumpy field for every quad of the stacks.
fn stack_heights() -> Heightfield {
    Generator::Fbm.generate(256, 256, 7)
}

/// The bench's stack: QDM quads.
fn stack_scene(quads: usize, spacing: f32, nearest_first: bool) -> Scene {
    relief_stack_scene(quads, spacing, nearest_first, Method::QDM)
}

fn row(frame: &str, opts: &RenderOptions, t: &SteadyFrames) -> FrameCostRow {
    FrameCostRow {
        frame: frame.to_owned(),
        size: [opts.width, opts.height],
        gpu_ms: t.total_ms,
        shadow_maps_ms: t.shadow_maps_ms,
        fragment_invocations: t.fragment_invocations,
    }
}

/// Runs the section; `quick` times fewer frames on smaller images.
pub fn run_frame_cost_section(
    ctx: &Arc<Context>,
    quick: bool,
    mut progress: impl FnMut(&str),
) -> Result<FrameCostSection, RenderError> {
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
    let scene = default_scene(DEFAULT_SCENE_METHOD);
    let heights = default_heightfield();
    progress("frame costs: the default scene, plain and looks, frames in turn");
    let mut looks = chain_looks(main);
    // Where the device has ray queries: the deferred look with its shadows traced, not mapped.
    if ctx.info().ray_query {
        let traced = RenderOptions {
            msaa: 1,
            lighting: Lighting::Deferred,
            traced_shadows: true,
            ..look(main)
        };
        looks.push((TRACED_LOOK, traced));
    }
    let options: Vec<RenderOptions> = looks.iter().map(|(_, o)| o.clone()).collect();
    let timed = time_interleaved(ctx, &scene, Some(&heights), &options, frames)?;
    let mut timelines = Vec::new();
    let mut keep = |label: String, t: &SteadyFrames| timelines.push((label, t.timelines.clone()));
    let mut rows: Vec<FrameCostRow> = looks
        .iter()
        .zip(&timed)
        .map(|((name, opts), t)| row(name, opts, t))
        .collect();
    for (r, t) in rows.iter().zip(&timed) {
        keep(format!("{} {}x{}", r.frame, r.size[0], r.size[1]), t);
    }
    let ms = |rows: &[FrameCostRow], name: &str| {
        rows.iter()
            .find(|r| r.frame == name && r.size == main)
            .map_or(f64::NAN, |r| r.gpu_ms)
    };
    let step = |rows: &[FrameCostRow], step: &str, from: &str, to: &str| ChainStep {
        step: step.to_owned(),
        from: from.to_owned(),
        to: to.to_owned(),
        ratio: ms(rows, to) / ms(rows, from),
    };
    let chain = vec![
        step(
            &rows,
            "sky light, background, tone curve",
            "plain",
            "look, 1 sample, no shadow maps",
        ),
        step(
            &rows,
            "4x MSAA",
            "look, 1 sample, no shadow maps",
            "look, no shadow maps",
        ),
        step(&rows, "PCSS shadow maps", "look, no shadow maps", "look"),
    ];
    let look_over_plain = ms(&rows, "look") / ms(&rows, "plain");
    let mut deferred: Vec<ChainStep> =
        ["plain", "look, 1 sample, no shadow maps", "look, 1 sample"]
            .iter()
            .map(|&frame| {
                let lit = format!("{frame}, deferred");
                step(&rows, &format!("deferred lighting, {frame}"), frame, &lit)
            })
            .collect();
    if rows.iter().any(|r| r.frame == TRACED_LOOK) {
        let maps = "look, 1 sample, deferred";
        deferred.push(step(
            &rows,
            "traced shadows against PCSS maps",
            maps,
            TRACED_LOOK,
        ));
    }
    let occluder_cost = ms(&rows, "plain") / ms(&rows, "plain, occluders off");
    for size in sizes {
        progress(&format!(
            "frame costs: plain and look at {}x{}",
            size[0], size[1]
        ));
        let options = [plain(size), look(size)];
        let timed = time_interleaved(ctx, &scene, Some(&heights), &options, frames)?;
        rows.push(row("plain", &options[0], &timed[0]));
        rows.push(row("look", &options[1], &timed[1]));
        keep(format!("plain {}x{}", size[0], size[1]), &timed[0]);
        keep(format!("look {}x{}", size[0], size[1]), &timed[1]);
    }
    let stack_heights = stack_heights();
    let mut stacks = Vec::new();
    for spacing in [0.25f32, 1.0] {
        progress(&format!(
            "frame costs: one quad and eight {spacing} apart, both orders"
        ));
        let culled = plain(stack_size);
        let forward = RenderOptions {
            occluders: false,
            ..plain(stack_size)
        };
        let scenes = [
            stack_scene(1, spacing, true),
            stack_scene(STACK_QUADS, spacing, true),
            stack_scene(STACK_QUADS, spacing, false),
        ];
        let heights = &stack_heights;
        let setups: Vec<FrameSetup> = [&culled, &forward]
            .into_iter()
            .flat_map(|opts| {
                scenes.iter().map(move |scene| FrameSetup {
                    scene,
                    heights: Some(heights),
                    opts,
                })
            })
            .collect();
        let timed = time_setups_interleaved(ctx, &setups, frames, MapRate::AsNeeded)?;
        let kinds = ["one quad", "eight, nearest first", "eight, farthest first"];
        for (k, t) in timed.iter().enumerate() {
            let path = if k < 3 { "occluders" } else { "forward" };
            keep(
                format!("stack {spacing} apart: {}, {path}", kinds[k % 3]),
                t,
            );
        }
        stacks.push(StackRow {
            spacing,
            one_ms: timed[0].total_ms,
            nearest_first_ms: timed[1].total_ms,
            farthest_first_ms: timed[2].total_ms,
            forward: Some([timed[3].total_ms, timed[4].total_ms, timed[5].total_ms]),
            occluders_ms: [
                timed[0].occluders_ms,
                timed[1].occluders_ms,
                timed[2].occluders_ms,
            ],
        });
    }
    progress("frame costs: the one-quad scene's steady shadow maps");
    let one_quad = stack_scene(1, 1.0, true);
    let look_opts = look(stack_size);
    let t = time_interleaved(
        ctx,
        &one_quad,
        Some(&stack_heights),
        std::slice::from_ref(&look_opts),
        frames,
    )?;
    let still = &t[0];
    keep("one quad, look, still view".to_owned(), still);
    let still_shadow_share =
        still.shadow_maps_ms / (still.total_ms - still.shadow_maps_ms).max(1e-9);
    progress("frame costs: 1 to 16 relief quads on screen, frames in turn");
    let (objects, timed) =
        run_objects_curve(ctx, &stack_heights, &plain(stack_size), quads, frames)?;
    for (r, t) in objects.iter().zip(&timed) {
        keep(format!("{} relief quads on screen", r.quads), t);
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
        timelines,
    })
}

/// The section's tables in `report.md`.
pub fn report(md: &mut String, s: &FrameCostSection) {
    let _ = writeln!(md, "\n## Frame costs\n");
    let _ = writeln!(
        md,
        "GPU ms per steady frame (every pass; median of {} frames taken in interleaved rounds). \
         *plain*: one sample, flat ambient light, no tone curve, no shadow maps. *look*: \
         `relief render`'s default (4x MSAA, sky light and background, PCSS shadow maps, PBR \
         Neutral). The default look costs **{:.2}x** the plain frame. The occluder pass \
         (on in every row but *occluders off*) costs the plain frame **{:.2}x** on this scene, \
         where it hides no relief.\n",
        s.frames, s.look_over_plain, s.occluder_cost
    );
    let _ = writeln!(
        md,
        "| frame | size | GPU ms | of it shadow maps | fragment invocations |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|");
    for r in &s.rows {
        let counted = r
            .fragment_invocations
            .map_or("-".to_owned(), |n| n.to_string());
        let _ = writeln!(
            md,
            "| {} | {}x{} | {:.3} | {:.3} | {counted} |",
            r.frame, r.size[0], r.size[1], r.gpu_ms, r.shadow_maps_ms
        );
    }
    let curves: Vec<String> = ["plain", "look"]
        .iter()
        .filter_map(|&frame| {
            let points: Vec<(f64, f64)> = s
                .rows
                .iter()
                .filter(|r| r.frame == frame)
                .map(|r| (f64::from(r.size[0]) * f64::from(r.size[1]), r.gpu_ms))
                .collect();
            let k = fitted_exponent(&points)?;
            Some(format!("*{frame}* k = {k:.3} over {} sizes", points.len()))
        })
        .collect();
    if !curves.is_empty() {
        let _ = writeln!(
            md,
            "\nCost against resolution, time ~ pixels^k fitted over the sizes above (1 is linear \
             in pixels; below 1, fixed costs such as the shadow maps and per-draw setup): {}.",
            curves.join(", ")
        );
    }
    let _ = writeln!(md, "\n| step | from | to | ratio |");
    let _ = writeln!(md, "|---|---|---|---|");
    for c in &s.chain {
        let _ = writeln!(
            md,
            "| {} | {} | {} | {:.2}x |",
            c.step, c.from, c.to, c.ratio
        );
    }
    if !s.deferred.is_empty() {
        let _ = writeln!(
            md,
            "\nDeferred lighting (`--lighting deferred`: the surface pass writes shading inputs, \
             a compute pass lights each pixel once) against forward, at one sample:\n"
        );
        let _ = writeln!(md, "| from | to | ratio (to over from) |");
        let _ = writeln!(md, "|---|---|---|");
        for c in &s.deferred {
            let _ = writeln!(md, "| {} | {} | {:.2}x |", c.from, c.to, c.ratio);
        }
    }
    let _ = writeln!(
        md,
        "\nHidden relief: eight QDM quads ({STACK_QUAD_SIDE} x {STACK_QUAD_SIDE} units, 0.3 units of relief, \
         one 256^2 fbm field), one behind the other, the nearest filling the {}x{} view, plain \
         frame; *forward* is the same without the occluder pass (`--occluders off`).\n",
        s.stack_size[0], s.stack_size[1]
    );
    let _ = writeln!(
        md,
        "| spacing | frame | one quad ms | eight, nearest first | eight, farthest first | eight vs one |"
    );
    let _ = writeln!(md, "|---|---|---|---|---|---|");
    for r in &s.stacks {
        let mut lines = vec![(
            "occluders",
            [r.one_ms, r.nearest_first_ms, r.farthest_first_ms],
        )];
        lines.extend(r.forward.map(|f| ("forward", f)));
        let pass = r.occluders_ms;
        let _ = writeln!(
            md,
            "| {} | of it the occluder pass | {:.3} | {:.3} | {:.3} | |",
            r.spacing, pass[0], pass[1], pass[2]
        );
        for (frame, [one, nearest, farthest]) in lines {
            let _ = writeln!(
                md,
                "| {} | {frame} | {one:.3} | {nearest:.3} | {farthest:.3} | {:.2}x |",
                r.spacing,
                nearest.max(farthest) / one.max(1e-9)
            );
        }
    }
    let _ = writeln!(
        md,
        "\nA still view's steady frames (the one-quad scene, default look): the shadow-map pass \
         costs **{:.1}%** of the rest of the frame.",
        100.0 * s.still_shadow_share
    );
    super::objects_curve::report(md, &s.objects, s.stack_size);
}
