//! The GPU conservative cone map against the CPU builder (the reference): the bound heights equal
//! bit for bit, every ratio at most the CPU's and within `RATIO_TOLERANCE` below it, on seeded
//! synthetic fields at awkward sizes under both addressings; and cones read from the GPU map never
//! step a ray past the first hit of the surface they were built for.

mod common;

use std::sync::Arc;

use relief::heightfield::cone_map::{trace_cone_cpu, ConeKind, ConeMap};
use relief::heightfield::reference::{trace, Address, RefRay, SurfaceModel};
use relief::heightfield::{Generator, Heightfield, MapData};
use relief::render::{ConeMapPass, RATIO_TOLERANCE};
use relief::vk::Context;

const FIELDS: [Generator; 5] = [
    Generator::Fbm,
    Generator::Noise,
    Generator::Step,
    Generator::Spikes,
    Generator::Bricks,
];
const SIZES: [(u32, u32); 5] = [(1, 1), (2, 2), (3, 5), (64, 64), (257, 129)];
const ADDRESSES: [Address; 2] = [Address::Repeat, Address::Clamp];

/// The GPU map as a `ConeMap`, so the CPU tracer can walk it.
fn as_cone_map(data: &MapData) -> ConeMap {
    assert_eq!(data.channels, 2, "ratio and bound height");
    ConeMap {
        kind: ConeKind::Conservative,
        width: data.width,
        height: data.height,
        ratio: data.texels.iter().step_by(2).copied().collect(),
        surface: data.texels.iter().skip(1).step_by(2).copied().collect(),
    }
}

/// Compares the GPU map of `hf` with the CPU's; returns the GPU map.
fn check(pass: &ConeMapPass, hf: &Heightfield, address: Address, what: &str) -> ConeMap {
    let (data, gpu_ms) = pass.build(hf, address).expect("GPU cone map builds");
    assert!(gpu_ms >= 0.0, "{what}: GPU time {gpu_ms}");
    assert_eq!(
        (data.width, data.height),
        (hf.width(), hf.height()),
        "{what}"
    );
    let gpu = as_cone_map(&data);
    let cpu = ConeMap::build(hf, ConeKind::Conservative, address);
    let surface_diff = gpu
        .surface
        .iter()
        .zip(&cpu.surface)
        .position(|(g, c)| g.to_bits() != c.to_bits());
    assert_eq!(surface_diff, None, "{what}: bound height differs");
    let (mut exact, mut worst) = (0, 0.0f64);
    for (k, (&g, &c)) in gpu.ratio.iter().zip(&cpu.ratio).enumerate() {
        let texel = (k as u32 % hf.width(), k as u32 / hf.width());
        assert!(g.is_finite() && g >= 0.0, "{what} {texel:?}: ratio {g}");
        assert!(
            g <= c,
            "{what} {texel:?}: GPU cone {g} wider than the CPU's {c}"
        );
        assert!(
            g >= c * (1.0 - RATIO_TOLERANCE),
            "{what} {texel:?}: GPU ratio {g} too far below the CPU's {c}"
        );
        exact += usize::from(g == c);
        worst = worst.max(1.0 - f64::from(g) / f64::from(c));
    }
    eprintln!(
        "{what}: {exact} of {} ratios equal the CPU's bit for bit; at most {worst:.2e} below",
        gpu.ratio.len()
    );
    gpu
}

fn context() -> Option<(Arc<Context>, ConeMapPass)> {
    let ctx = common::device("cone_map_gpu")?;
    let pass = ConeMapPass::new(&ctx).expect("cone map pipeline");
    Some((ctx, pass))
}

#[test]
fn gpu_cone_map_matches_the_cpu_builder_from_below() {
    let Some((ctx, pass)) = context() else {
        return;
    };
    for (k, generator) in FIELDS.into_iter().enumerate() {
        for (w, h) in SIZES {
            let hf = generator.generate(w, h, 17 + k as u64);
            for address in ADDRESSES {
                let what = format!("{generator:?} {w}x{h} {address}");
                check(&pass, &hf, address, &what);
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn capped_texels_keep_the_cap_exactly() {
    let Some((ctx, pass)) = context() else {
        return;
    };
    // A flat field: nothing is higher than anything, so every cone is the cap.
    let flat = Generator::Flat0.generate(9, 7, 1);
    for address in ADDRESSES {
        let gpu = check(&pass, &flat, address, &format!("flat {address}"));
        assert!(gpu.ratio.iter().all(|&c| c == 64.0), "{address}");
    }
    common::assert_no_validation_errors(&ctx);
}

/// A small deterministic generator for the rays (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }

    /// Elevation in [5, 90] degrees, any azimuth, entry anywhere in the first tile.
    fn ray(&mut self) -> RefRay {
        let e = (5.0 + 85.0 * self.next()).to_radians();
        let a = (360.0 * self.next()).to_radians();
        RefRay {
            u0: self.next(),
            v0: self.next(),
            dx: e.cos() * a.cos(),
            dy: e.cos() * a.sin(),
            dz: e.sin(),
        }
    }
}

#[test]
fn gpu_cones_never_step_past_the_first_hit() {
    let Some((ctx, pass)) = context() else {
        return;
    };
    let mut rng = Rng(5);
    for generator in [Generator::Fbm, Generator::Spikes, Generator::Step] {
        for (w, h) in [(16, 16), (33, 17)] {
            let hf = generator.generate(w, h, u64::from(w * 31 + h));
            for address in ADDRESSES {
                let what = format!("{generator:?} {w}x{h} {address}");
                let map = check(&pass, &hf, address, &what);
                let bound = Heightfield::new(w, h, map.surface.clone()).expect("valid heights");
                for _ in 0..150 {
                    let ray = rng.ray();
                    let s = 0.02 + 0.3 * rng.next();
                    // The cones are exact for the bound's boxes: the walk must end on their
                    // first hit, never below it, and a short budget must stop above it.
                    let first = trace(&bound, &ray, s, SurfaceModel::Nearest, address).z;
                    let walked = trace_cone_cpu(&hf, &map, &ray, s, address, 100_000, 0);
                    let at = format!("{what} {ray:?} s={s}");
                    assert!(!walked.capped, "{at}");
                    assert!(
                        (walked.z - first).abs() <= 1e-9,
                        "{at}: ended at {} for the first hit {first}",
                        walked.z
                    );
                    let short = trace_cone_cpu(&hf, &map, &ray, s, address, 3, 0);
                    assert!(short.z <= first + 1e-9, "{at}: {} past {first}", short.z);
                }
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}
