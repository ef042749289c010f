//! The GPU relaxed cone map against the CPU builder (the reference): the bound heights equal bit
//! for bit, every ratio at most the CPU's (never a wider cone) and within `RATIO_TOLERANCE` below
//! it, on seeded synthetic fields at awkward sizes under both addressings; relaxation pays where it
//! should (a plateau); and rays walked through the GPU map cross the surface at most once per step,
//! so the relaxed walk refines to the first hit of the surface the map was built for.

mod common;

use std::sync::Arc;

use relief::heightfield::cone_map::{trace_cone_cpu, ConeKind, ConeMap};
use relief::heightfield::reference::{trace, Address, RefRay, SurfaceModel};
use relief::heightfield::{Generator, Heightfield, MapData};
use relief::render::{RelaxedConeMapPass, RATIO_TOLERANCE};
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
        kind: ConeKind::Relaxed,
        width: data.width,
        height: data.height,
        ratio: data.texels.iter().step_by(2).copied().collect(),
        surface: data.texels.iter().skip(1).step_by(2).copied().collect(),
    }
}

/// Compares the GPU map of `hf` with the CPU's; returns the GPU map.
fn check(pass: &RelaxedConeMapPass, hf: &Heightfield, address: Address, what: &str) -> ConeMap {
    let (data, gpu_ms) = pass
        .build(hf, address)
        .expect("GPU relaxed cone map builds");
    assert!(gpu_ms >= 0.0, "{what}: GPU time {gpu_ms}");
    assert_eq!(
        (data.width, data.height),
        (hf.width(), hf.height()),
        "{what}"
    );
    let gpu = as_cone_map(&data);
    let cpu = ConeMap::build(hf, ConeKind::Relaxed, address);
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
        // Quadrants for sectors and the reach rounding could cost more than this in principle;
        // on these fields neither does.
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

fn context() -> Option<(Arc<Context>, RelaxedConeMapPass)> {
    let ctx = common::device("relaxed_cone_map_gpu")?;
    let pass = RelaxedConeMapPass::new(&ctx).expect("relaxed cone map pipelines");
    Some((ctx, pass))
}

#[test]
fn gpu_relaxed_cone_map_matches_the_cpu_builder_from_below() {
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
fn relaxation_pays_on_a_plateau() {
    let Some((ctx, pass)) = context() else {
        return;
    };
    // A raised square plateau on a flat floor: rays entering the plateau cannot leave it before
    // its far edge, so its neighbours' relaxed cones are far wider than their conservative ones.
    let (w, h) = (32, 32);
    let data = (0..w * h)
        .map(|k| {
            let (i, j) = (k % w, k / w);
            if (8..24).contains(&i) && (8..24).contains(&j) {
                0.6
            } else {
                0.1
            }
        })
        .collect();
    let hf = Heightfield::new(w, h, data).expect("valid heights");
    for address in ADDRESSES {
        let gpu = check(&pass, &hf, address, &format!("plateau {address}"));
        let conservative = ConeMap::build(&hf, ConeKind::Conservative, address);
        let wider = gpu
            .ratio
            .iter()
            .zip(&conservative.ratio)
            .filter(|(r, c)| **r > **c * 1.5)
            .count();
        assert!(
            wider >= 100,
            "{address}: only {wider} relaxed cones 1.5x wider"
        );
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
fn gpu_relaxed_steps_refine_to_the_first_hit() {
    let Some((ctx, pass)) = context() else {
        return;
    };
    let mut rng = Rng(9);
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
                    // A step may enter the solid but never leave it: had one crossed the surface
                    // twice, the walk would go on above a later stretch of surface and refine
                    // to a later hit. With any budget it stops, the refinement must land on the
                    // first hit of the bound's boxes.
                    let first = trace(&bound, &ray, s, SurfaceModel::Nearest, address).z;
                    let at = format!("{what} {ray:?} s={s}");
                    let walked = trace_cone_cpu(&hf, &map, &ray, s, address, 100_000, 64);
                    assert!(!walked.capped, "{at}");
                    assert!(
                        (walked.z - first).abs() <= 1e-9,
                        "{at}: refined to {} for the first hit {first}",
                        walked.z
                    );
                }
            }
        }
    }
    common::assert_no_validation_errors(&ctx);
}
