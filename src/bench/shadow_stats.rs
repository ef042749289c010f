//! Error of a shadow mode's visible fractions against the exact reference
//! (`heightfield::visibility`): at each traced hit, the GPU's fraction next to the exact fraction
//! of the light's disk seen from the bilinear surface at the hit's uv. The reference is many exact
//! rays per point, so the points are split between two threads.

use serde::{Deserialize, Serialize};

use super::trace_stats::Spread;
use crate::heightfield::visibility::{light_visibility, LightDir, ShadingError};
use crate::heightfield::{Address, Heightfield};

/// A reference below this counts as "in shadow" for the leak rate.
pub const LEAK_DARK: f64 = 0.05;
/// A method above this where the reference is dark leaks light.
pub const LEAK_LIT: f64 = 0.5;

/// How a shadow mode's fractions compare with the exact ones.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
pub struct ShadowStats {
    /// Points compared (hits with a finite uv and fraction).
    pub points: usize,
    /// Absolute difference of the visible fraction.
    pub abs_error: Spread,
    /// Share of points whose reference is below [`LEAK_DARK`] and method above [`LEAK_LIT`].
    pub leak_rate: f64,
    /// Share of points on the same side of 0.5 as the reference (the hard-shadow verdict).
    pub agreement: f64,
    /// Points whose GPU fraction is NaN or outside [0, 1].
    pub bad_values: usize,
    /// Mean of the reference's fractions (how much of the view is lit at all).
    pub reference_mean: f64,
}

/// Compares `visible[k]` at hit `hits[k]` (`u_hit` and `v_hit` in columns 5 and 6) with the exact
/// visible fraction of `light`, estimated with `samples_per_side^2` exact rays per point.
pub fn shadow_stats(
    hf: &Heightfield,
    hits: &[[f32; 8]],
    visible: &[f32],
    depth_scale: f64,
    address: Address,
    light: LightDir,
    samples_per_side: u32,
) -> Result<ShadowStats, ShadingError> {
    let reference = reference_fractions(hf, hits, depth_scale, address, light, samples_per_side)?;
    Ok(compare_fractions(visible, &reference))
}

/// Compares `visible[k]` with `reference[k]` (skipped where `None`).
pub fn compare_fractions(visible: &[f32], reference: &[Option<f64>]) -> ShadowStats {
    let mut errors = Vec::with_capacity(visible.len());
    let (mut leaks, mut agree, mut bad, mut lit) = (0usize, 0usize, 0usize, 0.0);
    for (&got, exact) in visible.iter().zip(reference) {
        let Some(exact) = *exact else { continue };
        let got = f64::from(got);
        if !(0.0..=1.0).contains(&got) {
            bad += 1;
            continue;
        }
        errors.push((got - exact).abs());
        leaks += usize::from(exact < LEAK_DARK && got > LEAK_LIT);
        agree += usize::from((exact >= 0.5) == (got >= 0.5));
        lit += exact;
    }
    let points = errors.len();
    let share = |n: usize| {
        if points == 0 {
            0.0
        } else {
            n as f64 / points as f64
        }
    };
    ShadowStats {
        points,
        abs_error: Spread::of(errors),
        leak_rate: share(leaks),
        agreement: share(agree),
        bad_values: bad,
        reference_mean: if points == 0 {
            0.0
        } else {
            lit / points as f64
        },
    }
}

/// The exact fraction at each hit's uv (`None` where the hit is not finite), with
/// `samples_per_side^2` exact rays per point, split between two threads.
pub fn reference_fractions(
    hf: &Heightfield,
    hits: &[[f32; 8]],
    depth_scale: f64,
    address: Address,
    light: LightDir,
    samples_per_side: u32,
) -> Result<Vec<Option<f64>>, ShadingError> {
    // Checks the arguments once, so the threads below cannot fail.
    light_visibility(hf, depth_scale, address, (0.5, 0.5), light, 1)?;
    let mut out = vec![None; hits.len()];
    let half = hits.len().div_ceil(2).max(1);
    std::thread::scope(|scope| {
        for (rows, part) in hits.chunks(half).zip(out.chunks_mut(half)) {
            scope.spawn(move || {
                for (hit, slot) in rows.iter().zip(part) {
                    let (u, v) = (f64::from(hit[5]), f64::from(hit[6]));
                    if !(u.is_finite() && v.is_finite()) {
                        continue;
                    }
                    *slot =
                        light_visibility(hf, depth_scale, address, (u, v), light, samples_per_side)
                            .ok()
                            .map(|vis| vis.fraction);
                }
            });
        }
    });
    Ok(out)
}
