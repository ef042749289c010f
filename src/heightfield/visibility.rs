//! The exact visible fraction of a disk light seen from a point on the bilinear surface (docs/conventions.md,
//! "Light"): the share of the disk's solid angle whose rays leave the top plane `z = 0` without passing below
//! the surface.
//!
//! Method. The disk of directions within `r` of the light's direction is a spherical cap. An `N x N` grid of
//! cell centres on the unit square is carried onto it by Shirley and Chiu's concentric map (square to disk,
//! area-preserving) followed by `1 - cos(theta) = rho^2 (1 - cos r)` (disk to cap, also area-preserving), so
//! every sample stands for the same solid angle and the estimate is a plain count. The only approximation is
//! this stratification of the disk; each ray's verdict is exact.
//!
//! Each ray is an exact *upward* query. Parameterised by the depth it has climbed, `t`, the ray from the point
//! (height `h_p`) is below the surface where `g(t) = t - s (h(t) - h_p)` is negative. The ray's uv projection
//! crosses bilinear cells (`cell_walk`); in each, `h(t)` is one quadratic, so the minimum of `g` over
//! the cell is found in closed form (ends and vertex). The walk stops at the first cell where `g` goes
//! negative (blocked), or once the ray is above the highest texel, `t >= s (h_max - h_p)`, where it can no
//! longer pass below (it escapes).
//!
//! Self-intersection. The point lies on the surface, so `g(0) = 0`. In the first cell `g` is written as
//! `t (b + a t)`, with no constant term at all, so rounding of the point's own height cannot make the ray look
//! blocked; a light below the surface's tangent plane there still gives `b < 0` and is blocked, as it should.
//! In later cells a ray counts as below only if `g < -DIP_TOLERANCE * s` (`1e-12 s`, in depth units), which
//! absorbs the rounding of `g` (about `1e-16 s`); the directions this can misjudge graze the surface within
//! `1e-12 s` and have vanishing solid angle.
//!
//! Directions at or below the horizon (`elevation <= 0`) never leave the top plane: they count as blocked, so
//! a disk wholly below it gives 0 and one straddling it counts only its upper part as possibly visible.

use std::ops::ControlFlow;

use super::cell_walk::{Field, WalkEnd};
use super::reference::Address;
use super::Heightfield;

/// The largest `samples_per_side` accepted: `1024^2` rays per query.
pub const MAX_SAMPLES_PER_SIDE: u32 = 1024;

/// The most cells one light ray walks. A ray reaching it is counted blocked and reported in
/// [`Visibility::capped`]; only rays within a hair of grazing over a repeating map get there.
pub const MAX_RAY_CELLS: u32 = 1 << 22;

/// How far below the surface (relative to the depth scale) a ray must go to count as passing below it.
const DIP_TOLERANCE: f64 = 1e-12;

/// Why a shading reference could not be computed: always a bad argument, never a property of the map.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShadingError {
    /// A NaN or infinite input.
    #[error("{name} must be finite, got {value}")]
    NonFinite {
        /// The argument's name as the caller's API spells it (e.g. `"depth_scale"`).
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// A finite input outside its valid range.
    #[error("{name} = {value} is outside [{min}, {max}]")]
    OutOfRange {
        /// The argument's name as the caller's API spells it (e.g. `"elevation_deg"`).
        name: &'static str,
        /// The value given, in the argument's own units (degrees for angles).
        value: f64,
        /// Smallest accepted value (inclusive).
        min: f64,
        /// Largest accepted value (inclusive).
        max: f64,
    },
    /// A sample or direction count outside its valid range.
    #[error("{name} = {count} is outside [{min}, {max}]")]
    BadCount {
        /// The argument's name (e.g. `"samples_per_side"`).
        name: &'static str,
        /// The count given.
        count: u32,
        /// Smallest accepted count (inclusive).
        min: u32,
        /// Largest accepted count (inclusive).
        max: u32,
    },
}

/// A disk light, in degrees: direction as in docs/conventions.md (elevation above the surface plane, azimuth from +u
/// toward +v) and its angular radius.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightDir {
    /// In [-90, 90]; 90 is straight overhead.
    pub elevation_deg: f64,
    /// Any finite value.
    pub azimuth_deg: f64,
    /// In [0, 90]; 0 is a point (directional) light.
    pub radius_deg: f64,
}

/// The result of [`light_visibility`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Visibility {
    /// The visible fraction in [0, 1].
    pub fraction: f64,
    /// Rays traced (0 when the whole disk is below the horizon, 1 for a point light).
    pub rays: u32,
    /// Rays that reached [`MAX_RAY_CELLS`] and were counted blocked (0 in any ordinary case).
    pub capped: u32,
}

/// What one exact ray query found.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Escape {
    Escapes,
    Blocked,
    Capped,
}

/// The visible fraction of `light` from the point `(u, v)` on the bilinear surface (its depth is the surface's
/// there), estimated with `samples_per_side^2` equal-solid-angle directions over the disk, each traced exactly.
///
/// Errors: non-finite inputs, `depth_scale < 0`, elevation outside [-90, 90], radius outside [0, 90], and
/// `samples_per_side` outside `1..=MAX_SAMPLES_PER_SIDE`.
pub fn light_visibility(
    hf: &Heightfield,
    depth_scale: f64,
    address: Address,
    (u, v): (f64, f64),
    light: LightDir,
    samples_per_side: u32,
) -> Result<Visibility, ShadingError> {
    check_depth_scale(depth_scale)?;
    check_finite("u", u)?;
    check_finite("v", v)?;
    check_light(&light)?;
    check_count(
        "samples_per_side",
        samples_per_side,
        1,
        MAX_SAMPLES_PER_SIDE,
    )?;
    let field = Field::new(hf, depth_scale, address);
    let start = field.grid(u, v);
    let cap = Cap::new(&light);
    if light.elevation_deg + light.radius_deg <= 0.0 {
        return Ok(Visibility {
            fraction: 0.0,
            rays: 0,
            capped: 0,
        });
    }
    let n = if light.radius_deg == 0.0 {
        1
    } else {
        samples_per_side
    };
    let (mut visible, mut capped) = (0u64, 0u32);
    for j in 0..n {
        for i in 0..n {
            let cell = |k: u32| (2 * k + 1) as f64 / n as f64 - 1.0;
            match ray_escapes(&field, start, cap.direction(cell(i), cell(j))) {
                Escape::Escapes => visible += 1,
                Escape::Blocked => {}
                Escape::Capped => capped += 1,
            }
        }
    }
    let rays = n * n;
    Ok(Visibility {
        fraction: visible as f64 / f64::from(rays),
        rays,
        capped,
    })
}

/// Whether the ray from the surface point at grid position `start` along `w` (in (u, v, up) coordinates, any
/// length) leaves the top plane without passing below the bilinear surface.
pub(crate) fn ray_escapes(field: &Field, start: (f64, f64), w: [f64; 3]) -> Escape {
    // Horizontal or downward rays never leave the top plane.
    if w[2].is_nan() || w[2] <= 0.0 {
        return Escape::Blocked;
    }
    let rate = (
        w[0] / w[2] * f64::from(field.hf.width()),
        w[1] / w[2] * f64::from(field.hf.height()),
    );
    if !(rate.0.is_finite() && rate.1.is_finite()) {
        return Escape::Blocked;
    }
    let s = field.s;
    // Once it has climbed this far the ray is above every texel and can no longer pass below.
    let end = s * (field.h_max - field.height(start));
    if end.is_nan() || end <= 0.0 {
        return Escape::Escapes;
    }
    let tol = DIP_TOLERANCE * s;
    let mut h_p = None;
    let walked = field.walk(start, rate, end, MAX_RAY_CELLS, |seg| {
        // The point's height is the first cell's value at its start, so that g(0) is exactly 0 there.
        let hp = *h_p.get_or_insert(seg.h0);
        let c = s * (hp - seg.h0) + seg.la;
        if dips_below(-s * seg.h2, 1.0 - s * seg.h1, c, seg.len(), tol) {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    });
    match walked {
        WalkEnd::Finished => Escape::Escapes,
        WalkEnd::Stopped => Escape::Blocked,
        WalkEnd::Capped => Escape::Capped,
    }
}

/// Whether `a t^2 + b t + c` drops below `-tol` somewhere on `[0, len]`.
fn dips_below(a: f64, b: f64, c: f64, len: f64, tol: f64) -> bool {
    let at = |t: f64| c + t * (b + a * t);
    if at(0.0) < -tol || (len.is_finite() && at(len) < -tol) {
        return true;
    }
    if a > 0.0 {
        let vertex = -b / (2.0 * a);
        if vertex > 0.0 && vertex < len && at(vertex) < -tol {
            return true;
        }
    }
    false
}

/// The spherical cap of a disk light, with an orthonormal frame about its centre.
struct Cap {
    centre: [f64; 3],
    /// Horizontal, perpendicular to the centre's azimuth.
    side: [f64; 3],
    /// Perpendicular to both, pointing toward increasing elevation.
    up: [f64; 3],
    /// `1 - cos(r)`, written `2 sin^2(r/2)` so small radii keep their precision.
    one_minus_cos: f64,
}

impl Cap {
    fn new(light: &LightDir) -> Self {
        let (se, ce) = light.elevation_deg.to_radians().sin_cos();
        let (sa, ca) = light.azimuth_deg.to_radians().sin_cos();
        let half = (0.5 * light.radius_deg.to_radians()).sin();
        Self {
            centre: [ce * ca, ce * sa, se],
            side: [-sa, ca, 0.0],
            up: [-se * ca, -se * sa, ce],
            one_minus_cos: 2.0 * half * half,
        }
    }

    /// The direction for the square point `(a, b)` in `[-1, 1]^2`: concentric map to the unit disk, then the
    /// equal-area map from the disk onto the cap.
    fn direction(&self, a: f64, b: f64) -> [f64; 3] {
        let (x, y) = concentric(a, b);
        let rho2 = x * x + y * y;
        let k = rho2 * self.one_minus_cos;
        let cos_t = 1.0 - k;
        // sin(theta) / rho, so that (x, y) scaled by it lands on the cap; its limit at rho = 0 is finite.
        let sin_over_rho = if rho2 > 0.0 {
            (self.one_minus_cos * (2.0 - k)).max(0.0).sqrt()
        } else {
            0.0
        };
        std::array::from_fn(|i| {
            cos_t * self.centre[i] + sin_over_rho * (x * self.side[i] + y * self.up[i])
        })
    }
}

/// Shirley and Chiu's concentric map from `[-1, 1]^2` to the unit disk (area-preserving up to a constant).
pub(crate) fn concentric(a: f64, b: f64) -> (f64, f64) {
    use std::f64::consts::FRAC_PI_4;
    let (rho, phi) = if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    } else if a.abs() > b.abs() {
        (a, FRAC_PI_4 * (b / a))
    } else {
        (b, 2.0 * FRAC_PI_4 - FRAC_PI_4 * (a / b))
    };
    let (sp, cp) = phi.sin_cos();
    (rho * cp, rho * sp)
}

pub(crate) fn check_finite(name: &'static str, value: f64) -> Result<(), ShadingError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(ShadingError::NonFinite { name, value })
    }
}

pub(crate) fn check_range(
    name: &'static str,
    value: f64,
    min: f64,
    max: f64,
) -> Result<(), ShadingError> {
    check_finite(name, value)?;
    if (min..=max).contains(&value) {
        Ok(())
    } else {
        Err(ShadingError::OutOfRange {
            name,
            value,
            min,
            max,
        })
    }
}

pub(crate) fn check_depth_scale(s: f64) -> Result<(), ShadingError> {
    check_range("depth_scale", s, 0.0, f64::MAX)
}

pub(crate) fn check_count(
    name: &'static str,
    count: u32,
    min: u32,
    max: u32,
) -> Result<(), ShadingError> {
    if (min..=max).contains(&count) {
        Ok(())
    } else {
        Err(ShadingError::BadCount {
            name,
            count,
            min,
            max,
        })
    }
}

fn check_light(light: &LightDir) -> Result<(), ShadingError> {
    check_range("light elevation_deg", light.elevation_deg, -90.0, 90.0)?;
    check_finite("light azimuth_deg", light.azimuth_deg)?;
    check_range("light radius_deg", light.radius_deg, 0.0, 90.0)
}

#[cfg(test)]
#[path = "visibility_tests.rs"]
mod tests;
