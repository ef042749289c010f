//! The blended terrain pyramid built on the GPU (`blended_pyramid.comp`) against its CPU
//! definition (`terrain::blended_pyramid`) on random layers and weights: level 0 is the blended
//! surface, every node above bounds the blended texels under it, and one-hot weights give the
//! layer's own GPU pyramid back bit for bit (so every method's hits are the single layer's).

mod common;

use relief::heightfield::{Address, Generator, Heightfield, LoadOptions, MaxPyramid};
use relief::render::{build_blended_pyramid_on_gpu, build_pyramid_on_gpu, HeightFormat};
use relief::terrain::{blended_pyramid, BlendMode, LayerStack, SplatMap};

/// Four different fields and a coarse splat map with holes where a layer has no weight.
fn random_stack(width: u32, height: u32, seed: u64) -> LayerStack {
    let generators = [
        Generator::Fbm,
        Generator::Bricks,
        Generator::Spikes,
        Generator::Fbm,
    ];
    let heights = generators
        .iter()
        .enumerate()
        .map(|(k, g)| g.generate(width, height, seed + k as u64))
        .collect();
    // A small deterministic hash for the splat weights (no extra dependency).
    let mut state = seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1;
    let mut next = || {
        state ^= state << 13;
        state ^= state >> 7;
        state ^= state << 17;
        (state >> 40) as f32 / (1u64 << 24) as f32
    };
    let texels = (0..25)
        .map(|_| std::array::from_fn(|_| if next() < 0.3 { 0.0 } else { next() }))
        .collect();
    LayerStack::from_splat(heights, &SplatMap::new(5, 5, texels).unwrap()).unwrap()
}

/// The stack as the GPU stores it in `format`.
fn stored(stack: &LayerStack, format: HeightFormat) -> LayerStack {
    match format {
        HeightFormat::R16Unorm => stack.quantized_unorm16(),
        HeightFormat::R32Float => stack.clone(),
    }
}

/// Builds `stack`'s blended pyramid on the GPU in every format, addressing and mode, and checks
/// it against the CPU's and against the blended texels it must bound.
fn check_stack(ctx: &std::sync::Arc<relief::vk::Context>, name: &str, stack: &LayerStack) {
    let step = 1.0 / 65535.0;
    let (w, h) = (stack.width(), stack.height());
    for format in [HeightFormat::R16Unorm, HeightFormat::R32Float] {
        let seen = stored(stack, format);
        for address in [Address::Repeat, Address::Clamp] {
            let wrap = address == Address::Repeat;
            for mode in BlendMode::ALL {
                let what = format!("{name} {w}x{h} {format:?} {address:?} {mode}");
                let (gpu, ms) = build_blended_pyramid_on_gpu(ctx, stack, mode, format, address)
                    .expect("builds");
                assert!(ms >= 0.0);
                let cpu =
                    blended_pyramid(&seen, mode, |hf| MaxPyramid::build_bilinear_bound(hf, wrap));
                assert_eq!(gpu.len() as u32, cpu.level_count(), "{what}");
                // Level 0 is the surface; the alpha blend's division may round differently.
                let tolerance = match format {
                    HeightFormat::R16Unorm => step * 1.01,
                    HeightFormat::R32Float => 3e-7,
                };
                for (t, (g, c)) in gpu[0].iter().zip(&cpu.level(0).data).enumerate() {
                    assert!((g - c).abs() <= tolerance, "{what}: texel {t}: {g} vs {c}");
                }
                // Above it, the CPU's bound: in 16 bits rounded up to a step, and the convex
                // blends' least weight sums rounded down with it (a little looser); below it by
                // at most the GPU's division error (2.5 ulps, inside the bound's 8-ulp margin).
                let slack = |c: f32| match format {
                    HeightFormat::R16Unorm => step * 1.01 + c * 1e-3,
                    HeightFormat::R32Float => 0.0,
                };
                for (level, data) in gpu.iter().enumerate().skip(1) {
                    let cpu_level = &cpu.level(level as u32).data;
                    for (t, (g, c)) in data.iter().zip(cpu_level).enumerate() {
                        assert!(
                            (-(c * 4e-7 + 1e-9)..=slack(*c)).contains(&(g - c)),
                            "{what}: level {level} node {t}: {g} against the CPU's {c}"
                        );
                    }
                }
                // And every node bounds the GPU's own blended texels under it.
                let surface = Heightfield::new(w, h, gpu[0].clone()).unwrap();
                let exact = MaxPyramid::build_bilinear_bound(&surface, wrap);
                for (level, data) in gpu.iter().enumerate().skip(1) {
                    let exact_level = &exact.level(level as u32).data;
                    for (t, (g, e)) in data.iter().zip(exact_level).enumerate() {
                        assert!(g >= e, "{what}: level {level} node {t}: {g} below {e}");
                    }
                }
            }
        }
    }
}

#[test]
fn the_gpu_blended_pyramid_is_the_cpu_one_and_bounds_the_blended_surface() {
    let Some(ctx) = common::device("the_gpu_blended_pyramid_is_the_cpu_one") else {
        return;
    };
    for (w, h, seed) in [(64, 64, 1), (37, 23, 2)] {
        check_stack(&ctx, "random", &random_stack(w, h, seed));
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn the_corpus_ground_layers_blend_and_bound() {
    let Some(corpus) = common::corpus::corpus("the_corpus_ground_layers_blend_and_bound") else {
        return;
    };
    let Some(ctx) = common::device("the_corpus_ground_layers_blend_and_bound") else {
        return;
    };
    // The corpus's suggested order, low to high: sand, grass, rock, cliff (8-bit, 512^2, tiling).
    let layers = corpus.join("terrain-layers");
    let files = [
        "hterrain-demo/sand_height.png",
        "terrain3d/ground037_height.png",
        "terrain3d/rock030_height.png",
        "terrain3d/rock023_height.png",
    ];
    let heights: Vec<Heightfield> = files
        .iter()
        .map(|f| {
            Heightfield::load_png(&layers.join(f), &LoadOptions::default())
                .unwrap_or_else(|e| panic!("{f}: {e}"))
        })
        .collect();
    assert!(heights
        .iter()
        .all(|h| (h.width(), h.height()) == (512, 512)));
    // Each layer owns a quadrant, blending across the middle: the splat map's four corners.
    let splat = SplatMap::new(
        2,
        2,
        vec![
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ],
    )
    .unwrap();
    let stack = LayerStack::from_splat(heights, &splat).unwrap();
    check_stack(&ctx, "corpus layers", &stack);
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn one_hot_weights_give_the_single_layer_pyramid_bit_for_bit() {
    let Some(ctx) = common::device("one_hot_weights_give_the_single_layer_pyramid") else {
        return;
    };
    let heights: Vec<Heightfield> = (0..4).map(|s| Generator::Fbm.generate(48, 48, s)).collect();
    for format in [HeightFormat::R16Unorm, HeightFormat::R32Float] {
        for only in [0, 3] {
            let single = match format {
                HeightFormat::R16Unorm => heights[only].quantized_unorm16(),
                HeightFormat::R32Float => heights[only].clone(),
            };
            let (alone, _) =
                build_pyramid_on_gpu(&ctx, &single, format, Address::Repeat).expect("builds");
            let stack = LayerStack::one_hot(heights.clone(), only).unwrap();
            for mode in BlendMode::ALL {
                let (blended, _) =
                    build_blended_pyramid_on_gpu(&ctx, &stack, mode, format, Address::Repeat)
                        .expect("builds");
                for (level, (b, a)) in blended.iter().zip(&alone).enumerate() {
                    let same = b.iter().zip(a).all(|(x, y)| x.to_bits() == y.to_bits());
                    assert!(
                        same,
                        "{format:?} {mode}, layer {only}: level {level} differs"
                    );
                }
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}
