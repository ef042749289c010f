//! The GPU AO map (`AoMapPass`) against the exact CPU reference (`ao_reference`, `ao_at_texel`):
//! a flat field gives exactly 1 in every mode; `horizon-8` stays within 0.03 and `exact-horizon`
//! within 0.01 mean absolute error on seeded fbm and bricks fields under both addressings;
//! degenerate fields (1x1, 2x2, 3x5, constant, spikes, a huge depth scale) give finite values in
//! [0, 1]; and a real height map from the shared corpus is checked on a seeded texel subset.
//! References are kept small (32x32) so the whole file runs in seconds on two cores.

mod common;

use std::sync::Arc;

use relief::heightfield::ambient_occlusion::{ao_at_texel, ao_reference};
use relief::heightfield::{Address, Channel, Generator, Heightfield, LoadOptions};
use relief::render::{AoMapPass, GpuHeightfield, HeightFormat, PyramidPass};
use relief::scene::AoMode;
use relief::vk::{raw, read_mip, Context};

const ADDRESSES: [Address; 2] = [Address::Repeat, Address::Clamp];
const REFERENCE_AZIMUTHS: u32 = 256;
const HORIZON_8: AoMode = AoMode::Horizon {
    directions: 8,
    rotated: false,
};

/// Every mode that builds a map, each with its pass.
fn passes(ctx: &Arc<Context>) -> Vec<AoMapPass> {
    AoMode::all()
        .into_iter()
        .filter(|m| m.is_some())
        .map(|m| AoMapPass::new(ctx, m).expect("AO pipeline"))
        .collect()
}

fn build(pass: &AoMapPass, hf: &Heightfield, s: f64, address: Address) -> Vec<f32> {
    let (ao, gpu_ms) = pass.build(hf, s, address).expect("AO map builds");
    assert_eq!(ao.len(), hf.texel_count());
    assert!(gpu_ms >= 0.0, "GPU time {gpu_ms}");
    ao
}

fn mean_abs(a: &[f32], b: &[f32]) -> f64 {
    let sum: f64 = a.iter().zip(b).map(|(x, y)| f64::from((x - y).abs())).sum();
    sum / a.len() as f64
}

#[test]
fn flat_fields_give_exactly_one_in_every_mode() {
    let Some(ctx) = common::device("ao_map_gpu flat") else {
        return;
    };
    let fields = [
        Generator::Flat0.generate(16, 16, 1),
        Generator::Flat1.generate(5, 3, 1),
        Heightfield::new(1, 1, vec![0.25]).expect("valid"),
        Heightfield::new(7, 4, vec![0.37; 28]).expect("valid"),
    ];
    for pass in passes(&ctx) {
        for hf in &fields {
            for address in ADDRESSES {
                let ao = build(&pass, hf, 0.1, address);
                let what = format!("{} {}x{} {address}", pass.mode(), hf.width(), hf.height());
                assert!(ao.iter().all(|&v| v == 1.0), "{what}: {ao:?}");
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn maps_meet_the_exact_reference() {
    let Some(ctx) = common::device("ao_map_gpu reference") else {
        return;
    };
    let horizon = AoMapPass::new(&ctx, HORIZON_8).expect("horizon pipeline");
    let exact = AoMapPass::new(&ctx, AoMode::ExactHorizon).expect("sweep pipeline");
    let cases = [(Generator::Fbm, 0.08, 11), (Generator::Bricks, 0.05, 12)];
    for (generator, s, seed) in cases {
        let hf = generator.generate(32, 32, seed);
        for address in ADDRESSES {
            let reference = ao_reference(&hf, s, address, REFERENCE_AZIMUTHS).expect("reference");
            let h8 = mean_abs(&build(&horizon, &hf, s, address), &reference);
            let ex = mean_abs(&build(&exact, &hf, s, address), &reference);
            let what = format!("{generator:?} 32x32 s={s} {address}");
            eprintln!("{what}: mean abs error horizon-8 {h8:.4}, exact-horizon {ex:.4}");
            assert!(h8 <= 0.03, "{what}: horizon-8 mean abs error {h8}");
            assert!(ex <= 0.01, "{what}: exact-horizon mean abs error {ex}");
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn degenerate_fields_stay_finite_and_in_range() {
    let Some(ctx) = common::device("ao_map_gpu degenerate") else {
        return;
    };
    let cases = [
        (Generator::Fbm.generate(1, 1, 3), 0.1),
        (Generator::Noise.generate(2, 2, 4), 0.1),
        (Generator::Fbm.generate(3, 5, 5), 0.1),
        (Generator::Spikes.generate(17, 9, 6), 0.1),
        (Generator::Step.generate(8, 8, 7), 0.3),
        (Generator::Fbm.generate(16, 16, 8), 50.0),
    ];
    for pass in passes(&ctx) {
        for (hf, s) in &cases {
            for address in ADDRESSES {
                let ao = build(&pass, hf, *s, address);
                let what = format!(
                    "{} {}x{} s={s} {address}",
                    pass.mode(),
                    hf.width(),
                    hf.height()
                );
                let bad = ao.iter().position(|v| !(0.0..=1.0).contains(v));
                assert_eq!(bad, None, "{what}: {ao:?}");
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn exact_horizon_meets_the_reference_on_tiny_and_steep_fields() {
    let Some(ctx) = common::device("ao_map_gpu tiny") else {
        return;
    };
    let exact = AoMapPass::new(&ctx, AoMode::ExactHorizon).expect("sweep pipeline");
    let cases = [
        (Generator::Noise.generate(2, 2, 4), 0.1),
        (Generator::Fbm.generate(3, 5, 5), 0.1),
        (Generator::Spikes.generate(17, 9, 6), 0.1),
        (Generator::Fbm.generate(16, 16, 8), 2.0),
        // Coprime sides: diagonal orbits run around the whole map and are walked in segments.
        (Generator::Bricks.generate(37, 23, 9), 0.1),
    ];
    for (hf, s) in &cases {
        for address in ADDRESSES {
            let reference = ao_reference(hf, *s, address, REFERENCE_AZIMUTHS).expect("reference");
            let error = mean_abs(&build(&exact, hf, *s, address), &reference);
            let what = format!("{}x{} s={s} {address}", hf.width(), hf.height());
            eprintln!("{what}: exact-horizon mean abs error {error:.4}");
            assert!(error <= 0.01, "{what}: mean abs error {error}");
        }
    }
    common::assert_no_validation_errors(&ctx);
}

/// The renderer's path: an R16 height image (with its pyramid for the horizon mode, without for
/// the sweep), `prepare`, `record` into a submission, `into_map`; the map is read back from its
/// image, which must be left in `SHADER_READ_ONLY_OPTIMAL`.
#[test]
fn renderer_path_with_r16_heights() {
    let Some(ctx) = common::device("ao_map_gpu renderer path") else {
        return;
    };
    let hf = Generator::Fbm.generate(24, 24, 31).quantized_unorm16();
    let (s, address) = (0.08, Address::Repeat);
    let reference = ao_reference(&hf, s, address, REFERENCE_AZIMUTHS).expect("reference");
    for (mode, bound) in [(HORIZON_8, 0.03), (AoMode::ExactHorizon, 0.01)] {
        let format = HeightFormat::R16Unorm;
        let gpu = if mode == AoMode::ExactHorizon {
            GpuHeightfield::upload_without_pyramid(&ctx, &hf, format, address).expect("upload")
        } else {
            let gpu = GpuHeightfield::upload(&ctx, &hf, format, address).expect("upload");
            let pyramid = PyramidPass::new(&ctx, format.shader_suffix()).expect("pyramid");
            let job = pyramid.prepare(&gpu).expect("pyramid job");
            ctx.one_shot(|rec| pyramid.record(rec, &gpu, &job))
                .expect("pyramid");
            gpu
        };
        let pass = AoMapPass::new(&ctx, mode).expect("AO pipeline");
        let job = pass.prepare(&gpu, s as f32).expect("AO job");
        ctx.one_shot(|rec| pass.record(rec, &job))
            .expect("AO build");
        let map = job.into_map();
        let layout = raw::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let bytes = read_mip(&ctx, &map.image, 0, layout).expect("read back");
        let ao = le_floats(&bytes);
        let error = mean_abs(&ao, &reference);
        eprintln!("{mode} through prepare/record, R16 heights: mean abs error {error:.4}");
        assert!(error <= bound, "{mode}: mean abs error {error}");
    }
    common::assert_no_validation_errors(&ctx);
}

/// Little-endian f32s from bytes.
fn le_floats(bytes: &[u8]) -> Vec<f32> {
    bytes
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect()
}

/// Mean absolute error of `ao` against the reference at `count` seeded texels.
fn subset_error(hf: &Heightfield, s: f64, address: Address, ao: &[f32], count: u32) -> f64 {
    let (w, n) = (hf.width(), hf.texel_count() as u64);
    let mut state = 7u64;
    let mut sum = 0.0;
    for _ in 0..count {
        // A linear congruential walk over the texels: seeded, spread, no extra crate.
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1);
        let k = ((state >> 33) % n) as u32;
        let reference = ao_at_texel(hf, s, address, (k % w, k / w), REFERENCE_AZIMUTHS);
        sum += (f64::from(ao[k as usize]) - reference.expect("reference").value).abs();
    }
    sum / f64::from(count)
}

/// Both passes at the size the horizon pass was tuned for (128x128), on a texel subset. The
/// sweep's bound is tighter than its 0.01 target: it measures about 0.0002 here, and a version
/// that drifted to 0.006 at this size (but not at 64) must not pass.
#[test]
fn maps_meet_the_reference_at_128() {
    let Some(ctx) = common::device("ao_map_gpu 128") else {
        return;
    };
    let horizon = AoMapPass::new(&ctx, HORIZON_8).expect("horizon pipeline");
    let exact = AoMapPass::new(&ctx, AoMode::ExactHorizon).expect("sweep pipeline");
    let cases = [
        (Generator::Fbm, 0.1, Address::Repeat),
        (Generator::Bricks, 0.05, Address::Clamp),
    ];
    for (generator, s, address) in cases {
        let hf = generator.generate(128, 128, 21);
        let what = format!("{generator:?} 128x128 s={s} {address}");
        for (pass, bound) in [(&horizon, 0.03), (&exact, 0.002)] {
            let error = subset_error(&hf, s, address, &build(pass, &hf, s, address), 40);
            eprintln!(
                "{what}: {} mean abs error {error:.4} on 40 texels",
                pass.mode()
            );
            assert!(
                error <= bound,
                "{what}: {} mean abs error {error}",
                pass.mode()
            );
        }
    }
    common::assert_no_validation_errors(&ctx);
}

/// Long walks: under repeat a 256x256 orbit is walked twice (512 steps, 12 profile points a step
/// on the steepest azimuths), past lavapipe's 65535 loop iterations per invocation when walked in
/// one dispatch (mean error 0.06 then, texels late on the walks left unoccluded); resumed walks of
/// `CHUNK_STEPS` per dispatch meet the reference as clamp does.
#[test]
fn exact_horizon_repeat_at_256() {
    let Some(ctx) = common::device("ao_map_gpu repeat 256") else {
        return;
    };
    let exact = AoMapPass::new(&ctx, AoMode::ExactHorizon).expect("sweep pipeline");
    let hf = Generator::Bricks.generate(256, 256, 1);
    let (s, address) = (0.1, Address::Repeat);
    let error = subset_error(&hf, s, address, &build(&exact, &hf, s, address), 40);
    eprintln!("bricks 256x256 repeat: exact-horizon mean abs error {error:.4} on 40 texels");
    assert!(error <= 0.002, "mean abs error {error}");
    common::assert_no_validation_errors(&ctx);
}

/// A small real depth map from the shared corpus, compared on 48 seeded texels.
#[test]
fn corpus_height_map_meets_the_reference_on_a_subset() {
    let Some(corpus) = common::corpus::corpus("ao_map_gpu corpus") else {
        return;
    };
    let path = corpus.join("heightmaps/bevy-parallax/cube_depth.png");
    if !path.is_file() {
        eprintln!(
            "SKIPPED: {} not present (ao_map_gpu corpus)",
            path.display()
        );
        return;
    }
    let Some(ctx) = common::device("ao_map_gpu corpus") else {
        return;
    };
    let options = LoadOptions {
        channel: Channel::Luma,
        invert: true,
    };
    let hf = Heightfield::load_png(&path, &options).expect("corpus depth map loads");
    let (s, address) = (0.05, Address::Repeat);
    let pass = AoMapPass::new(&ctx, HORIZON_8).expect("horizon pipeline");
    let ao = build(&pass, &hf, s, address);
    let mean = subset_error(&hf, s, address, &ao, 48);
    eprintln!("cube_depth.png 348x348: horizon-8 mean abs error {mean:.4} on 48 texels");
    assert!(mean <= 0.03, "horizon-8 mean abs error {mean}");
    assert!(ao.iter().all(|v| (0.0..=1.0).contains(v)));
    common::assert_no_validation_errors(&ctx);
}
