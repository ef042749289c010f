//! The ray test of a plain (flat, opaque) triangle, from either side.
//!
//! Both sides block: the reference answers what is physically in the way, and a closed mesh blocks light
//! whichever of its faces the ray meets, whatever the material's back-face culling does when it is drawn.

use glam::Vec3;

/// Rays closer to the triangle's plane than this (sine of the angle, times the edge lengths) count as parallel:
/// they meet it at most along an edge-on line, which has no area to block.
const PARALLEL: f32 = 1e-12;

/// A world-space triangle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Triangle {
    /// Its three corners.
    pub corners: [Vec3; 3],
}

impl Triangle {
    /// Where the ray `origin + t dir` crosses the triangle, for `t` in `[0, max_t]` (Moeller and Trumbore's
    /// test, without culling).
    pub fn hit(&self, origin: Vec3, dir: Vec3, max_t: f32) -> Option<f32> {
        let [a, b, c] = self.corners;
        let (e1, e2) = (b - a, c - a);
        let p = dir.cross(e2);
        let det = e1.dot(p);
        if det.abs() <= PARALLEL * e1.length_squared().max(e2.length_squared()) {
            return None;
        }
        let inv = 1.0 / det;
        let s = origin - a;
        let u = s.dot(p) * inv;
        if !(0.0..=1.0).contains(&u) {
            return None;
        }
        let q = s.cross(e1);
        let v = dir.dot(q) * inv;
        if v < 0.0 || u + v > 1.0 {
            return None;
        }
        let t = e2.dot(q) * inv;
        (0.0..=max_t).contains(&t).then_some(t)
    }
}
