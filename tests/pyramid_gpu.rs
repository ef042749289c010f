//! The GPU max pyramid equals the CPU builder texel for texel, at awkward sizes too.

mod common;

use relief::heightfield::Address;
use relief::heightfield::{Generator, Heightfield, MaxPyramid};
use relief::render::{build_pyramid_on_gpu, HeightFormat};

fn check(
    ctx: &std::sync::Arc<relief::vk::Context>,
    hf: &Heightfield,
    format: HeightFormat,
    address: Address,
) {
    let (gpu, ms) = build_pyramid_on_gpu(ctx, hf, format, address).expect("GPU pyramid builds");
    let stored = match format {
        HeightFormat::R16Unorm => hf.quantized_unorm16(),
        HeightFormat::R32Float => hf.clone(),
    };
    let cpu = MaxPyramid::build_bilinear_bound(&stored, address == Address::Repeat);
    assert_eq!(
        gpu.len() as u32,
        cpu.level_count(),
        "{}x{}: level count",
        hf.width(),
        hf.height()
    );
    for (k, (g, c)) in gpu.iter().zip(cpu.levels()).enumerate() {
        let bad = g.iter().zip(&c.data).position(|(a, b)| a != b);
        assert!(
            bad.is_none(),
            "{}x{} {format:?}: level {k} ({}x{}) differs at texel {:?}: gpu {} cpu {}",
            hf.width(),
            hf.height(),
            c.width,
            c.height,
            bad,
            bad.map(|i| g[i]).unwrap_or_default(),
            bad.map(|i| c.data[i]).unwrap_or_default()
        );
    }
    assert!(ms >= 0.0 && ms.is_finite());
}

#[test]
fn gpu_pyramid_equals_cpu_pyramid() {
    let Some(ctx) = common::device("gpu_pyramid_equals_cpu_pyramid") else {
        return;
    };
    for (k, (w, h)) in [(1, 1), (2, 2), (3, 5), (64, 64), (257, 129), (1024, 1024)]
        .into_iter()
        .enumerate()
    {
        let hf = Generator::Noise.generate(w, h, 7 + k as u64);
        check(&ctx, &hf, HeightFormat::R16Unorm, Address::Clamp);
        check(&ctx, &hf, HeightFormat::R16Unorm, Address::Repeat);
    }
    for (w, h) in [(3, 5), (257, 129)] {
        check(
            &ctx,
            &Generator::Fbm.generate(w, h, 3),
            HeightFormat::R32Float,
            Address::Repeat,
        );
    }
    common::assert_no_validation_errors(&ctx);
}
