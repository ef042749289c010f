//! The surface shader's own work counters (`RenderOptions::count_work`): for a stack of eight
//! relief quads one unit apart (farther than their 0.3 units of relief) filling the view, each
//! pixel traces eight fragments on the forward path and one where the occluder pass culls, in
//! either draw order; quads closer than their relief overlap in depth, so there a second trace
//! stays; each trace's texel fetches are counted beside its steps, the same in two frames;
//! and frames that do not count return no counts.

mod common;

use relief::heightfield::{Generator, Heightfield};
use relief::method::Method;
use relief::render::{
    FrameRequest, RenderOptions, Renderer, ShadowOptions, ToneMapping, WorkCounts,
};
use relief::scene::relief_stack_scene;

const SIZE: (u32, u32) = (96, 54);

fn counts(
    ctx: &std::sync::Arc<relief::vk::Context>,
    hf: &Heightfield,
    (spacing, nearest_first): (f32, bool),
    occluders: bool,
) -> WorkCounts {
    let scene = relief_stack_scene(8, spacing, nearest_first, Method::QDM);
    let opts = RenderOptions::default()
        .with_width(SIZE.0)
        .with_height(SIZE.1)
        .with_msaa(1)
        .with_tone_mapping(ToneMapping::NONE)
        .with_shadows(ShadowOptions::OFF)
        .with_occluders(occluders)
        .with_count_work(true);
    let mut renderer = Renderer::new(ctx, &scene, Some(hf), &opts).expect("renderer");
    let request =
        FrameRequest::new(scene.camera.expect("the stack has a camera")).with_read_back(false);
    let frame = renderer.draw(&request).expect("frame");
    frame.work.expect("a counting frame returns its counts")
}

#[test]
fn a_culled_stack_traces_each_pixel_once_and_the_forward_path_eight_times() {
    let Some(ctx) = common::device("work_counters") else {
        return;
    };
    let hf = Generator::Fbm.generate(64, 64, 7);
    let centre = (SIZE.1 / 2 * SIZE.0 + SIZE.0 / 2) as usize;
    for nearest_first in [true, false] {
        let forward = counts(&ctx, &hf, (1.0, nearest_first), false);
        let culled = counts(&ctx, &hf, (1.0, nearest_first), true);
        let (f, c) = (forward.summary(), culled.summary());
        let order = if nearest_first {
            "nearest first"
        } else {
            "farthest first"
        };
        assert_eq!(forward.traced[centre], 8, "forward, {order}: {f:?}");
        assert_eq!(f.most_fragments_at_a_pixel, 8, "forward, {order}");
        assert_eq!(
            c.traced_pixels,
            u64::from(SIZE.0 * SIZE.1),
            "the nearest quad fills the view, {order}: {c:?}"
        );
        assert_eq!(culled.traced[centre], 1, "culled, {order}: {c:?}");
        assert_eq!(c.most_fragments_at_a_pixel, 1, "culled, {order}: {c:?}");
        assert_eq!(c.fragments_per_traced_pixel, 1.0, "culled, {order}");
        assert!(
            c.steps * 4 < f.steps,
            "culled {} steps, forward {}",
            c.steps,
            f.steps
        );
    }
    // A quarter unit apart the relief ranges (0.3 deep) overlap: the second quad's fragments
    // may hold the nearest hit, so they still trace, but the six behind them do not.
    let overlapping = counts(&ctx, &hf, (0.25, true), true).summary();
    assert_eq!(overlapping.most_fragments_at_a_pixel, 2, "{overlapping:?}");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn texel_fetches_are_counted_per_pixel_and_the_same_in_two_frames() {
    let Some(ctx) = common::device("work_counters_fetches") else {
        return;
    };
    let hf = Generator::Fbm.generate(64, 64, 7);
    let first = counts(&ctx, &hf, (1.0, true), true);
    let again = counts(&ctx, &hf, (1.0, true), true);
    assert_eq!(first, again, "two frames count the same");
    let s = first.summary();
    // Every QDM step reads a pyramid node or, at a leaf, at least one bilinear cell.
    assert!(s.fetches >= s.steps && s.steps > 0, "{s:?}");
    for (k, (&steps, &fetches)) in first.steps.iter().zip(&first.fetches).enumerate() {
        assert!(
            fetches >= steps,
            "pixel {k}: {steps} steps, {fetches} fetches"
        );
        assert_eq!(fetches > 0, first.traced[k] > 0, "pixel {k}");
    }
    let forward = counts(&ctx, &hf, (1.0, true), false).summary();
    assert!(forward.fetches > 4 * s.fetches, "{forward:?} against {s:?}");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn frames_that_do_not_count_return_no_counts() {
    let Some(ctx) = common::device("work_counters_off") else {
        return;
    };
    let hf = Generator::Fbm.generate(64, 64, 7);
    let scene = relief_stack_scene(2, 1.0, true, Method::QDM);
    let opts = RenderOptions::default()
        .with_width(32)
        .with_height(18)
        .with_shadows(ShadowOptions::OFF);
    let mut renderer = Renderer::new(&ctx, &scene, Some(&hf), &opts).expect("renderer");
    let request = FrameRequest::new(scene.camera.expect("camera")).with_read_back(false);
    assert!(renderer.draw(&request).expect("frame").work.is_none());
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn relief_render_reports_the_counts_and_draws_cost_maps() {
    use common::cli::{assert_usage_failure, relief};
    let dir = common::scratch_dir("cost-maps");
    let out = dir.join("f.png");
    let run = relief(&[
        "render",
        "--width",
        "80",
        "--height",
        "45",
        "--json",
        "--cost-map",
        "steps,fragments",
        "--out",
        out.to_str().expect("UTF-8 path"),
    ]);
    let err = String::from_utf8_lossy(&run.stderr);
    assert!(run.status.success(), "{err}");
    let report: serde_json::Value = serde_json::from_slice(&run.stdout).expect("JSON");
    let work = &report["work"];
    assert!(
        work["traced_pixels"].as_u64().is_some_and(|n| n > 0),
        "{work}"
    );
    let per_pixel = work["fragments_per_traced_pixel"]
        .as_f64()
        .expect("a ratio");
    assert!((1.0..1.5).contains(&per_pixel), "{work}");
    assert!(
        work["fetches"].as_u64() >= work["steps"].as_u64()
            && work["fetches_per_traced_pixel"].as_f64() > Some(1.0),
        "the trace's texel fetches: {work}"
    );
    for map in ["steps", "fragments"] {
        let path = dir.join(format!("f.cost-{map}.png"));
        let img = image::open(&path).expect("the cost map is a PNG").to_rgb8();
        assert_eq!(
            img.dimensions(),
            (80 + 12, 45),
            "{map}: the frame and its colour bar"
        );
        let lit = img.pixels().filter(|p| p.0 != [0, 0, 0]).count();
        assert!(lit > 80, "{map}: traced pixels are drawn");
    }
    let refused = relief(&["render", "--no-write", "--cost-map", "steps"]);
    assert_usage_failure(&refused, &["--cost-map", "--no-write"]);
}
