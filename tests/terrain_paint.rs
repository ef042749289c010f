//! Painting a layered material's weights: strokes move the splat map and rebuild only the blended
//! texels, pyramid nodes and AO texels near them. After a hundred random strokes the partially
//! rebuilt pyramid equals one built afresh from the painted splat map, bit for bit; a renderer
//! painted between frames draws the same image, bit for bit, as one made from the terrain loaded
//! with that splat map; bad strokes change nothing and say why.

mod common;

use std::sync::Arc;

use common::terrain::small_terrain;

use relief::heightfield::{Address, Generator, Heightfield};
use relief::render::{
    build_blended_pyramid_on_gpu, render, time_on_gpu, BlendedPyramid, FrameRequest, HeightFormat,
    LayerPainter, RenderOptions, Renderer,
};
use relief::scene::{procedural_layers, rules_splat, terrain_scene};
use relief::terrain::{BlendMode, BrushKind, LayerStack, SplatMap, Stroke};
use relief::vk::Context;

/// A deterministic stream in [0, 1).
fn stream(seed: u64) -> impl FnMut() -> f32 {
    let mut state = seed;
    move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 40) as f32 / (1u64 << 24) as f32
    }
}

fn paint_strokes(count: usize, (w, h): (u32, u32), layers: u32, seed: u64) -> Vec<Stroke> {
    let mut next = stream(seed);
    (0..count)
        .map(|_| Stroke {
            kind: BrushKind::Paint,
            x: next() * w as f32,
            y: next() * h as f32,
            radius: 0.6 + next() * 6.0,
            strength: next(),
            target: 0.0,
            layer: (next() * layers as f32) as u32 % layers,
        })
        .collect()
}

fn random_splat(w: u32, h: u32, seed: u64) -> SplatMap {
    let mut next = stream(seed);
    let texels = (0..w * h)
        .map(|_| [next(), next(), next() * 0.5, 0.0])
        .collect();
    SplatMap::new(w, h, texels).unwrap()
}

const SIZE: u32 = 128;

fn layer_heights() -> Vec<Heightfield> {
    vec![
        Generator::Fbm.generate(SIZE, SIZE, 11),
        Generator::Fbm.generate(SIZE, SIZE, 12),
        Generator::Fbm.generate(SIZE, SIZE, 13),
    ]
}

/// A painter over the three layers weighed by `splat`, its pyramid built.
fn painter(
    ctx: &Arc<Context>,
    splat: &SplatMap,
    mode: BlendMode,
    format: HeightFormat,
) -> LayerPainter {
    let stack = LayerStack::from_splat(layer_heights(), splat).unwrap();
    let pyramid = BlendedPyramid::new(ctx, &stack, mode, format, Address::Clamp).unwrap();
    time_on_gpu(ctx, |rec| pyramid.record_build(rec)).unwrap();
    LayerPainter::new(pyramid, splat.clone(), SIZE)
}

fn bits(levels: &[Vec<f32>]) -> Vec<Vec<u32>> {
    levels
        .iter()
        .map(|l| l.iter().map(|v| v.to_bits()).collect())
        .collect()
}

#[test]
fn a_hundred_paint_strokes_rebuilt_in_place_equal_a_fresh_build() {
    let Some(ctx) = common::device("a_hundred_paint_strokes_rebuilt_in_place") else {
        return;
    };
    for (format, mode) in [
        (HeightFormat::R16Unorm, BlendMode::HeightIntersect),
        (HeightFormat::R32Float, BlendMode::Alpha),
    ] {
        let mut painter = painter(&ctx, &random_splat(24, 19, 5), mode, format);
        let before = painter.pyramid().read_levels().unwrap();
        let strokes = paint_strokes(100, (24, 19), 3, 9);
        let mut rebuilt_texels = 0u64;
        for batch in strokes.chunks(10) {
            let staged = painter.paint(batch).expect("in-range paint strokes");
            rebuilt_texels += staged.stack_rects.iter().map(|r| r.texels()).sum::<u64>();
            time_on_gpu(&ctx, |rec| painter.record(rec, &staged).map(drop)).unwrap();
        }
        let painted = painter.pyramid().read_levels().unwrap();
        assert_ne!(
            bits(&painted),
            bits(&before),
            "{format:?}: the strokes changed nothing"
        );
        assert!(
            rebuilt_texels < 100 * u64::from(SIZE * SIZE) / 4,
            "{format:?}: the strokes rebuilt most of the field"
        );
        let fresh_stack = LayerStack::from_splat(layer_heights(), painter.splat()).unwrap();
        let (fresh, _) =
            build_blended_pyramid_on_gpu(&ctx, &fresh_stack, mode, format, Address::Clamp).unwrap();
        for (level, (a, b)) in bits(&painted).iter().zip(bits(&fresh)).enumerate() {
            let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
            assert_eq!(
                differ, 0,
                "{format:?} {mode}: level {level}: {differ} texels differ"
            );
        }
        // Re-staging every weight (a full rebuild in place) changes nothing either.
        let all = painter.stage_all().unwrap();
        time_on_gpu(&ctx, |rec| painter.record(rec, &all).map(drop)).unwrap();
        assert_eq!(
            bits(&painter.pyramid().read_levels().unwrap()),
            bits(&painted)
        );
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn weights_set_from_elsewhere_leave_what_was_painted_by_hand() {
    let Some(ctx) = common::device("weights_set_from_elsewhere_leave_painted") else {
        return;
    };
    let splat = random_splat(16, 16, 3);
    let format = HeightFormat::R16Unorm;
    let mode = BlendMode::Height;
    let mut painter = painter(&ctx, &splat, mode, format);
    let stroke = Stroke {
        kind: BrushKind::Paint,
        x: 8.0,
        y: 8.0,
        radius: 3.0,
        strength: 1.0,
        target: 0.0,
        layer: 0,
    };
    let staged = painter.paint(&[stroke]).unwrap();
    time_on_gpu(&ctx, |rec| painter.record(rec, &staged).map(drop)).unwrap();
    let painted = painter.splat().clone();
    let all = relief::terrain::TexelRect {
        x0: 0,
        y0: 0,
        x1: 15,
        y1: 15,
    };
    let staged = painter
        .reweigh(all, |_, _| [0.0, 0.0, 1.0, 0.0])
        .unwrap()
        .expect("the weights changed");
    time_on_gpu(&ctx, |rec| painter.record(rec, &staged).map(drop)).unwrap();
    for j in 0..16 {
        for i in 0..16 {
            let expected = if stroke.covers(i, j) {
                painted.texel(i, j)
            } else {
                [0.0, 0.0, 1.0, 0.0]
            };
            assert_eq!(painter.splat().texel(i, j), expected, "texel ({i}, {j})");
        }
    }
    assert!(
        painter
            .reweigh(all, |_, _| [0.0, 0.0, 1.0, 0.0])
            .unwrap()
            .is_none(),
        "the same weights again changed something"
    );
    let fresh_stack = LayerStack::from_splat(layer_heights(), painter.splat()).unwrap();
    let (fresh, _) =
        build_blended_pyramid_on_gpu(&ctx, &fresh_stack, mode, format, Address::Clamp).unwrap();
    assert_eq!(
        bits(&painter.pyramid().read_levels().unwrap()),
        bits(&fresh)
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn bad_paint_strokes_change_nothing_and_say_why() {
    let Some(ctx) = common::device("bad_paint_strokes_change_nothing") else {
        return;
    };
    let splat = random_splat(16, 16, 2);
    let mut painter = painter(&ctx, &splat, BlendMode::Height, HeightFormat::R32Float);
    let good = paint_strokes(1, (16, 16), 3, 4)[0];
    for (bad, needle) in [
        (
            Stroke { layer: 3, ..good },
            "layer 3, but the material has 3 layers",
        ),
        (
            Stroke {
                kind: BrushKind::Raise,
                ..good
            },
            "moves the elevation",
        ),
        (
            Stroke {
                strength: f32::NAN,
                ..good
            },
            "strength is NaN",
        ),
        (Stroke { x: 90.0, ..good }, "misses the 16x16 map"),
    ] {
        let err = painter.paint(&[good, bad]).err().expect("refused");
        assert!(err.to_string().contains(needle), "{err}");
        assert!(err.to_string().starts_with("stroke 1"), "{err}");
        assert_eq!(painter.splat(), &splat, "a refused list painted");
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn a_terrain_painted_between_frames_draws_what_the_painted_terrain_draws() {
    let Some(ctx) = common::device("a_terrain_painted_between_frames") else {
        return;
    };
    let opts = small_terrain();
    let elevation = Generator::Fbm.generate(64, 64, 3);
    let splat = rules_splat(&elevation, 4, &opts).unwrap();
    let scene = terrain_scene(&elevation, procedural_layers(64), &splat, &opts);
    let render_opts = RenderOptions::default()
        .with_width(160)
        .with_height(96)
        .with_paintable_layers(true);
    let mut renderer = Renderer::new(&ctx, &scene, None, &render_opts).expect("prepares");
    let camera = renderer.default_camera();
    let request = FrameRequest::new(camera);
    let mut frames: Vec<_> = renderer.submit(&request).unwrap().into_iter().collect();
    let strokes = [
        Stroke {
            kind: BrushKind::Paint,
            x: 12.0,
            y: 14.0,
            radius: 5.0,
            strength: 1.0,
            target: 0.0,
            layer: 3,
        },
        Stroke {
            kind: BrushKind::Paint,
            x: 20.0,
            y: 9.0,
            radius: 3.0,
            strength: 0.7,
            target: 0.0,
            layer: 0,
        },
    ];
    let (waited, report) = renderer.paint_layers(0, &strokes).expect("paints");
    frames.extend(waited);
    assert!(report.ao_texels > 0, "the AO near the strokes was rebuilt");
    assert!(
        report.ao_texels < 256 * 256,
        "the whole AO map was rebuilt: {report:?}"
    );
    frames.extend(renderer.submit(&request).unwrap());
    frames.extend(renderer.finish().unwrap());
    let painted = renderer.layer_splat(0).unwrap().clone();
    let first = frames[0].rgba.clone().unwrap();
    let second = frames[1].rgba.clone().unwrap();
    assert_ne!(first, second, "painting changed nothing on screen");

    let loaded = terrain_scene(&elevation, procedural_layers(64), &painted, &opts);
    let fresh = render(&ctx, &loaded, None, &render_opts).expect("renders");
    let differ = second
        .iter()
        .zip(&fresh.rgba)
        .filter(|(a, b)| a != b)
        .count();
    if differ != 0 {
        let dir = common::evidence_dir("terrain-paint");
        for (name, rgba) in [("painted.png", &second), ("loaded.png", &fresh.rgba)] {
            image::save_buffer(dir.join(name), rgba, 160, 96, image::ColorType::Rgba8).unwrap();
        }
    }
    assert_eq!(
        differ, 0,
        "the painted terrain differs from the terrain loaded painted in {differ} channels"
    );
    common::assert_no_validation_errors(&ctx);
}
