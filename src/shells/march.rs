//! Tracing a ray through a shell: for each prism, the stretches of the ray inside it (between its
//! face crossings), each walked in small steps in the prism's coordinates until the ray passes
//! from above the relief to under it, and that crossing bisected. The nearest hit over all prisms
//! is the ray's.
//!
//! A point's prism coordinates solve `point(b, w) = p`, which is linear in `b` for fixed `w` but
//! not jointly (the side faces may be bent), so they come from Newton's method on the 3x3
//! Jacobian, warm-started from the previous step. The point lies under the relief where its depth
//! fraction `w` is at least the field's `1 - h` at its height uv.
//!
//! A hit is a passage from outside to inside: a ray entering through a prism's top comes from
//! outside the shell, one entering through its bottom from under the relief, one entering through
//! a side from the neighbour prism in the state the neighbour leaves it (or, at an open boundary,
//! from under the relief's sheet when it is below the surface there, which the one-sided displaced
//! mesh does not stop either).

use glam::{DVec2, DVec3};

use super::prism::{Prism, PrismFace, Shell};
use crate::heightfield::reference::{surface_depth, SurfaceModel};

/// Where a ray meets a shell's relief.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellHit {
    /// The ray's parameter at the hit: `origin + t * dir`.
    pub t: f64,
    /// The hit in world space.
    pub point: DVec3,
    /// Index of the prism it lies in.
    pub prism: usize,
    /// Barycentric weights of the prism's second and third corners.
    pub barycentric: DVec2,
    /// Depth below the top as a fraction of the relief's full depth (the field's `1 - h`).
    pub depth: f64,
    /// Height uv at the hit.
    pub uv: DVec2,
}

/// Slack on a triangle's edges and on a prism's bounds: a ray through an edge two prisms share
/// counts in both, so rounding cannot slip it between them.
const EDGE_SLACK: f64 = 1e-9;
/// Steps per height texel the ray's height uv crosses, and per full relief depth it descends.
const STEPS_PER_TEXEL: f64 = 4.0;
const STEPS_PER_DEPTH: f64 = 32.0;
const MIN_STEPS: f64 = 16.0;
const MAX_STEPS: f64 = 65536.0;
/// Halvings of the step in which the relief was crossed: far below f32's resolution.
const BISECTIONS: u32 = 48;
const NEWTON_STEPS: u32 = 32;

impl Shell {
    /// The first hit of the ray `origin + t * dir` (t >= 0) on the relief inside the shell, or
    /// `None` where it passes the relief by: through the shell and out, or beside it.
    pub fn trace(&self, origin: DVec3, dir: DVec3) -> Option<ShellHit> {
        let mut best: Option<ShellHit> = None;
        let inverse = dir.recip();
        for (index, (prism, bounds)) in self.prisms.iter().zip(&self.bounds).enumerate() {
            let limit = best.map_or(f64::INFINITY, |h| h.t);
            if !box_reached(bounds, origin, inverse, limit) {
                continue;
            }
            if let Some(hit) = self.prism_hit(index, prism, origin, dir, limit) {
                best = Some(hit);
            }
        }
        best
    }

    /// The field's depth fraction `1 - h` at height uv `uv`.
    fn field_depth(&self, uv: DVec2) -> f64 {
        let h = &self.heights;
        surface_depth(
            &h.heights,
            uv.x,
            uv.y,
            1.0,
            SurfaceModel::Bilinear,
            h.address,
        )
    }

    /// The first hit inside one prism nearer than `limit`.
    fn prism_hit(
        &self,
        index: usize,
        prism: &Prism,
        origin: DVec3,
        dir: DVec3,
        limit: f64,
    ) -> Option<ShellHit> {
        let crossings = crossings(prism, origin, dir);
        let first = crossings.first().map_or(f64::INFINITY, |c| c.0);
        let from_inside = crossings.len() % 2 == 1 && locate(prism, origin, None).is_some();
        if first >= limit && !from_inside {
            return None;
        }
        let mut starts: Vec<(f64, Option<PrismFace>)> = Vec::new();
        if from_inside {
            starts.push((0.0, None));
        }
        starts.extend(crossings.iter().map(|&(t, face)| (t, Some(face))));
        for pair in starts.windows(2) {
            let ((ta, face), (tb, exit)) = (pair[0], pair[1]);
            if ta >= limit {
                return None;
            }
            let middle = origin + dir * (0.5 * (ta + tb));
            if locate(prism, middle, None).is_none() {
                continue;
            }
            if let Some(hit) = self.walk(index, prism, origin, dir, (ta, tb), (face, exit)) {
                return (hit.t < limit).then_some(hit);
            }
        }
        None
    }

    /// Steps along the stretch `span` of the ray inside `prism`, entered and left through `faces`
    /// (`None`: the ray starts inside), to its first passage under the relief.
    fn walk(
        &self,
        index: usize,
        prism: &Prism,
        origin: DVec3,
        dir: DVec3,
        (ta, tb): (f64, f64),
        (face, exit): (Option<PrismFace>, Option<PrismFace>),
    ) -> Option<ShellHit> {
        let at = |t: f64, guess: Option<(DVec2, f64)>| {
            // The stretch's ends lie on the prism's faces: allow them their slack, and put them
            // on the top or the bottom exactly when they cross it, so a relief at either is met.
            let (b, w) = locate_loose(prism, origin + dir * t, guess)?;
            let w = match (t == ta, t == tb) {
                (true, _) if face == Some(PrismFace::Top) => 0.0,
                (_, true) if exit == Some(PrismFace::Bottom) => 1.0,
                _ => w,
            };
            Some((b, w))
        };
        let enter = at(ta, None)?;
        let leave = at(tb, Some(enter))?;
        let size = DVec2::new(
            f64::from(self.heights.heights.width()),
            f64::from(self.heights.heights.height()),
        );
        let texels = ((prism.uv_at(leave.0) - prism.uv_at(enter.0)) * size).length();
        let steps = (texels * STEPS_PER_TEXEL + (leave.1 - enter.1).abs() * STEPS_PER_DEPTH)
            .ceil()
            .clamp(MIN_STEPS, MAX_STEPS) as u32;
        let under = |c: (DVec2, f64)| c.1 >= self.field_depth(prism.uv_at(c.0));
        let mut was_under = match face {
            Some(PrismFace::Top) => false,
            Some(PrismFace::Bottom) => true,
            Some(PrismFace::Side) | None => under(enter),
        };
        let (mut t_prev, mut c_prev) = (ta, enter);
        for k in 0..=steps {
            let t = ta + (tb - ta) * f64::from(k) / f64::from(steps);
            let c = at(t, Some(c_prev))?;
            let now_under = under(c);
            if now_under && !was_under {
                let (t, c) = if k == 0 {
                    (t, c)
                } else {
                    self.bisect(prism, origin, dir, (t_prev, c_prev), (t, c))
                };
                return Some(ShellHit {
                    t,
                    point: origin + dir * t,
                    prism: index,
                    barycentric: c.0,
                    depth: c.1,
                    uv: prism.uv_at(c.0),
                });
            }
            was_under = now_under;
            (t_prev, c_prev) = (t, c);
        }
        None
    }

    /// Halves the step from `above` (over the relief) to `below` (under it).
    fn bisect(
        &self,
        prism: &Prism,
        origin: DVec3,
        dir: DVec3,
        mut above: (f64, (DVec2, f64)),
        mut below: (f64, (DVec2, f64)),
    ) -> (f64, (DVec2, f64)) {
        for _ in 0..BISECTIONS {
            let t = 0.5 * (above.0 + below.0);
            let Some(c) = locate_loose(prism, origin + dir * t, Some(below.1)) else {
                break;
            };
            if c.1 >= self.field_depth(prism.uv_at(c.0)) {
                below = (t, c);
            } else {
                above = (t, c);
            }
        }
        below
    }
}

/// Whether the ray (direction `1 / inverse`) meets the box `[lo, hi]` before `limit`.
fn box_reached([lo, hi]: &[DVec3; 2], origin: DVec3, inverse: DVec3, limit: f64) -> bool {
    let (a, b) = ((*lo - origin) * inverse, (*hi - origin) * inverse);
    // A zero direction component gives infinities, or NaN for an origin on the slab's plane,
    // which max and min pass over.
    let enter = a.min(b).max_element().max(0.0);
    let leave = a.max(b).min_element().min(limit);
    enter <= leave
}

/// Where the ray crosses the prism's faces, nearest first, with the face; crossings of two faces
/// at one point (an edge) merged into one, a top crossing preferred (it says the ray came from
/// outside the shell).
fn crossings(prism: &Prism, origin: DVec3, dir: DVec3) -> Vec<(f64, PrismFace)> {
    let mut found: Vec<(f64, PrismFace)> = prism
        .faces()
        .iter()
        .filter_map(|&(face, tri)| ray_triangle(origin, dir, tri).map(|t| (t, face)))
        .collect();
    found.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut merged: Vec<(f64, PrismFace)> = Vec::with_capacity(found.len());
    for (t, face) in found {
        match merged.last_mut() {
            Some(last) if (t - last.0).abs() <= EDGE_SLACK * (1.0 + t.abs()) => {
                if face == PrismFace::Top {
                    last.1 = face;
                }
            }
            _ => merged.push((t, face)),
        }
    }
    merged
}

/// Möller and Trumbore's ray/triangle test with [`EDGE_SLACK`] on the edges: the ray's parameter
/// at the crossing, `t >= 0`.
pub(super) fn ray_triangle(origin: DVec3, dir: DVec3, [a, b, c]: [DVec3; 3]) -> Option<f64> {
    let (e1, e2) = (b - a, c - a);
    let p = dir.cross(e2);
    let det = e1.dot(p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = origin - a;
    let u = s.dot(p) / det;
    let q = s.cross(e1);
    let v = dir.dot(q) / det;
    let t = e2.dot(q) / det;
    let slack = -EDGE_SLACK;
    (u >= slack && v >= slack && u + v <= 1.0 + EDGE_SLACK && t >= 0.0).then_some(t)
}

/// The prism coordinates (barycentric `b`, depth fraction `w`) of world point `p`, if it lies in
/// the prism.
fn locate(prism: &Prism, p: DVec3, guess: Option<(DVec2, f64)>) -> Option<(DVec2, f64)> {
    let c = solve(prism, p, guess)?;
    let inside = c.0.x >= -EDGE_SLACK
        && c.0.y >= -EDGE_SLACK
        && c.0.x + c.0.y <= 1.0 + EDGE_SLACK
        && (-EDGE_SLACK..=1.0 + EDGE_SLACK).contains(&c.1);
    inside.then_some(c)
}

/// [`locate`] for points known to lie on or in the prism: the coordinates clamped into it.
fn locate_loose(prism: &Prism, p: DVec3, guess: Option<(DVec2, f64)>) -> Option<(DVec2, f64)> {
    let (b, w) = solve(prism, p, guess)?;
    let b = b.max(DVec2::ZERO);
    let b = if b.x + b.y > 1.0 { b / (b.x + b.y) } else { b };
    Some((b, w.clamp(0.0, 1.0)))
}

/// Newton's method on `point(b, w) = p`; `None` where it does not converge (a degenerate prism).
fn solve(prism: &Prism, p: DVec3, guess: Option<(DVec2, f64)>) -> Option<(DVec2, f64)> {
    let (mut b, mut w) = guess.unwrap_or((DVec2::splat(1.0 / 3.0), 0.5));
    let scale = (prism.top[1] - prism.top[0])
        .length()
        .max((prism.top[2] - prism.top[0]).length())
        .max(prism.depth[0]);
    for _ in 0..NEWTON_STEPS {
        let r = prism.point(b, w) - p;
        if r.length() <= 1e-13 * scale {
            return Some((b, w));
        }
        let j = prism.jacobian(b, w);
        if j.determinant().abs() < 1e-300 {
            return None;
        }
        let step = j.inverse() * r;
        b -= DVec2::new(step.x, step.y);
        w -= step.z;
        if !(b.is_finite() && w.is_finite()) {
            return None;
        }
    }
    let r = prism.point(b, w) - p;
    (r.length() <= 1e-9 * scale).then_some((b, w))
}
