//! Local rebuilds of horizon AO maps: with a bounded reach, after brush strokes change the heights
//! (and `ElevationEditor` rebuilds the touched pyramid nodes), rebuilding only the influence
//! regions of the strokes' rectangles gives the map a full rebuild gives, bit for bit, under both
//! addressings and both height formats; bad reaches, and regions of the exact sweep, are refused.

mod common;

use std::sync::Arc;

use relief::heightfield::{Address, Generator, Heightfield};
use relief::render::{AoJob, AoMapPass, ElevationEditor, GpuHeightfield, HeightFormat};
use relief::scene::AoMode;
use relief::terrain::Stroke;
use relief::vk::{raw, read_mip, Context, VkError};

const HORIZON_8_ROTATED: AoMode = AoMode::Horizon {
    directions: 8,
    rotated: true,
};
const REACH_TEXELS: f32 = 12.0;
const DEPTH_SCALE: f32 = 0.1;
const ADDRESSES: [Address; 2] = [Address::Clamp, Address::Repeat];

/// A stroke from its JSON form (the shape `relief render --edits` reads), so that fields other
/// tests do not need keep their defaults.
fn stroke(kind: &str, x: f32, y: f32, radius: f32, strength: f32) -> Stroke {
    let json = serde_json::json!({
        "kind": kind, "x": x, "y": y, "radius": radius, "strength": strength,
    });
    serde_json::from_value(json).expect("a valid stroke")
}

/// The map's texels as bits, so that comparisons are exact (no -0.0 == 0.0, no NaN != NaN).
fn map_bits(ctx: &Arc<Context>, job: &AoJob) -> Vec<u32> {
    let layout = raw::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
    let bytes = read_mip(ctx, &job.map().image, 0, layout).expect("AO map reads back");
    bytemuck::pod_collect_to_vec::<u8, f32>(&bytes)
        .iter()
        .map(|v| v.to_bits())
        .collect()
}

/// A fully built map of `heights` with the test's bounded reach.
fn built(ctx: &Arc<Context>, pass: &AoMapPass, heights: &GpuHeightfield) -> AoJob {
    let job = pass
        .prepare_reaching(heights, DEPTH_SCALE, Some(REACH_TEXELS))
        .expect("AO job");
    ctx.one_shot(|rec| pass.record(rec, &job))
        .expect("AO map builds");
    job
}

/// Whether texel `i` of a `w`-wide map lies in `rect` (x0, y0, width, height).
fn inside(i: usize, w: u32, rect: [u32; 4]) -> bool {
    let (x, y) = ((i % w as usize) as u32, (i / w as usize) as u32);
    x >= rect[0] && x < rect[0] + rect[2] && y >= rect[1] && y < rect[1] + rect[3]
}

#[test]
fn regions_rebuilt_after_strokes_equal_a_full_rebuild() {
    let Some(ctx) = common::device("ao_region rebuild") else {
        return;
    };
    let (w, h) = (128, 96);
    let elevation = Generator::Fbm.generate(w, h, 7);
    let pass = AoMapPass::new(&ctx, HORIZON_8_ROTATED).expect("AO pipeline");
    // One stroke inside, one over a corner (its influence wraps under repeat).
    let strokes = [
        stroke("raise", 50.5, 40.0, 5.0, 0.3),
        stroke("crater", 2.0, 93.0, 6.0, 0.2),
    ];
    for format in [HeightFormat::R32Float, HeightFormat::R16Unorm] {
        for address in ADDRESSES {
            let what = format!("{format:?} {address:?}");
            let mut editor = ElevationEditor::new(&ctx, &elevation, format, address).unwrap();
            let job = built(&ctx, &pass, editor.heights());
            let before = map_bits(&ctx, &job);
            editor.apply(&strokes).expect("strokes apply");
            let changed: Vec<[u32; 4]> = strokes
                .iter()
                .map(|s| s.rect(w, h).expect("the stroke touches the map"))
                .map(|r| [r.x0, r.y0, r.width(), r.height()])
                .collect();
            let regions: Vec<[u32; 4]> = changed
                .iter()
                .map(|&c| job.influence_region(c).expect("a bounded reach"))
                .collect();
            ctx.one_shot(|rec| {
                regions
                    .iter()
                    .try_for_each(|&r| pass.record_region(rec, &job, r))
            })
            .expect("regions rebuild");
            let partial = map_bits(&ctx, &job);
            let full = map_bits(&ctx, &built(&ctx, &pass, editor.heights()));

            let differing = partial.iter().zip(&full).filter(|(a, b)| a != b).count();
            assert_eq!(differing, 0, "{what}: texels differ from a full rebuild");
            // The test can fail: the strokes altered the AO, and beyond their own rectangles.
            let altered: Vec<usize> = (0..full.len()).filter(|&i| full[i] != before[i]).collect();
            assert!(
                !altered.is_empty(),
                "{what}: the strokes altered no AO texel"
            );
            assert!(
                altered
                    .iter()
                    .any(|&i| changed.iter().all(|&c| !inside(i, w, c))),
                "{what}: the AO changed only under the strokes"
            );
            // And it is local: the inner stroke's region is a small part of the map.
            let inner = regions[0];
            assert!(
                inner[2] * inner[3] < w * h / 4,
                "{what}: region {inner:?} of a {w}x{h} map"
            );
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn influence_regions_grow_clip_and_wrap() {
    let Some(ctx) = common::device("ao_region influence") else {
        return;
    };
    let (w, h) = (128, 96);
    let field = Generator::Fbm.generate(w, h, 3);
    let pass = AoMapPass::new(&ctx, HORIZON_8_ROTATED).expect("AO pipeline");
    for address in ADDRESSES {
        let gpu = GpuHeightfield::upload(&ctx, &field, HeightFormat::R32Float, address).unwrap();
        let unbounded = pass.prepare(&gpu, DEPTH_SCALE).expect("AO job");
        assert_eq!(unbounded.influence_texels(), None);
        assert_eq!(unbounded.influence_region([3, 4, 5, 6]), None);
        let job = pass
            .prepare_reaching(&gpu, DEPTH_SCALE, Some(REACH_TEXELS))
            .expect("AO job");
        let r = job.influence_texels().expect("a bounded reach");
        assert!((12..=24).contains(&r), "radius {r} for a 12-texel reach");
        assert_eq!(
            job.influence_region([60, 40, 2, 3]),
            Some([60 - r, 40 - r, 2 + 2 * r, 3 + 2 * r])
        );
        assert_eq!(job.influence_region([5, 5, 0, 3]), Some([0; 4]));
        assert_eq!(job.influence_region([500, 5, 3, 3]), Some([0; 4]));
        let corner = job.influence_region([0, 0, 1, 1]);
        let expected = match address {
            Address::Clamp => [0, 0, 1 + r, 1 + r],
            // The grown rectangle crosses both edges, so it continues on the far sides.
            Address::Repeat => [0, 0, w, h],
        };
        assert_eq!(corner, Some(expected), "{address:?}");
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn bad_reaches_and_regions_of_the_exact_sweep_are_refused() {
    let Some(ctx) = common::device("ao_region refused") else {
        return;
    };
    let field = Heightfield::new(4, 4, (0..16).map(|k| k as f32 / 16.0).collect()).unwrap();
    let gpu = GpuHeightfield::upload(&ctx, &field, HeightFormat::R32Float, Address::Clamp).unwrap();
    let horizon = AoMapPass::new(&ctx, HORIZON_8_ROTATED).expect("AO pipeline");
    for reach in [0.0, 0.5, -3.0, f32::NAN, f32::INFINITY] {
        match horizon.prepare_reaching(&gpu, DEPTH_SCALE, Some(reach)) {
            Err(VkError::Invalid(why)) => {
                assert!(why.contains("reach") && why.contains("at least 1"), "{why}")
            }
            Err(e) => panic!("reach {reach}: {e}"),
            Ok(_) => panic!("reach {reach} accepted"),
        }
    }
    // An empty region records nothing, which is fine even before a build.
    let job = horizon.prepare(&gpu, DEPTH_SCALE).expect("AO job");
    ctx.one_shot(|rec| horizon.record_region(rec, &job, [1, 1, 0, 2]))
        .expect("an empty region");

    let exact = AoMapPass::new(&ctx, AoMode::ExactHorizon).expect("sweep pipeline");
    match exact.prepare_reaching(&gpu, DEPTH_SCALE, Some(REACH_TEXELS)) {
        Err(VkError::Invalid(why)) => assert!(why.contains("no bounded reach"), "{why}"),
        Err(e) => panic!("{e}"),
        Ok(_) => panic!("the exact sweep accepted a bounded reach"),
    }
    let job = exact.prepare(&gpu, DEPTH_SCALE).expect("sweep job");
    match ctx.one_shot(|rec| exact.record_region(rec, &job, [0, 0, 2, 2])) {
        Err(VkError::Invalid(why)) => assert!(why.contains("whole maps"), "{why}"),
        Err(e) => panic!("{e}"),
        Ok(()) => panic!("the exact sweep recorded a region"),
    }
    common::assert_no_validation_errors(&ctx);
}
