//! The walk along a straight line over the cells of the bilinear surface, shared by the shading references
//! ([`super::visibility`], [`super::ambient_occlusion`]).
//!
//! The line is `g(l) = g0 + l * rate` in grid units (the texel-centre lattice: texel `(i, j)`'s value sits at
//! grid point `(i, j)`), for a caller-chosen parameter `l >= 0` (climb in depth for a light ray, horizontal
//! distance for a horizon). Between lattice lines the height is one bilinear patch, so along the line it is
//! exactly a quadratic in `l`; the walk hands each cell's quadratic to the caller, in order. Nothing is
//! sampled, so the callers' answers are exact up to rounding.
//!
//! The first cell is the one the line *enters* for `l > 0`: a start on a lattice line (every texel centre is
//! on two) picks the cell on the side the line goes, so the first quadratic starts exactly at the start point.
//! Addressing is as in [`super::reference`]: `Repeat` wraps texel indices; under `Clamp` each half-line beyond
//! the border is one cell along that axis (the surface does not change along it there), which bounds a
//! clamped walk by about `W + H + 3` cells.

use std::ops::ControlFlow;

use super::reference::{corners, Address};
use super::Heightfield;

/// One cell's piece of the line: over `l` in `[la, lb]`, the height is `h0 + h1 t + h2 t^2`, `t = l - la`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) struct Segment {
    pub la: f64,
    pub lb: f64,
    pub h0: f64,
    pub h1: f64,
    pub h2: f64,
}

impl Segment {
    /// `lb - la`; infinite for the last, unbounded cell of a clamped walk (then `h1 == h2 == 0`).
    pub fn len(&self) -> f64 {
        self.lb - self.la
    }
}

/// How a walk ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum WalkEnd {
    /// It reached the caller's end parameter (or left the map for good under `Clamp`).
    Finished,
    /// The caller broke out.
    Stopped,
    /// It visited the cell cap without either.
    Capped,
}

/// A height field with the parameters every walk over it shares.
pub(crate) struct Field<'a> {
    pub hf: &'a Heightfield,
    /// The depth scale `s`: depth is `s * (1 - h)`.
    pub s: f64,
    pub address: Address,
    /// The largest height in the map: a ray above `s * (1 - h_max)` depth can no longer pass below.
    pub h_max: f64,
}

impl<'a> Field<'a> {
    pub fn new(hf: &'a Heightfield, s: f64, address: Address) -> Self {
        let h_max = hf.data().iter().copied().fold(0.0f32, f32::max);
        Self {
            hf,
            s,
            address,
            h_max: f64::from(h_max),
        }
    }

    /// Grid coordinates of the texture point `(u, v)` (moved into the first tile under `Repeat`).
    pub fn grid(&self, u: f64, v: f64) -> (f64, f64) {
        let (u, v) = match self.address {
            Address::Repeat => (u - u.floor(), v - v.floor()),
            Address::Clamp => (u, v),
        };
        (
            u * f64::from(self.hf.width()) - 0.5,
            v * f64::from(self.hf.height()) - 0.5,
        )
    }

    /// The bilinear height at grid position `g`.
    pub fn height(&self, g: (f64, f64)) -> f64 {
        let (x0, y0) = (g.0.floor(), g.1.floor());
        let [h00, h10, h01, h11] = corners(self.hf, x0 as i64, y0 as i64, self.address);
        let (fx, fy) = (g.0 - x0, g.1 - y0);
        let bottom = h00 + fx * (h10 - h00);
        let top = h01 + fx * (h11 - h01);
        bottom + fy * (top - bottom)
    }

    /// Walks the line from `start` with `rate` grid units per unit of `l` (both finite) up to `end`, calling
    /// `visit` on each cell in order until it breaks, `end` is reached, or `max_cells` cells were visited.
    pub fn walk(
        &self,
        start: (f64, f64),
        rate: (f64, f64),
        end: f64,
        max_cells: u32,
        mut visit: impl FnMut(&Segment) -> ControlFlow<()>,
    ) -> WalkEnd {
        let mut ax = Axis::new(start.0, rate.0, self.hf.width(), self.address);
        let mut ay = Axis::new(start.1, rate.1, self.hf.height(), self.address);
        let mut la = 0.0;
        let mut cells = 0u32;
        loop {
            cells += 1;
            let (ex, ey) = (ax.exit(), ay.exit());
            let lb = ex.min(ey).min(end).max(la);
            let segment = self.segment(&ax, &ay, la, lb);
            if visit(&segment).is_break() {
                return WalkEnd::Stopped;
            }
            if lb >= end {
                return WalkEnd::Finished;
            }
            if cells >= max_cells {
                return WalkEnd::Capped;
            }
            if ex <= lb {
                ax.advance();
            }
            if ey <= lb {
                ay.advance();
            }
            la = lb;
        }
    }

    /// The current cell's bilinear patch restricted to the line, expanded about `la`.
    fn segment(&self, ax: &Axis, ay: &Axis, la: f64, lb: f64) -> Segment {
        let [h00, h10, h01, h11] = corners(self.hf, ax.k, ay.k, self.address);
        let (p, q) = (h10 - h00, h01 - h00);
        // A difference of differences, so that a merged (clamped) axis with equal corners gives r == 0 exactly.
        let r = (h11 - h01) - (h10 - h00);
        let (fx, bx) = ax.local(la);
        let (fy, by) = ay.local(la);
        Segment {
            la,
            lb,
            h0: h00 + fx * p + fy * q + fx * fy * r,
            h1: p * bx + q * by + r * (bx * fy + by * fx),
            h2: r * bx * by,
        }
    }
}

/// One axis of the walk: cell `k` is `[k, k+1)` in grid units; under `Clamp`, cell -1 is everything below 0
/// and cell `n - 1` everything from `n - 1` up.
struct Axis {
    g0: f64,
    rate: f64,
    k: i64,
    /// `Some(n - 1)` under `Clamp`, `None` under `Repeat`.
    last: Option<i64>,
}

impl Axis {
    fn new(g0: f64, rate: f64, n: u32, address: Address) -> Self {
        // The cell the line enters for l > 0: on a lattice line, the one on the side it goes.
        let k = if rate >= 0.0 {
            g0.floor()
        } else {
            g0.ceil() - 1.0
        } as i64;
        let last = match address {
            Address::Repeat => None,
            Address::Clamp => Some(i64::from(n) - 1),
        };
        let k = last.map_or(k, |last| k.clamp(-1, last));
        Self { g0, rate, k, last }
    }

    fn merged(&self) -> bool {
        self.last.is_some_and(|last| self.k == -1 || self.k == last)
    }

    /// The `l` at which the line leaves the current cell along this axis (infinite if never).
    fn exit(&self) -> f64 {
        let bound = if self.rate > 0.0 {
            (self.last != Some(self.k)).then(|| (self.k + 1) as f64)
        } else if self.rate < 0.0 {
            (self.last.is_none() || self.k != -1).then_some(self.k as f64)
        } else {
            None
        };
        bound.map_or(f64::INFINITY, |b| (b - self.g0) / self.rate)
    }

    fn advance(&mut self) {
        self.k += if self.rate > 0.0 { 1 } else { -1 };
    }

    /// The fraction across the cell at `l` and its rate per unit `l` (both 0 in a merged cell).
    fn local(&self, l: f64) -> (f64, f64) {
        if self.merged() {
            (0.0, 0.0)
        } else {
            (
                (self.g0 + l * self.rate - self.k as f64).clamp(0.0, 1.0),
                self.rate,
            )
        }
    }
}
