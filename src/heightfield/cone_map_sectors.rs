//! Geometry in uv for the cone-map searches: boxes, distances, and which direction sectors a straight line
//! from one box to another can take. Texels and regions are half-open boxes (the nearest model's ownership
//! rule); distances are Euclidean, between closed boxes.

/// Directions in the uv plane are split into this many closed sectors, four per quadrant: sector `k` covers
/// the directions whose diamond angle (see [`diamond`]) lies in `[k, k + 1] / 4`, i.e. each quadrant is cut
/// at slopes 1/3, 1 and 3. Any partition would do; this one needs no trigonometry.
pub(super) const SECTORS: usize = 16;
/// A set of sectors, bit `k` for sector `k`.
pub(super) type Mask = u32;
/// Angular slack (diamond-angle units) when a box's direction interval is turned into sectors: leaves use
/// the smaller one, pyramid nodes the larger, so a node's sectors include those of every texel under it.
const EPS_LEAF: f64 = 1e-9;
const EPS_NODE: f64 = 1e-7;

/// An axis-aligned box in uv.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct Rect {
    pub u0: f64,
    pub u1: f64,
    pub v0: f64,
    pub v1: f64,
}

impl Rect {
    /// Distance from the point `(u, v)` to the closed box.
    pub fn dist_point(&self, u: f64, v: f64) -> f64 {
        let du = (self.u0 - u).max(u - self.u1).max(0.0);
        let dv = (self.v0 - v).max(v - self.v1).max(0.0);
        (du * du + dv * dv).sqrt()
    }

    /// Distance between two closed boxes.
    pub fn dist_rect(&self, o: &Rect) -> f64 {
        let du = (o.u0 - self.u1).max(self.u0 - o.u1).max(0.0);
        let dv = (o.v0 - self.v1).max(self.v0 - o.v1).max(0.0);
        (du * du + dv * dv).sqrt()
    }
}

/// Sectors of the directions `b - a` for `a` in `from` and `b` in `to`, both half-open like texels: a
/// superset (never a subset) of the exact set. Sectors are closed, so a direction on a sector border belongs to
/// both. `leaf` picks the smaller angular slack (see [`EPS_LEAF`]).
///
/// Half-open `from` is right for a ray's cell too: a ray point lies on its cell's upper edge only after a
/// cell step in the negative direction along that axis, so it never moves toward the cells on that side.
pub(super) fn direction_mask(from: &Rect, to: &Rect, leaf: bool) -> Mask {
    let mut mask =
        sign_mask(from.u0, from.u1, to.u0, to.u1, 0) & sign_mask(from.v0, from.v1, to.v0, to.v1, 1);
    let (a0, a1) = (to.u0 - from.u1, to.u1 - from.u0);
    let (b0, b1) = (to.v0 - from.v1, to.v1 - from.v0);
    if !(a0 <= 0.0 && a1 >= 0.0 && b0 <= 0.0 && b1 >= 0.0) {
        mask &= angular_mask([(a0, b0), (a1, b0), (a0, b1), (a1, b1)], leaf);
    }
    mask
}

/// Sectors of the open half-plane the sign of one component of `b - a` allows (`axis` 0 for u, 1 for v):
/// `to` wholly above `from` gives a strictly positive component (`b >= to.lo >= from.hi > a`), wholly below a
/// strictly negative one; overlapping intervals allow any. Sector borders fall on the axes since
/// `SECTORS % 4 == 0`, so each sector lies wholly inside or outside each open half-plane.
fn sign_mask(f0: f64, f1: f64, t0: f64, t1: f64, axis: usize) -> Mask {
    let q = SECTORS / 4;
    // Quarter turns where the positive half-plane starts: -90 degrees for u, 0 for v.
    let start = [3 * q, 0][axis];
    let positive = (start..start + 2 * q).fold(0, |m, k| m | (1 << (k % SECTORS)));
    if t0 >= f1 {
        positive
    } else if t1 <= f0 {
        range_mask(0, SECTORS) & !positive
    } else {
        range_mask(0, SECTORS)
    }
}

/// Bits `lo..hi`.
fn range_mask(lo: usize, hi: usize) -> Mask {
    (lo..hi).fold(0, |m, k| m | (1 << k))
}

/// The diamond angle of a nonzero vector: a number in `[0, 4)` that increases with the true angle from +u
/// toward +v, reaching 1, 2 and 3 on the axes, with one division instead of an `atan2`.
fn diamond(u: f64, v: f64) -> f64 {
    if v >= 0.0 {
        if u >= 0.0 {
            v / (u + v)
        } else {
            1.0 - u / (v - u)
        }
    } else if u < 0.0 {
        2.0 - v / (-u - v)
    } else {
        3.0 + u / (u - v)
    }
}

/// Sectors meeting the angular interval spanned by the corners of a box that excludes the origin (so the
/// interval is shorter than a half turn and contains the direction of the box centre).
fn angular_mask(corners: [(f64, f64); 4], leaf: bool) -> Mask {
    let eps = if leaf { EPS_LEAF } else { EPS_NODE };
    let (cu, cv) = corners.iter().fold((0.0, 0.0), |(su, sv), &(u, v)| {
        (su + 0.25 * u, sv + 0.25 * v)
    });
    let centre = diamond(cu, cv);
    let (mut lo, mut hi) = (0.0f64, 0.0f64);
    for (u, v) in corners {
        let mut rel = diamond(u, v) - centre;
        if rel > 2.0 {
            rel -= 4.0;
        } else if rel < -2.0 {
            rel += 4.0;
        }
        lo = lo.min(rel);
        hi = hi.max(rel);
    }
    let per_unit = (SECTORS / 4) as f64;
    let k_lo = ((centre + lo - eps) * per_unit).floor() as i64;
    let k_hi = ((centre + hi + eps) * per_unit).floor() as i64;
    (k_lo..=k_hi).fold(0, |m, k| m | (1 << k.rem_euclid(SECTORS as i64)))
}
