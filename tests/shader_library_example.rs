//! The shader-library example (`examples/shader_library/`) draws a relief quad with its own
//! raw-`ash` pipeline, its shaders including nothing but relief's shader library; relief's own
//! renderer draws the same quad (same map, camera, method and budget) through its surface pass.
//! What the method computes must agree pixel for pixel: which pixels the quad covers, the hit's
//! uv, its view depth and the steps QDM took (on lavapipe they agree to float rounding, steps
//! exactly; the allowances are for GPUs that round an edge pixel or a texel choice another way);
//! and the image of the hits each side makes passes the golden-image tolerance. The example's
//! depth attachment holds the displaced depth in standard and in reversed depth alike. All of it
//! runs under the validation layer.

mod common;

use glam::Vec3;
use relief::heightfield::Generator;
use relief::method::Method;
use relief::render::{render, HeightFormat, RenderOptions};
use relief::scene::{quad_mesh, Camera, Material, Relief, Scene};

#[path = "../examples/shader_library/quad.rs"]
mod quad;

const WIDTH: u32 = 160;
const HEIGHT: u32 = 96;

fn view() -> quad::QuadView {
    quad::QuadView {
        eye: Vec3::new(0.3, 0.9, 1.6),
        target: Vec3::new(0.0, -0.1, 0.0),
        yfov: 45f32.to_radians(),
        half: 1.0,
        depth_scale: 0.08,
        width: WIDTH,
        height: HEIGHT,
        reverse_z: false,
    }
}

/// relief's scene of the example's quad: `quad_mesh` has the example's corners, uv and tangents.
fn scene(v: &quad::QuadView) -> Scene {
    Scene {
        meshes: vec![quad_mesh("quad", 2.0 * v.half, 2.0 * v.half, 1.0, 0)],
        materials: vec![Material {
            name: "quad".into(),
            relief: Some(Relief::new(v.depth_scale, Method::QDM)),
            ..Material::default()
        }],
        camera: Some(Camera::look_at(v.eye, v.target, v.yfov, 0.05, 50.0)),
        ..Scene::default()
    }
}

/// A hit as 8-bit colour: uv in red and green (four repeats, so a wrong hit shows), view depth
/// in blue; black where nothing was drawn.
fn hit_pixel(uv: [f32; 2], depth: f32, covered: bool) -> [u8; 4] {
    if !covered {
        return [0, 0, 0, 255];
    }
    let byte = |x: f32| (x.clamp(0.0, 1.0) * 255.0).round() as u8;
    [
        byte((uv[0] * 4.0).rem_euclid(1.0)),
        byte((uv[1] * 4.0).rem_euclid(1.0)),
        byte((depth - 1.0) / 2.0),
        255,
    ]
}

#[test]
fn the_shader_library_example_traces_what_relief_s_renderer_traces() {
    let test = "the_shader_library_example_traces_what_relief_s_renderer_traces";
    let Some(ctx) = common::device(test) else {
        return;
    };
    let heights = Generator::Fbm.generate(128, 128, 3);
    let v = view();
    let example = quad::draw_quad(&ctx, &heights, &v).expect("the example draws");

    let opts = RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT)
        .with_msaa(1)
        .with_gbuffer(true)
        .with_height_format(HeightFormat::R32Float);
    let frame = render(&ctx, &scene(&v), Some(&heights), &opts).expect("relief renders");
    let g = frame.gbuffer.expect("the G-buffer was asked for");

    let (mut both, mut coverage_differs, mut uv_off, mut steps_differ) = (0, 0, 0, 0);
    let (mut worst_uv, mut worst_depth) = (0f32, 0f32);
    let (mut theirs, mut ours) = (Vec::new(), Vec::new());
    for (k, hit) in example.hits.iter().enumerate() {
        let covered_example = hit[3] > 0.0;
        let covered_relief = g.mesh[k] == 1;
        theirs.extend(hit_pixel([hit[0], hit[1]], hit[3], covered_example));
        ours.extend(hit_pixel(g.uv[k], g.depth[k], covered_relief));
        if covered_example != covered_relief {
            coverage_differs += 1;
            continue;
        }
        if !covered_example {
            continue;
        }
        both += 1;
        let uv = (hit[0] - g.uv[k][0]).abs().max((hit[1] - g.uv[k][1]).abs());
        worst_uv = worst_uv.max(uv);
        worst_depth = worst_depth.max((hit[3] - g.depth[k]).abs() / g.depth[k]);
        if uv > 1e-4 {
            uv_off += 1;
        }
        if hit[2] as u32 != g.steps[k] {
            steps_differ += 1;
        }
    }
    let pixels = (WIDTH * HEIGHT) as usize;
    eprintln!(
        "{both} pixels covered by both, {coverage_differs} by one; uv off by more than 1e-4 at \
         {uv_off} (worst {worst_uv:.2e}), steps differ at {steps_differ}, worst relative depth \
         {worst_depth:.2e}"
    );
    assert!(
        both > pixels / 3,
        "the quad fills a third of the view: {both}"
    );
    // Edge pixels may rasterise differently (relief's quad is indexed, the example's is not).
    assert!(
        coverage_differs <= pixels / 200,
        "coverage differs at {coverage_differs}"
    );
    assert!(
        uv_off <= both / 500,
        "{uv_off} of {both} hits more than 1e-4 apart in uv"
    );
    assert!(
        steps_differ <= both / 200,
        "steps differ at {steps_differ} of {both}"
    );

    let (mean, p99, _) = common::golden::compare(&theirs, &ours);
    assert!(
        mean <= common::golden::MAX_MEAN_DIFF && p99 <= common::golden::MAX_P99_DIFF,
        "the hit images differ: mean {mean:.2}, p99 {p99}"
    );
    assert_eq!(example.rgba.len(), pixels * 4);
    common::assert_no_validation_errors(&ctx);
}

/// The view depth (distance along the camera's axis) of window depth `d`, standard or reversed.
fn view_depth(d: f32, reverse_z: bool) -> f64 {
    let (n, f, d) = (f64::from(quad::NEAR), f64::from(quad::FAR), f64::from(d));
    if reverse_z {
        n * f / (n + d * (f - n))
    } else {
        n * f / (f - d * (f - n))
    }
}

#[test]
fn the_depth_attachment_holds_the_displaced_depth_in_either_convention() {
    let test = "the_depth_attachment_holds_the_displaced_depth_in_either_convention";
    let Some(ctx) = common::device(test) else {
        return;
    };
    let heights = Generator::Fbm.generate(128, 128, 3);
    let standard = quad::draw_quad(&ctx, &heights, &view()).expect("standard depth");
    let reversed_view = quad::QuadView {
        reverse_z: true,
        ..view()
    };
    let reversed = quad::draw_quad(&ctx, &heights, &reversed_view).expect("reversed depth");
    let (mut covered, mut worst_sum, mut worst_standard, mut worst_reversed) =
        (0, 0f64, 0f64, 0f64);
    for k in 0..standard.hits.len() {
        let hit = standard.hits[k];
        assert_eq!(
            hit, reversed.hits[k],
            "pixel {k}: the convention changed the hit"
        );
        if hit[3] <= 0.0 {
            assert_eq!(
                (standard.depth[k], reversed.depth[k]),
                (1.0, 0.0),
                "pixel {k}: cleared"
            );
            continue;
        }
        covered += 1;
        // Swapping the planes of a [0, 1] perspective maps d to 1 - d.
        worst_sum = worst_sum.max(f64::from(standard.depth[k] + reversed.depth[k] - 1.0).abs());
        // Both hold the displaced hit's depth, which the fragment also reports as view depth.
        let view = f64::from(hit[3]);
        worst_standard =
            worst_standard.max((view_depth(standard.depth[k], false) - view).abs() / view);
        worst_reversed =
            worst_reversed.max((view_depth(reversed.depth[k], true) - view).abs() / view);
    }
    eprintln!(
        "{covered} pixels: |d + d_reversed - 1| <= {worst_sum:.1e}; view depth from the \
         attachment within {worst_standard:.1e} (standard), {worst_reversed:.1e} (reversed)"
    );
    assert!(covered > standard.hits.len() / 3);
    assert!(
        worst_sum < 1e-5,
        "reversed depth is not 1 - d: {worst_sum:e}"
    );
    assert!(
        worst_standard < 1e-3,
        "standard depth off the hit by {worst_standard:e}"
    );
    assert!(
        worst_reversed < 1e-5,
        "reversed depth off the hit by {worst_reversed:e}"
    );
    common::assert_no_validation_errors(&ctx);
}
