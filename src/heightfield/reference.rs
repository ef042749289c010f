//! The exact reference tracer: the ground truth every displacement method is measured against.
//!
//! Conventions are those of docs/conventions.md: the ray enters the top plane at `(u0, v0, 0)`, is parameterised by
//! depth, `p(z) = (u0 + z*dx/dz, v0 + z*dy/dz, z)`, and hits at the smallest `z >= 0` with
//! `z >= d(u(z), v(z)) = s * (1 - h(u(z), v(z)))` (the infimum, where a cliff makes the set half-open).
//!
//! How it stays exact: the surface is piecewise simple over a grid of cells, so the tracer walks the cells
//! the ray's uv projection crosses, in order (a 2D DDA parameterised by z), and solves each cell in closed form.
//! - *nearest*: cells are texels and the depth is a constant `c` in each, so the hit is `za` (the ray enters
//!   through a cliff face) or `c` (it reaches the floor) or nothing.
//! - *bilinear*: cells are the squares between four texel centres (the texel grid shifted by half a texel),
//!   where `h` is one bilinear patch; along the ray `f(z) = z - d(z)` is a quadratic whose first root in the
//!   cell is found with the stable formula, then polished by Newton steps on the patch itself.
//!
//! Addressing: `Repeat` wraps texel indices (the ray's start is moved into the first tile, which changes
//! nothing but rounding); `Clamp` clamps texel indices to the border like `CLAMP_TO_EDGE`, so beyond the map the
//! surface is constant along the clamped axis. The walk treats each such outside half-line as one cell per axis,
//! which keeps it exact and bounds a clamped walk by about `W + H + 4` cells wherever the ray goes.
//!
//! Cost is proportional to the cells crossed, about `s * |(dx, dy)| / dz * (W + H)`: cheap for ordinary views,
//! huge near grazing with `Repeat`. A walk stops after [`MAX_CELLS`] cells and then answers the bottom plane
//! `z = s` (a point that is under the surface, though maybe not the first); `cells_visited == MAX_CELLS` says so.

use std::fmt;
use std::str::FromStr;

use crate::heightfield::Heightfield;

/// The most cells one trace walks before giving up with the bottom-plane fallback (a few seconds of CPU
/// at the measured 30-55 ns per cell).
pub const MAX_CELLS: u32 = 1 << 26;

/// Roots this far outside a cell (relative to the z reached) still count for it: a crossing that sits on a
/// cell boundary may round to just outside both cells, and must not be lost.
const ROOT_WINDOW: f64 = 1e-11;

/// Newton steps that polish a bilinear root against the patch (each kept only if it lowers |f|).
const POLISH_STEPS: usize = 3;

/// How heights between texel centres are defined.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SurfaceModel {
    /// Interpolated between texel centres, as GPU linear filtering does: the true surface.
    Bilinear,
    /// Constant over each texel: the box surface a max pyramid bounds exactly.
    Nearest,
}

/// What lies outside the map.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Address {
    /// The map tiles: texel indices wrap.
    Repeat,
    /// Texel indices clamp to the border, so the border values extend outward.
    Clamp,
}

impl FromStr for Address {
    type Err = String;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "repeat" => Ok(Self::Repeat),
            "clamp" => Ok(Self::Clamp),
            _ => Err(format!(
                "unknown address mode `{s}` (expected `repeat` or `clamp`)"
            )),
        }
    }
}

impl fmt::Display for Address {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Self::Repeat => "repeat",
            Self::Clamp => "clamp",
        })
    }
}

/// A ray entering the top plane at `(u0, v0, 0)` going down along `(dx, dy, dz)`, `dz > 0`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefRay {
    /// Entry point's u on the top plane, in uv units (need not lie in [0, 1]).
    pub u0: f64,
    /// Entry point's v on the top plane, in uv units (need not lie in [0, 1]).
    pub v0: f64,
    /// Direction's u component; only the ratios `dx / dz` and `dy / dz` matter, not the length.
    pub dx: f64,
    /// Direction's v component.
    pub dy: f64,
    /// Direction's depth component, downward; must be `> 0`.
    pub dz: f64,
}

/// The exact hit: depth `z` in [0, s] and the ray's `(u, v)` there, not wrapped into [0, 1].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RefHit {
    /// Depth of the hit below the top plane, in [0, s] (depth units: `s * (1 - h)` at the surface).
    pub z: f64,
    /// The ray's u at depth `z`, in uv units, not wrapped into [0, 1].
    pub u: f64,
    /// The ray's v at depth `z`, in uv units, not wrapped into [0, 1].
    pub v: f64,
    /// Cells the walk solved; [`MAX_CELLS`] means it gave up and `z` is the bottom-plane fallback.
    pub cells_visited: u32,
}

/// The surface depth `d(u, v) = s * (1 - h(u, v))` under the given model and addressing.
pub fn surface_depth(
    hf: &Heightfield,
    u: f64,
    v: f64,
    depth_scale: f64,
    model: SurfaceModel,
    address: Address,
) -> f64 {
    let (u, v) = match address {
        Address::Repeat => (u - u.floor(), v - v.floor()),
        Address::Clamp => (u, v),
    };
    let (w, h) = (hf.width(), hf.height());
    let height = match model {
        SurfaceModel::Nearest => {
            let i = texel_index((u * f64::from(w)).floor() as i64, w, address);
            let j = texel_index((v * f64::from(h)).floor() as i64, h, address);
            f64::from(hf.get(i, j))
        }
        SurfaceModel::Bilinear => {
            let x = u * f64::from(w) - 0.5;
            let y = v * f64::from(h) - 0.5;
            let (x0, y0) = (x.floor(), y.floor());
            let [h00, h10, h01, h11] = corners(hf, x0 as i64, y0 as i64, address);
            let (fx, fy) = (x - x0, y - y0);
            let bottom = h00 + fx * (h10 - h00);
            let top = h01 + fx * (h11 - h01);
            bottom + fy * (top - bottom)
        }
    };
    depth_scale * (1.0 - height)
}

/// Traces one ray exactly. Panics if `dz` is not positive and finite, if the ray is so close to horizontal
/// that `dx/dz` or `dy/dz` overflows, or if `depth_scale` is negative or not finite.
pub fn trace(
    hf: &Heightfield,
    ray: &RefRay,
    depth_scale: f64,
    model: SurfaceModel,
    address: Address,
) -> RefHit {
    trace_capped(hf, ray, depth_scale, model, address, MAX_CELLS)
}

/// [`trace`] with the cell cap as a parameter, so tests can reach the fallback cheaply.
fn trace_capped(
    hf: &Heightfield,
    ray: &RefRay,
    s: f64,
    model: SurfaceModel,
    address: Address,
    cap: u32,
) -> RefHit {
    let (tx, ty) = check_ray(ray, s);
    let (u0, v0) = match address {
        Address::Repeat => (ray.u0 - ray.u0.floor(), ray.v0 - ray.v0.floor()),
        Address::Clamp => (ray.u0, ray.v0),
    };
    let mut ax = Axis::new(u0, tx, hf.width(), model, address);
    let mut ay = Axis::new(v0, ty, hf.height(), model, address);
    let mut za = 0.0;
    let mut visited = 0;
    let z = loop {
        visited += 1;
        let (zx, zy) = (ax.exit_z(), ay.exit_z());
        let zb = zx.min(zy).min(s).max(za);
        if let Some(z) = cell_hit(hf, &ax, &ay, za, zb, s, model, address) {
            break z;
        }
        // Past the last cell f(s) >= 0 holds, so only rounding or the cap gets here.
        if zb >= s || visited >= cap {
            break s;
        }
        if zx <= zb {
            ax.advance();
        }
        if zy <= zb {
            ay.advance();
        }
        za = zb;
    };
    let z = z.clamp(0.0, s);
    RefHit {
        z,
        u: ray.u0 + z * tx,
        v: ray.v0 + z * ty,
        cells_visited: visited,
    }
}

/// The ray's uv slopes per unit depth, after checking the preconditions.
fn check_ray(ray: &RefRay, s: f64) -> (f64, f64) {
    assert!(
        ray.dz > 0.0 && ray.dz.is_finite(),
        "reference ray needs 0 < dz < inf, got {ray:?}"
    );
    assert!(
        s >= 0.0 && s.is_finite(),
        "depth scale must be finite and >= 0, got {s}"
    );
    assert!(
        ray.u0.is_finite() && ray.v0.is_finite(),
        "ray entry must be finite, got {ray:?}"
    );
    let (tx, ty) = (ray.dx / ray.dz, ray.dy / ray.dz);
    assert!(
        tx.is_finite() && ty.is_finite(),
        "ray too close to horizontal: {ray:?}"
    );
    (tx, ty)
}

/// Texel index `k` (any integer) mapped into `[0, n)` by the addressing mode.
pub(crate) fn texel_index(k: i64, n: u32, address: Address) -> u32 {
    match address {
        Address::Repeat => k.rem_euclid(i64::from(n)) as u32,
        Address::Clamp => k.clamp(0, i64::from(n) - 1) as u32,
    }
}

/// Heights at the lattice corners `(x0, y0)`, `(x0+1, y0)`, `(x0, y0+1)`, `(x0+1, y0+1)`.
pub(crate) fn corners(hf: &Heightfield, x0: i64, y0: i64, address: Address) -> [f64; 4] {
    let (w, h) = (hf.width(), hf.height());
    let (i0, i1) = (
        texel_index(x0, w, address),
        texel_index(x0.saturating_add(1), w, address),
    );
    let (j0, j1) = (
        texel_index(y0, h, address),
        texel_index(y0.saturating_add(1), h, address),
    );
    [
        hf.get(i0, j0),
        hf.get(i1, j0),
        hf.get(i0, j1),
        hf.get(i1, j1),
    ]
    .map(f64::from)
}

/// One axis of the cell walk, in grid units: texels for nearest, the centre lattice (texels - 1/2) for
/// bilinear, so cell `k` is `[k, k+1)`. With `Clamp`, cell -1 is the whole half-line below 0 and cell `last`
/// the whole half-line from `last` up, since the surface does not change along this axis there.
struct Axis {
    /// Grid coordinate at z = 0.
    g0: f64,
    /// Grid units per unit of depth.
    slope: f64,
    /// The current cell.
    k: i64,
    /// `Some(last cell)` under `Clamp`, `None` (unbounded) under `Repeat`.
    last: Option<i64>,
    /// Texels along this axis.
    n: u32,
    address: Address,
}

impl Axis {
    fn new(coord: f64, slope_uv: f64, n: u32, model: SurfaceModel, address: Address) -> Self {
        let offset = match model {
            SurfaceModel::Nearest => 0.0,
            SurfaceModel::Bilinear => 0.5,
        };
        let g0 = coord * f64::from(n) - offset;
        let last = match (address, model) {
            (Address::Repeat, _) => None,
            (Address::Clamp, SurfaceModel::Nearest) => Some(i64::from(n)),
            (Address::Clamp, SurfaceModel::Bilinear) => Some(i64::from(n) - 1),
        };
        let k = g0.floor() as i64;
        let k = last.map_or(k, |last| k.clamp(-1, last));
        Self {
            g0,
            slope: slope_uv * f64::from(n),
            k,
            last,
            n,
            address,
        }
    }

    /// Whether the current cell is a clamped half-line (the surface is constant along this axis in it).
    fn merged(&self) -> bool {
        self.last.is_some_and(|last| self.k == -1 || self.k == last)
    }

    /// The depth at which the ray leaves the current cell along this axis (infinite if never).
    fn exit_z(&self) -> f64 {
        let bound = if self.slope > 0.0 {
            (self.last != Some(self.k)).then(|| (self.k + 1) as f64)
        } else if self.slope < 0.0 {
            (self.last.is_none() || self.k != -1).then_some(self.k as f64)
        } else {
            None
        };
        bound.map_or(f64::INFINITY, |b| (b - self.g0) / self.slope)
    }

    fn advance(&mut self) {
        self.k += if self.slope > 0.0 { 1 } else { -1 };
    }

    /// The texel index of the current nearest cell.
    fn texel(&self) -> u32 {
        texel_index(self.k, self.n, self.address)
    }

    /// The fraction across the current cell at depth z, and its rate per unit depth (both 0 when merged).
    fn local(&self, z: f64) -> (f64, f64) {
        if self.merged() {
            (0.0, 0.0)
        } else {
            (
                (self.g0 + z * self.slope - self.k as f64).clamp(0.0, 1.0),
                self.slope,
            )
        }
    }
}

/// The hit inside the current cell over depths `[za, zb]`, if any.
#[allow(clippy::too_many_arguments)]
fn cell_hit(
    hf: &Heightfield,
    ax: &Axis,
    ay: &Axis,
    za: f64,
    zb: f64,
    s: f64,
    model: SurfaceModel,
    address: Address,
) -> Option<f64> {
    match model {
        SurfaceModel::Nearest => {
            let c = s * (1.0 - f64::from(hf.get(ax.texel(), ay.texel())));
            if za >= c {
                Some(za)
            } else if zb >= c {
                Some(c)
            } else {
                None
            }
        }
        SurfaceModel::Bilinear => {
            let patch = Patch::new(corners(hf, ax.k, ay.k, address), ax.local(za), ay.local(za));
            bilinear_hit(&patch, za, zb, s)
        }
    }
}

/// A bilinear patch seen along the ray, in `t = z - za`: `h(t) = h00 + p fx + q fy + r fx fy` with
/// `fx = fx0 + bx t`, `fy = fy0 + by t`. A clamped (merged) axis has equal corners along it, so its `p` or `q`
/// and `r` are exactly zero and its fraction is irrelevant.
struct Patch {
    h00: f64,
    p: f64,
    q: f64,
    r: f64,
    fx0: f64,
    fy0: f64,
    bx: f64,
    by: f64,
}

impl Patch {
    fn new([h00, h10, h01, h11]: [f64; 4], (fx0, bx): (f64, f64), (fy0, by): (f64, f64)) -> Self {
        // Written as a difference of differences so that equal corner pairs give r == 0 exactly.
        let r = (h11 - h01) - (h10 - h00);
        Self {
            h00,
            p: h10 - h00,
            q: h01 - h00,
            r,
            fx0,
            fy0,
            bx,
            by,
        }
    }

    fn height(&self, t: f64) -> f64 {
        let (fx, fy) = (self.fx0 + self.bx * t, self.fy0 + self.by * t);
        self.h00 + fx * self.p + fy * self.q + fx * fy * self.r
    }

    fn height_rate(&self, t: f64) -> f64 {
        let (fx, fy) = (self.fx0 + self.bx * t, self.fy0 + self.by * t);
        self.p * self.bx + self.q * self.by + self.r * (self.bx * fy + self.by * fx)
    }

    /// `f(za + t) = z - s(1 - h) = a t^2 + b t + c`.
    fn quadratic(&self, za: f64, s: f64) -> (f64, f64, f64) {
        let a = s * self.r * self.bx * self.by;
        let b = 1.0 + s * self.height_rate(0.0);
        let c = (za - s) + s * self.height(0.0);
        (a, b, c)
    }
}

/// The first depth in `[za, zb]` where the ray reaches the patch, if any.
fn bilinear_hit(patch: &Patch, za: f64, zb: f64, s: f64) -> Option<f64> {
    let len = zb - za;
    let (a, b, c) = patch.quadratic(za, s);
    if c >= 0.0 {
        return Some(za);
    }
    let tol = ROOT_WINDOW * zb;
    let t = match first_root(a, b, c, -tol, len + tol) {
        Some(t) => t,
        // A crossing must exist; the roots rounded out of the window (or the discriminant below zero).
        None if c + len * (b + a * len) >= 0.0 => bisect(a, b, c, len),
        None => return None,
    };
    Some(za + polish(patch, za, s, t, (-tol, len + tol)))
}

/// The smallest real root of `a t^2 + b t + c` in `[lo, hi]`. With `c < 0` it is where f first reaches 0.
/// Stable form: `q = -(b + sign(b) sqrt(disc)) / 2`, roots `q/a` and `c/q`; a vanishing `a` (linear) or
/// `q` only makes a root non-finite, and it is dropped. A discriminant below zero (which rounding can make
/// of a tangent touch) counts as no root: such touches have no extent along the ray.
fn first_root(a: f64, b: f64, c: f64, lo: f64, hi: f64) -> Option<f64> {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return None;
    }
    let q = -0.5 * (b + disc.sqrt().copysign(b));
    let (r1, r2) = (q / a, c / q);
    let (r1, r2) = if r1 <= r2 { (r1, r2) } else { (r2, r1) };
    [r1, r2]
        .into_iter()
        .find(|r| r.is_finite() && (lo..=hi).contains(r))
}

/// The crossing of `a t^2 + b t + c` in `[0, len]` given f(0) < 0 <= f(len) (then there is exactly one).
fn bisect(a: f64, b: f64, c: f64, len: f64) -> f64 {
    let (mut lo, mut hi) = (0.0, len);
    for _ in 0..200 {
        let mid = 0.5 * (lo + hi);
        if mid <= lo || mid >= hi {
            break;
        }
        if c + mid * (b + a * mid) >= 0.0 {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    hi
}

/// Newton steps on `f(t) = za + t - s(1 - h(t))` evaluated on the patch (not the expanded coefficients),
/// each kept only if it stays in the window and lowers |f|.
fn polish(patch: &Patch, za: f64, s: f64, t: f64, (lo, hi): (f64, f64)) -> f64 {
    let f = |t: f64| (za - s) + t + s * patch.height(t);
    let (mut t, mut ft) = (t, f(t));
    for _ in 0..POLISH_STEPS {
        let slope = 1.0 + s * patch.height_rate(t);
        let next = t - ft / slope;
        if ft == 0.0 || !next.is_finite() || !(lo..=hi).contains(&next) {
            break;
        }
        let f_next = f(next);
        if f_next.abs() >= ft.abs() {
            break;
        }
        (t, ft) = (next, f_next);
    }
    t
}

#[cfg(test)]
#[path = "reference_tests.rs"]
mod tests;
