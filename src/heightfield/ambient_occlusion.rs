//! Exact ambient occlusion at texel centres of the bilinear surface (docs/conventions.md, "Lights, shadows and ambient occlusion"):
//! `AO = (1/pi) * integral over the hemisphere about the normal of V(w) cos(n, w) dw`, with `V = 1` when the
//! ray leaves the top plane without passing below the surface, and the normal from central differences.
//!
//! Method: exact horizons. On a height field, the rays of one azimuth `phi` that pass below the surface are
//! exactly those below its *horizon*: the ray at elevation `theta` is blocked iff `tan(theta) < tau(phi)`,
//! where `tau(phi) = sup over x > 0 of s (h(x) - h_p) / x` along the horizontal line from the point (`x` is
//! the distance in uv units). Rays at or below the horizontal never leave the top plane, so the effective
//! horizon is `max(tau, 0)`. `tau` is computed exactly by walking the bilinear cells along the line
//! (`cell_walk`): in each, `h` is a quadratic in `x`, so `s (h - h_p) / x` is maximised in closed form
//! (the cell's ends and the stationary point `x* = sqrt(c0 / c2)`). The walk stops once the highest texel,
//! seen from beyond the distance walked, could not raise the horizon. The elevation integral above the lower
//! limit `max(horizon, edge of the normal's hemisphere)` is then closed-form:
//!
//! `integral from t0 to pi/2 of (n_z sin t + c cos t) cos t dt = n_z cos^2(t0) / 2 + c ((pi/2 - t0)/2 - sin(2 t0)/4)`
//!
//! with `c = n_x cos(phi) + n_y sin(phi)` (unit normal). Only the azimuth integral is numerical: the midpoint
//! rule over `azimuths` equal slices. A flat field gives exactly 1; beside a long low wall the error is at
//! rounding level with 64 slices; a horizon that changes abruptly with azimuth (a tall wall seen edge-on, a
//! spike) converges as `1/azimuths` (about 1e-3 with 256 slices for an 89-degree wall, see the tests).
//!
//! Cost: each walk ends once `x > s (h_max - h_p) / tau`; only lines that find nothing higher for a long way
//! (rare over repeating maps) walk to [`MAX_HORIZON_CELLS`], which [`AoTexel::capped_azimuths`] reports.

use std::f64::consts::{FRAC_PI_2, TAU};
use std::ops::ControlFlow;

use super::cell_walk::{Field, Segment, WalkEnd};
use super::reference::{texel_index, Address};
use super::visibility::{check_count, check_depth_scale, ShadingError};
use super::Heightfield;

/// The most azimuth slices accepted.
pub const MAX_AZIMUTHS: u32 = 1 << 16;

/// The most cells one horizon walk visits. A capped walk keeps the horizon found so far, which can only
/// miss occluders seen below `atan(s (h_max - h_p) / distance walked)`.
pub const MAX_HORIZON_CELLS: u32 = 1 << 20;

/// Horizons flatter than this tangent count as 0 for the walk's stopping test: what it may miss is a band of
/// directions below elevation 1e-9 rad, less than 1e-9 of the AO.
const TAU_FLOOR: f64 = 1e-9;

/// AO at one texel centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AoTexel {
    /// The ambient occlusion in [0, 1] (1 = unoccluded).
    pub value: f64,
    /// Azimuth slices whose horizon walk hit [`MAX_HORIZON_CELLS`] (0 in any ordinary case).
    pub capped_azimuths: u32,
}

/// The unit surface normal at texel `(i, j)` in (u, v, up) units: `(-s dh/du, -s dh/dv, 1)` normalised, the
/// derivatives as central differences `(h[i+1] - h[i-1]) * W / 2` with the map's addressing.
///
/// Panics if `(i, j)` is outside the map.
pub fn texel_normal(
    hf: &Heightfield,
    depth_scale: f64,
    address: Address,
    i: u32,
    j: u32,
) -> [f64; 3] {
    let (w, h) = (hf.width(), hf.height());
    assert!(i < w && j < h, "texel ({i}, {j}) outside {w}x{h}");
    let at = |di: i64, dj: i64| {
        let x = texel_index(i64::from(i) + di, w, address);
        let y = texel_index(i64::from(j) + dj, h, address);
        f64::from(hf.get(x, y))
    };
    let dh_du = (at(1, 0) - at(-1, 0)) * f64::from(w) / 2.0;
    let dh_dv = (at(0, 1) - at(0, -1)) * f64::from(h) / 2.0;
    let n = [-depth_scale * dh_du, -depth_scale * dh_dv, 1.0];
    let len = (n[0] * n[0] + n[1] * n[1] + 1.0).sqrt();
    n.map(|c| c / len)
}

/// AO at texel `(i, j)` with `azimuths` slices. Errors on a bad depth scale or count; panics if `(i, j)` is
/// outside the map.
pub fn ao_at_texel(
    hf: &Heightfield,
    depth_scale: f64,
    address: Address,
    (i, j): (u32, u32),
    azimuths: u32,
) -> Result<AoTexel, ShadingError> {
    check_depth_scale(depth_scale)?;
    check_count("azimuths", azimuths, 1, MAX_AZIMUTHS)?;
    let field = Field::new(hf, depth_scale, address);
    Ok(ao_texel(&field, i, j, azimuths))
}

/// AO at every texel centre, row-major (`j * W + i`), with `azimuths` slices each; deterministic (rows are
/// split between two threads, each texel computed alone).
///
/// Errors: `depth_scale` negative or not finite, `azimuths` outside `1..=MAX_AZIMUTHS`.
pub fn ao_reference(
    hf: &Heightfield,
    depth_scale: f64,
    address: Address,
    azimuths: u32,
) -> Result<Vec<f32>, ShadingError> {
    check_depth_scale(depth_scale)?;
    check_count("azimuths", azimuths, 1, MAX_AZIMUTHS)?;
    let field = Field::new(hf, depth_scale, address);
    let w = hf.width() as usize;
    let mut out = vec![0.0f32; hf.texel_count()];
    let rows_per_thread = (hf.height() as usize).div_ceil(2);
    std::thread::scope(|scope| {
        for (chunk_index, chunk) in out.chunks_mut(rows_per_thread * w).enumerate() {
            let field = &field;
            scope.spawn(move || {
                for (k, value) in chunk.iter_mut().enumerate() {
                    let index = chunk_index * rows_per_thread * w + k;
                    let (i, j) = ((index % w) as u32, (index / w) as u32);
                    *value = ao_texel(field, i, j, azimuths).value as f32;
                }
            });
        }
    });
    Ok(out)
}

fn ao_texel(field: &Field, i: u32, j: u32, azimuths: u32) -> AoTexel {
    let n = texel_normal(field.hf, field.s, field.address, i, j);
    let start = (f64::from(i), f64::from(j));
    let (mut sum, mut capped) = (0.0, 0);
    for k in 0..azimuths {
        let phi = TAU * (f64::from(k) + 0.5) / f64::from(azimuths);
        let (sp, cp) = phi.sin_cos();
        let (tau, walked) = horizon(field, start, (cp, sp));
        capped += u32::from(walked == WalkEnd::Capped);
        let c = n[0] * cp + n[1] * sp;
        // The lower limit: the horizon, or the edge of the normal's hemisphere if that is higher.
        let t0 = tau.atan().max((-c).atan2(n[2]));
        sum +=
            n[2] * t0.cos().powi(2) / 2.0 + c * ((FRAC_PI_2 - t0) / 2.0 - (2.0 * t0).sin() / 4.0);
    }
    // (1/pi) * sum * (2 pi / azimuths), ordered so that a flat field gives exactly 1.
    let value = (sum * 2.0 / f64::from(azimuths)).clamp(0.0, 1.0);
    AoTexel {
        value,
        capped_azimuths: capped,
    }
}

/// The horizon tangent `max(0, sup s (h(x) - h_p) / x)` from the surface point at grid `start` along the uv
/// unit direction `dir`, and how the walk ended.
fn horizon(field: &Field, start: (f64, f64), dir: (f64, f64)) -> (f64, WalkEnd) {
    let s = field.s;
    let rate = (
        dir.0 * f64::from(field.hf.width()),
        dir.1 * f64::from(field.hf.height()),
    );
    let rise_max = s * (field.h_max - field.height(start));
    if rise_max.is_nan() || rise_max <= 0.0 {
        return (0.0, WalkEnd::Finished);
    }
    let mut tau = 0.0f64;
    let mut h_p = None;
    let walked = field.walk(start, rate, f64::INFINITY, MAX_HORIZON_CELLS, |seg| {
        let hp = *h_p.get_or_insert(seg.h0);
        if seg.la > 0.0 && rise_max <= tau.max(TAU_FLOOR) * seg.la {
            return ControlFlow::Break(());
        }
        tau = tau.max(max_slope(seg, hp, s));
        ControlFlow::Continue(())
    });
    (tau, walked)
}

/// `max over the segment of s (h(x) - h_p) / x`, `x` the distance from the point (the segment's `l`).
fn max_slope(seg: &Segment, hp: f64, s: f64) -> f64 {
    let (a0, a1, a2) = (s * (seg.h0 - hp), s * seg.h1, s * seg.h2);
    let len = seg.len();
    if seg.la == 0.0 {
        // The point's own cell: a0 is exactly 0, the ratio is a1 + a2 t, its sup at an end (t -> 0+ gives a1).
        return if len.is_finite() {
            a1.max(a1 + a2 * len)
        } else {
            a1
        };
    }
    let ratio = |t: f64| (a0 + t * (a1 + a2 * t)) / (seg.la + t);
    let mut best = ratio(0.0);
    if len.is_finite() {
        best = best.max(ratio(len));
        // d/dx of (c0 + c1 x + c2 x^2) / x vanishes at x^2 = c0 / c2, c0 the quadratic's value at x = 0.
        let c0 = a0 - seg.la * (a1 - a2 * seg.la);
        let x2 = c0 / a2;
        if a2 != 0.0 && x2 > 0.0 {
            let t = x2.sqrt() - seg.la;
            if t > 0.0 && t < len {
                best = best.max(ratio(t));
            }
        }
    }
    best
}

#[cfg(test)]
#[path = "ambient_occlusion_tests.rs"]
mod tests;
