//! The GPU cone maps, conservative and relaxed, against the CPU builder (the reference): the
//! bound heights equal bit for bit, every ratio at most the CPU's (never a wider cone) and within
//! `RATIO_TOLERANCE` below it, on seeded synthetic fields at awkward sizes under both
//! addressings; conservative cones never step a ray past the first hit of the surface they were
//! built for; relaxed cones relax where they should (a plateau) and let a step cross the surface at
//! most once, so the relaxed walk refines to that first hit.

mod common;

use std::sync::Arc;

use relief::heightfield::cone_map::{trace_cone_cpu, ConeKind, ConeMap};
use relief::heightfield::reference::{trace, Address, SurfaceModel};
use relief::heightfield::{Generator, Heightfield, MapData};
use relief::render::{ConeMapPass, RelaxedConeMapPass, RATIO_TOLERANCE};
use relief::vk::{Context, VkResult};

use common::rays::Rng;

const FIELDS: [Generator; 5] = [
    Generator::Fbm,
    Generator::Noise,
    Generator::Step,
    Generator::Spikes,
    Generator::Bricks,
];
const SIZES: [(u32, u32); 5] = [(1, 1), (2, 2), (3, 5), (64, 64), (257, 129)];
const ADDRESSES: [Address; 2] = [Address::Repeat, Address::Clamp];

/// Both GPU builders, one per kind.
struct Builders {
    ctx: Arc<Context>,
    conservative: ConeMapPass,
    relaxed: RelaxedConeMapPass,
}

impl Builders {
    fn build(
        &self,
        kind: ConeKind,
        hf: &Heightfield,
        address: Address,
    ) -> VkResult<(MapData, f64)> {
        match kind {
            ConeKind::Conservative => self.conservative.build(hf, address),
            ConeKind::Relaxed => self.relaxed.build(hf, address),
        }
    }
}

fn builders() -> Option<Builders> {
    let ctx = common::device("cone_map_gpu")?;
    Some(Builders {
        conservative: ConeMapPass::new(&ctx).expect("cone map pipeline"),
        relaxed: RelaxedConeMapPass::new(&ctx).expect("relaxed cone map pipelines"),
        ctx,
    })
}

/// The GPU map as a `ConeMap`, so the CPU tracer can walk it.
fn as_cone_map(kind: ConeKind, data: &MapData) -> ConeMap {
    assert_eq!(data.channels, 2, "ratio and bound height");
    ConeMap {
        kind,
        width: data.width,
        height: data.height,
        ratio: data.texels.iter().step_by(2).copied().collect(),
        surface: data.texels.iter().skip(1).step_by(2).copied().collect(),
    }
}

/// Compares the GPU map of `kind` for `hf` with the CPU's; returns the GPU map.
fn check(b: &Builders, kind: ConeKind, hf: &Heightfield, address: Address, what: &str) -> ConeMap {
    let what = format!("{kind:?} {what}");
    let (data, gpu_ms) = b.build(kind, hf, address).expect("GPU cone map builds");
    assert!(gpu_ms >= 0.0, "{what}: GPU time {gpu_ms}");
    assert_eq!(
        (data.width, data.height),
        (hf.width(), hf.height()),
        "{what}"
    );
    let gpu = as_cone_map(kind, &data);
    let cpu = ConeMap::build(hf, kind, address);
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
        // For relaxed maps, the quadrants and the reach rounding could cost more than this in
        // principle; on these fields neither does.
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

#[test]
fn gpu_cone_maps_match_the_cpu_builder_from_below() {
    let Some(b) = builders() else {
        return;
    };
    for kind in [ConeKind::Conservative, ConeKind::Relaxed] {
        for (k, generator) in FIELDS.into_iter().enumerate() {
            for (w, h) in SIZES {
                let hf = generator.generate(w, h, 17 + k as u64);
                for address in ADDRESSES {
                    check(
                        &b,
                        kind,
                        &hf,
                        address,
                        &format!("{generator:?} {w}x{h} {address}"),
                    );
                }
            }
        }
    }
    common::assert_no_validation_errors(&b.ctx);
}

#[test]
fn capped_texels_keep_the_cap_exactly() {
    let Some(b) = builders() else {
        return;
    };
    // A flat field: nothing is higher than anything, so every cone is the cap.
    let flat = Generator::Flat0.generate(9, 7, 1);
    for kind in [ConeKind::Conservative, ConeKind::Relaxed] {
        for address in ADDRESSES {
            let gpu = check(&b, kind, &flat, address, &format!("flat {address}"));
            assert!(gpu.ratio.iter().all(|&c| c == 64.0), "{kind:?} {address}");
        }
    }
    common::assert_no_validation_errors(&b.ctx);
}

#[test]
fn relaxation_pays_on_a_plateau() {
    let Some(b) = builders() else {
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
        let what = format!("plateau {address}");
        let relaxed = check(&b, ConeKind::Relaxed, &hf, address, &what);
        let conservative = check(&b, ConeKind::Conservative, &hf, address, &what);
        let wider = relaxed
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
    common::assert_no_validation_errors(&b.ctx);
}

#[test]
fn gpu_cones_never_step_past_the_first_hit() {
    let Some(b) = builders() else {
        return;
    };
    let mut rng = Rng(5);
    for kind in [ConeKind::Conservative, ConeKind::Relaxed] {
        for generator in [Generator::Fbm, Generator::Spikes, Generator::Step] {
            for (w, h) in [(16, 16), (33, 17)] {
                let hf = generator.generate(w, h, u64::from(w * 31 + h));
                for address in ADDRESSES {
                    let what = format!("{generator:?} {w}x{h} {address}");
                    let map = check(&b, kind, &hf, address, &what);
                    let bound = Heightfield::new(w, h, map.surface.clone()).expect("valid heights");
                    for _ in 0..150 {
                        let ray = rng.ray();
                        let s = 0.02 + 0.3 * rng.next();
                        let first = trace(&bound, &ray, s, SurfaceModel::Nearest, address).z;
                        let at = format!("{kind:?} {what} {ray:?} s={s}");
                        // The cones are exact for the bound's boxes. A conservative walk ends on
                        // their first hit, and a short budget stops above it. A relaxed step may
                        // enter the solid but never leave it: had one crossed the surface twice,
                        // the walk would go on above a later stretch and refine to a later hit.
                        let refine = if kind == ConeKind::Relaxed { 64 } else { 0 };
                        let walked = trace_cone_cpu(&hf, &map, &ray, s, address, 100_000, refine);
                        assert!(!walked.capped, "{at}");
                        assert!(
                            (walked.z - first).abs() <= 1e-9,
                            "{at}: ended at {} for the first hit {first}",
                            walked.z
                        );
                        if kind == ConeKind::Conservative {
                            let short = trace_cone_cpu(&hf, &map, &ray, s, address, 3, 0);
                            assert!(short.z <= first + 1e-9, "{at}: {} past {first}", short.z);
                        }
                    }
                }
            }
        }
    }
    common::assert_no_validation_errors(&b.ctx);
}
