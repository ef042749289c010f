//! How well a renderer's shadow term agrees with the exact reference, pixel by pixel.
//!
//! Inputs are visible fractions in [0, 1] per pixel, row-major, with negative markers for pixels that have no
//! receiver (-1: background, -2: the surface faces away from the light); a pixel negative in either image is
//! skipped. Pixels in the edge band (`shadow_edge_band`: within a shadow-map texel or so of an exact shadow
//! edge, where a map of finite resolution cannot be expected to agree) are excluded from *every* statistic and
//! counted in `excluded_band`, so each number describes the same set of pixels.

use std::fmt;

use serde::Serialize;

/// Exact visibility at or above this is "fully lit" (for acne).
const FULLY_LIT: f32 = 0.999;
/// Exact visibility at or below this is "fully occluded" (for leaks).
const FULLY_OCCLUDED: f32 = 0.001;
/// Hard shadows: visible above this.
const LIT: f32 = 0.5;

/// A count of pixels and its share of the compared pixels.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Tally {
    /// How many pixels.
    pub count: usize,
    /// `count / pixels` (0 when no pixel was compared).
    pub share: f64,
}

/// The agreement of a shadow term with the exact reference (see the module docs for which pixels count).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ShadowAgreement {
    /// Receiver pixels compared (outside the band).
    pub pixels: usize,
    /// Receiver pixels left out because they lie in the edge band.
    pub excluded_band: usize,
    /// Share of compared pixels where "visible > 0.5" is the same in both.
    pub hard_agreement: f64,
    /// Mean absolute difference of the visible fractions.
    pub mean_abs_error: f64,
    /// Largest absolute difference.
    pub max_abs_error: f64,
    /// Exactly fully lit (>= 0.999) but reported below 0.5.
    pub acne: Tally,
    /// Exactly fully occluded (<= 0.001) but reported above 0.5.
    pub leaks: Tally,
}

impl fmt::Display for ShadowAgreement {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} pixels ({} in the edge band left out): hard agreement {:.3}%, mean |error| {:.4}, \
             max |error| {:.4}, acne {} ({:.3}%), leaks {} ({:.3}%)",
            self.pixels,
            self.excluded_band,
            100.0 * self.hard_agreement,
            self.mean_abs_error,
            self.max_abs_error,
            self.acne.count,
            100.0 * self.acne.share,
            self.leaks.count,
            100.0 * self.leaks.share,
        )
    }
}

/// Compares `relief` with `exact` (both row-major, same length) outside `band` (same length, or empty for no
/// band). Panics if the lengths differ.
pub fn measure_agreement(exact: &[f32], relief: &[f32], band: &[bool]) -> ShadowAgreement {
    assert_eq!(exact.len(), relief.len(), "exact and relief sizes differ");
    assert!(
        band.is_empty() || band.len() == exact.len(),
        "the band's size differs from the images'"
    );
    let (mut pixels, mut excluded, mut agree, mut acne, mut leaks) = (0, 0, 0, 0, 0);
    let (mut sum, mut max) = (0.0f64, 0.0f64);
    for (k, (&e, &r)) in exact.iter().zip(relief).enumerate() {
        if e < 0.0 || r < 0.0 || e.is_nan() || r.is_nan() {
            continue;
        }
        if band.get(k).copied().unwrap_or(false) {
            excluded += 1;
            continue;
        }
        pixels += 1;
        let error = f64::from((e - r).abs());
        sum += error;
        max = max.max(error);
        agree += usize::from((e > LIT) == (r > LIT));
        acne += usize::from(e >= FULLY_LIT && r < LIT);
        leaks += usize::from(e <= FULLY_OCCLUDED && r > LIT);
    }
    let share = |count: usize| {
        if pixels == 0 {
            0.0
        } else {
            count as f64 / pixels as f64
        }
    };
    ShadowAgreement {
        pixels,
        excluded_band: excluded,
        hard_agreement: if pixels == 0 { 1.0 } else { share(agree) },
        mean_abs_error: if pixels == 0 {
            0.0
        } else {
            sum / pixels as f64
        },
        max_abs_error: max,
        acne: Tally {
            count: acne,
            share: share(acne),
        },
        leaks: Tally {
            count: leaks,
            share: share(leaks),
        },
    }
}

/// The pixels within `radius_px` of an exact shadow edge: a receiver pixel whose hard visibility (> 0.5)
/// differs from a 4-neighbour receiver's is on an edge, and a pixel is in the band when such a pixel lies within
/// its own radius (Euclidean, in pixels). `radius_px` holds one radius per pixel (a shadow-map texel's footprint
/// varies over the image) or a single radius for all. Panics if `exact` is not `width * height` long or
/// `radius_px` has another length than 1 or that.
pub fn shadow_edge_band(
    exact: &[f32],
    width: usize,
    height: usize,
    radius_px: &[f32],
) -> Vec<bool> {
    assert_eq!(exact.len(), width * height, "image size mismatch");
    assert!(
        radius_px.len() == 1 || radius_px.len() == exact.len(),
        "radius_px needs one radius or one per pixel"
    );
    let edge = edge_pixels(exact, width, height);
    (0..exact.len())
        .map(|k| {
            let r = radius_px[if radius_px.len() == 1 { 0 } else { k }].max(0.0);
            near_edge(&edge, width, height, (k % width, k / width), r)
        })
        .collect()
}

/// Receiver pixels whose hard visibility differs from a 4-neighbour receiver's.
fn edge_pixels(exact: &[f32], width: usize, height: usize) -> Vec<bool> {
    let lit = |x: usize, y: usize| {
        let e = exact[y * width + x];
        (e >= 0.0).then_some(e > LIT)
    };
    (0..exact.len())
        .map(|k| {
            let (x, y) = (k % width, k / width);
            let Some(here) = lit(x, y) else {
                return false;
            };
            let neighbours = [
                (x > 0).then(|| (x - 1, y)),
                (x + 1 < width).then(|| (x + 1, y)),
                (y > 0).then(|| (x, y - 1)),
                (y + 1 < height).then(|| (x, y + 1)),
            ];
            neighbours
                .into_iter()
                .flatten()
                .any(|(nx, ny)| lit(nx, ny).is_some_and(|there| there != here))
        })
        .collect()
}

fn near_edge(edge: &[bool], width: usize, height: usize, (x, y): (usize, usize), r: f32) -> bool {
    let reach = r.floor() as usize;
    let (x0, x1) = (x.saturating_sub(reach), (x + reach).min(width - 1));
    let (y0, y1) = (y.saturating_sub(reach), (y + reach).min(height - 1));
    (y0..=y1).any(|ny| {
        (x0..=x1).any(|nx| {
            let (dx, dy) = (nx.abs_diff(x) as f32, ny.abs_diff(y) as f32);
            edge[ny * width + nx] && dx * dx + dy * dy <= r * r
        })
    })
}
