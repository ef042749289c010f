//! A relief material's AO map in a frame: it only ever darkens (it multiplies the ambient term),
//! it darkens the mortar between the default scene's bricks visibly, and without an AO mode
//! nothing of it is planned or built.

mod common;

use relief::render::{render, Pass, RenderOptions};
use relief::scene::{default_heightfield, default_scene, AoMode, DEFAULT_SCENE_METHOD};

/// The bench's plain frame, small.
fn opts() -> RenderOptions {
    RenderOptions::default().with_size(160, 90)
}

#[test]
fn ao_only_darkens_and_shows_in_the_mortar() {
    let Some(ctx) = common::device("ao_only_darkens_and_shows_in_the_mortar") else {
        return;
    };
    let hf = default_heightfield();
    let with_ao = default_scene(DEFAULT_SCENE_METHOD);
    let mut without_ao = with_ao.clone();
    for relief in without_ao
        .materials
        .iter_mut()
        .filter_map(|m| m.relief.as_mut())
    {
        relief.ao = AoMode::None;
    }
    let lit = render(&ctx, &with_ao, Some(&hf), &opts()).expect("renders with AO");
    let plain = render(&ctx, &without_ao, Some(&hf), &opts()).expect("renders without AO");
    assert!(lit
        .plan
        .passes
        .iter()
        .any(|p| p.pass == Pass::AmbientOcclusion));
    assert!(plain.plan.ao_maps.is_empty());
    assert!(!plain
        .plan
        .passes
        .iter()
        .any(|p| p.pass == Pass::AmbientOcclusion));
    let (mut darker, mut brighter) = (0usize, 0usize);
    for (a, b) in lit.rgba.chunks_exact(4).zip(plain.rgba.chunks_exact(4)) {
        for c in 0..3 {
            if a[c] + 1 < b[c] {
                darker += 1;
            }
            if a[c] > b[c] + 1 {
                brighter += 1;
            }
        }
    }
    assert_eq!(brighter, 0, "AO brightened {brighter} channels");
    assert!(darker > 200, "AO darkened only {darker} channels");
    common::assert_no_validation_errors(&ctx);
}
