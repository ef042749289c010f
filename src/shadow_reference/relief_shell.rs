//! One relief triangle as an occluder: the solid between its displaced height field and its bottom plane,
//! over the triangle's footprint, tested exactly with the reference tracer in the triangle's texture space.
//!
//! The frame. A point of the triangle's plane is an affine function of its height-map uv `(hu, hv)` (the
//! interpolation the rasteriser does); a point `z` below it (depth in height-uv units, as docs/conventions.md
//! defines it) lies `z * depth_len` world units behind the front face, with `depth_len` computed as `relief_frame.glsl` does
//! (the geometric mean of the world lengths of one uv0 unit, over the area factor of the height uv transform).
//! So world space and `(hu, hv, z)` are related by one affine map per triangle, and a straight world ray stays
//! straight in it.
//!
//! The occluder. The relief a renderer draws for a polygon is the height field seen *through the
//! polygon*: a ray that crosses the triangle's top plane inside its footprint is traced down from there,
//! and the field blocks it where it first dips below the surface (`d(hu, hv) <= z`, with `d` the bilinear
//! depth of the unorm16-quantized heights the GPU samples), provided that point still lies over the
//! footprint; a ray that reaches the shell sideways, below the top plane, meets nothing, as no fragment of
//! the polygon ever traces it, and a ray that leaves the footprint before meeting the field passes beside
//! the object (the silhouette cut of clamp-addressed maps). This is the object the surface pass and the
//! shadow pass draw, so the reference and the renderer agree on what casts; a closed relief object gets
//! its walls from its other faces. The test clips the segment to the prism (footprint x `[0, s]`) and
//! traces the line from its top-plane crossing with [`crate::heightfield::reference::trace`]: the first
//! depth below the field, accepted if it falls inside the clipped piece.
//!
//! Direction: the trace needs a ray going down, so a segment climbing toward the light is traced reversed, from
//! its upper end; both orders answer the same "blocked" question. For the *nearest* hit (`first_hit`) a
//! climbing segment reports a point inside the solid that is not always its first contact (documented there).
//! A segment parallel to the plane (slope beyond [`MAX_SLOPE`]) cannot be traced from the top plane; it is
//! sampled every eighth of a texel along its footprint piece instead, the one approximate case.

use std::sync::Arc;

use glam::{DMat2, DMat3, DVec2, DVec3, Vec2, Vec3};

use super::bvh::Aabb;
use crate::geometry::{depth_length, world_per_uv};
use crate::heightfield::reference::{surface_depth, trace, Address, RefRay, SurfaceModel};
use crate::heightfield::Heightfield;

/// Barycentric slack that keeps coplanar neighbours from leaving a crack of rounding between them.
const FOOTPRINT_TOLERANCE: f64 = 1e-7;

/// Horizontal uv per unit of depth beyond which a line counts as parallel to the plane: its top-plane crossing
/// would be so far that the trace's walk (cells proportional to the slope) stops paying.
pub const MAX_SLOPE: f64 = 1e4;

/// Samples per texel along a parallel segment.
const PARALLEL_SAMPLES_PER_TEXEL: f64 = 8.0;

/// How far (relative to the depth scale) a receiver may lie from the exact field and still count as lying on it.
pub const SNAP_RANGE: f64 = 0.25;

/// A relief triangle's occluding solid.
#[derive(Debug, Clone)]
pub struct ReliefShell {
    corners: [Vec3; 3],
    heights: Arc<Heightfield>,
    address: Address,
    depth_scale: f64,
    /// World position of the first corner, in f64 so the frame keeps its precision far from the origin.
    anchor: DVec3,
    /// Height uv of the first corner.
    anchor_uv: DVec2,
    /// World offset from `anchor` to `(hu, hv, z)` offset, and back.
    to_local: DMat3,
    to_world: DMat3,
    /// `(hu, hv)` offset from `anchor_uv` to the barycentric weights of corners 1 and 2.
    to_bary: DMat2,
}

/// A shell's frame as numbers, for a copy of the test elsewhere (the GPU's ray queries).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShellFrame {
    /// Rows of the affine map from a world point `(x, y, z, 1)` to `(hu, hv, z)`.
    pub to_local: [[f64; 4]; 3],
    /// Columns of the map from a height-uv offset from `anchor_uv` to the barycentric weights of
    /// corners 1 and 2.
    pub to_bary: [[f64; 2]; 2],
    /// Height uv of the first corner.
    pub anchor_uv: [f64; 2],
    /// Depth of height 0 below the top plane, in height-uv units.
    pub depth_scale: f64,
}

/// Where a world segment lies in one shell's frame: `q(t) = q0 + t dq`, `t` clipped to the prism.
struct Span {
    q0: DVec3,
    dq: DVec3,
    ta: f64,
    tb: f64,
}

impl Span {
    fn at(&self, t: f64) -> DVec3 {
        self.q0 + self.dq * t
    }
}

impl ReliefShell {
    /// The shell of the triangle with world `corners`, height-map uvs `height_uv` and uv0 `uv0` (for the depth
    /// unit), or `None` when the triangle or one of its uv maps is degenerate (it then has no texture frame).
    pub fn new(
        corners: [Vec3; 3],
        height_uv: [Vec2; 3],
        uv0: [Vec2; 3],
        depth_scale: f32,
        heights: Arc<Heightfield>,
        address: Address,
    ) -> Option<ReliefShell> {
        let p = corners.map(|c| c.as_dvec3());
        let (e1, e2) = (p[1] - p[0], p[2] - p[0]);
        let normal = e1.cross(e2).try_normalize()?;
        let per_height = world_per_uv(e1, e2, height_uv)?;
        let depth_len = depth_length(e1, e2, height_uv, uv0)?;
        let to_world = DMat3::from_cols(per_height[0], per_height[1], -normal * depth_len);
        let to_local = to_world.inverse();
        let uv = height_uv.map(|h| h.as_dvec2());
        let to_bary = DMat2::from_cols(uv[1] - uv[0], uv[2] - uv[0]).inverse();
        let finite = to_local.is_finite() && to_bary.is_finite() && depth_len.is_finite();
        finite.then(|| ReliefShell {
            corners,
            heights,
            address,
            depth_scale: f64::from(depth_scale),
            anchor: p[0],
            anchor_uv: uv[0],
            to_local,
            to_world,
            to_bary,
        })
    }

    /// The shell's frame, as [`ShellFrame`] spells it out.
    pub fn frame(&self) -> ShellFrame {
        let m = self.to_local.transpose();
        let shift = self.to_local * self.anchor;
        let uv = [self.anchor_uv.x, self.anchor_uv.y, 0.0];
        let row = |i: usize| {
            let r = m.col(i);
            [r.x, r.y, r.z, uv[i] - shift[i]]
        };
        ShellFrame {
            to_local: [row(0), row(1), row(2)],
            to_bary: [self.to_bary.x_axis.into(), self.to_bary.y_axis.into()],
            anchor_uv: self.anchor_uv.into(),
            depth_scale: self.depth_scale,
        }
    }

    /// The height map the shell's field reads.
    pub fn heights(&self) -> &Arc<Heightfield> {
        &self.heights
    }

    /// How the shell's height map is addressed.
    pub fn address(&self) -> Address {
        self.address
    }

    /// The triangle's polygon (the top plane), as a flat caster would see it.
    pub fn corners(&self) -> [Vec3; 3] {
        self.corners
    }

    /// The box around the prism (the polygon and its copy on the bottom plane), widened by the depths over
    /// which [`Self::surface_point`] still moves a receiver onto the field.
    pub fn bounds(&self) -> Aabb {
        let depth = self.to_world.z_axis * self.depth_scale;
        let (up, down) = (
            (-depth * SNAP_RANGE).as_vec3(),
            (depth * (1.0 + SNAP_RANGE)).as_vec3(),
        );
        let [a, b, c] = self.corners;
        Aabb::around(&[a + up, b + up, c + up, a + down, b + down, c + down])
    }

    fn local(&self, p: Vec3) -> DVec3 {
        let q = self.to_local * (p.as_dvec3() - self.anchor);
        DVec3::new(q.x + self.anchor_uv.x, q.y + self.anchor_uv.y, q.z)
    }

    fn world(&self, q: DVec3) -> Vec3 {
        let offset = DVec3::new(q.x - self.anchor_uv.x, q.y - self.anchor_uv.y, q.z);
        (self.anchor + self.to_world * offset).as_vec3()
    }

    /// Barycentric weights of the footprint point `(hu, hv)`.
    fn bary(&self, q: DVec3) -> [f64; 3] {
        let w = self.to_bary * (DVec2::new(q.x, q.y) - self.anchor_uv);
        [1.0 - w.x - w.y, w.x, w.y]
    }

    fn field_depth(&self, q: DVec3) -> f64 {
        surface_depth(
            &self.heights,
            q.x,
            q.y,
            self.depth_scale,
            SurfaceModel::Bilinear,
            self.address,
        )
    }

    fn in_solid(&self, q: DVec3) -> bool {
        q.z >= self.field_depth(q)
    }

    /// The exact surface point over `p`, when `p` lies in the prism within [`SNAP_RANGE`] of the field: a
    /// receiver read back from a frame carries the method's error, and would otherwise start its light rays
    /// inside the solid it lies on. With `displaced == false` the point goes to the polygon instead (the
    /// flat-caster world, where the relief is its polygon).
    pub fn surface_point(&self, p: Vec3, displaced: bool) -> Option<Vec3> {
        let q = self.local(p);
        let s = self.depth_scale;
        let inside = self.bary(q).iter().all(|&b| b >= -FOOTPRINT_TOLERANCE)
            && (-SNAP_RANGE * s..=s * (1.0 + SNAP_RANGE)).contains(&q.z);
        let d = self.field_depth(q);
        if !inside || (q.z - d).abs() > SNAP_RANGE * s {
            return None;
        }
        let z = if displaced { d } else { 0.0 };
        Some(self.world(DVec3::new(q.x, q.y, z)))
    }

    /// Where the segment `origin + t dir`, `t` in `[0, max_t]`, meets the solid (see the module docs): for a
    /// segment going down, its first contact; for one climbing, a point of the segment inside the solid.
    pub fn hit(&self, origin: Vec3, dir: Vec3, max_t: f32) -> Option<f32> {
        // The tracer asserts on non-finite rays; such a ray has no place to be blocked at.
        if !origin.is_finite() || !dir.is_finite() {
            return None;
        }
        let q0 = self.local(origin);
        let dq = self.to_local * dir.as_dvec3();
        let horizontal = DVec2::new(dq.x, dq.y).length();
        // `>=`, so a zero direction (a point, not a line) is sampled rather than traced.
        let t = if horizontal >= MAX_SLOPE * dq.z.abs() {
            let span = self.clip(origin, dir, max_t)?;
            self.scan(&span, horizontal)
        } else {
            self.traced(q0, dq, f64::from(max_t))
        };
        t.map(|t| t as f32)
    }

    /// The segment in the shell's frame, clipped to `[0, s]` in depth and to the footprint; `None` if empty.
    fn clip(&self, origin: Vec3, dir: Vec3, max_t: f32) -> Option<Span> {
        let q0 = self.local(origin);
        let dq = self.to_local * dir.as_dvec3();
        let (mut ta, mut tb) = (0.0, f64::from(max_t));
        keep_above(&mut ta, &mut tb, q0.z, dq.z, 0.0);
        keep_above(&mut ta, &mut tb, -q0.z, -dq.z, -self.depth_scale);
        let b0 = self.bary(q0);
        let b1 = self.bary(q0 + dq);
        for k in 0..3 {
            keep_above(&mut ta, &mut tb, b0[k], b1[k] - b0[k], -FOOTPRINT_TOLERANCE);
        }
        (ta <= tb).then_some(Span { q0, dq, ta, tb })
    }

    /// Where the line `q0 + t dq` (shell frame) first dips below the field, traced down from its
    /// top-plane crossing as a fragment of the triangle there would trace it, if that `t` lies in
    /// `[0, max_t]`: the crossing must lie over the footprint, and with clamp addressing a ray
    /// that entered the map and leaves it before meeting the field passes beside the object.
    fn traced(&self, q0: DVec3, dq: DVec3, max_t: f64) -> Option<f64> {
        let entry = q0 + dq * (-q0.z / dq.z);
        if self.bary(entry).iter().any(|&b| b < -FOOTPRINT_TOLERANCE) {
            return None;
        }
        let down = dq * dq.z.signum();
        let ray = RefRay {
            u0: entry.x,
            v0: entry.y,
            dx: down.x,
            dy: down.y,
            dz: down.z,
        };
        let hit = trace(
            &self.heights,
            &ray,
            self.depth_scale,
            SurfaceModel::Bilinear,
            self.address,
        );
        let in_map = |u: f64, v: f64| (0.0..=1.0).contains(&u) && (0.0..=1.0).contains(&v);
        if self.address == Address::Clamp && in_map(entry.x, entry.y) && !in_map(hit.u, hit.v) {
            return None;
        }
        let t = (hit.z - q0.z) / dq.z;
        (0.0..=max_t).contains(&t).then_some(t)
    }

    /// The first sample inside the solid along a segment parallel to the plane.
    fn scan(&self, span: &Span, horizontal: f64) -> Option<f64> {
        let texels = f64::from(self.heights.width().max(self.heights.height()));
        let length = (span.tb - span.ta) * horizontal * texels;
        let steps = (length * PARALLEL_SAMPLES_PER_TEXEL).ceil().clamp(1.0, 1e6) as u32;
        (0..=steps)
            .map(|k| span.ta + (span.tb - span.ta) * f64::from(k) / f64::from(steps))
            .find(|&t| self.in_solid(span.at(t)))
    }
}

/// Narrows `[ta, tb]` to where `a + t b >= floor`.
fn keep_above(ta: &mut f64, tb: &mut f64, a: f64, b: f64, floor: f64) {
    if b == 0.0 {
        if a < floor {
            *ta = f64::INFINITY;
        }
        return;
    }
    let t = (floor - a) / b;
    if b > 0.0 {
        *ta = ta.max(t);
    } else {
        *tb = tb.min(t);
    }
}
