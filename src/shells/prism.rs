//! The shell's prisms: one per triangle, its top the triangle, its bottom the triangle moved down
//! the vertex normals by the relief's full depth, and the map from prism coordinates to the world.

use glam::{DMat3, DVec2, DVec3, Mat3, Vec3};

use crate::displaced_reference::welded_depth_lengths;
use crate::geometry::Mesh;
use crate::scene::{HeightLookup, HeightUv};

/// Why a shell could not be built.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShellError {
    /// The depth scale is zero, negative or not finite: a shell needs a positive depth.
    #[error("mesh {mesh:?}: a shell needs a positive, finite depth scale, not {depth_scale}")]
    DepthScale {
        /// The mesh's name.
        mesh: String,
        /// The depth scale asked for.
        depth_scale: f32,
    },
    /// No triangle has usable uvs, so no depth has a world length.
    #[error("mesh {mesh:?} has no triangle with usable texture coordinates to extrude")]
    NoUvs {
        /// The mesh's name.
        mesh: String,
    },
}

/// One face of a prism, where a ray crosses into or out of it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PrismFace {
    /// The triangle itself: relief depth 0, the outside of the shell.
    Top,
    /// The triangle at the relief's full depth.
    Bottom,
    /// One of the three side quads, shared with the neighbour across that edge (or the shell's
    /// own wall at an open boundary).
    Side,
}

/// One triangle extruded: corners in world space, the direction and world length each goes
/// down, and the height uv of each.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Prism {
    /// The triangle's corners (relief depth 0).
    pub top: [DVec3; 3],
    /// Each corner's unit normal (outward: the relief goes the other way).
    pub normal: [DVec3; 3],
    /// World length of the relief's full depth at each corner.
    pub depth: [f64; 3],
    /// Height uv at each corner.
    pub uv: [DVec2; 3],
    /// Each corner's vertex identity: repeats of one point with one normal share it.
    pub welds: [u32; 3],
}

/// `(1 - b.x - b.y, b.x, b.y)`: the weights of a prism's corners at barycentric `b`.
fn weights(b: DVec2) -> [f64; 3] {
    [1.0 - b.x - b.y, b.x, b.y]
}

fn blend<T: std::ops::Mul<f64, Output = T> + std::ops::Add<Output = T> + Copy>(
    v: [T; 3],
    b: DVec2,
) -> T {
    let [w0, w1, w2] = weights(b);
    v[0] * w0 + v[1] * w1 + v[2] * w2
}

impl Prism {
    /// The corners at the relief's full depth.
    pub fn bottom(&self) -> [DVec3; 3] {
        [0, 1, 2].map(|k| self.top[k] - self.normal[k] * self.depth[k])
    }

    /// The world point at barycentric weights `b` and depth fraction `w` (0 at the top, 1 at the
    /// bottom): down the interpolated normal, renormalized, by the interpolated depth, as the
    /// displaced reference moves the vertices of a finely subdivided triangle.
    pub fn point(&self, b: DVec2, w: f64) -> DVec3 {
        let m = blend(self.normal, b);
        blend(self.top, b) - m.normalize_or_zero() * (blend(self.depth, b) * w)
    }

    /// The height uv at barycentric weights `b`.
    pub fn uv_at(&self, b: DVec2) -> DVec2 {
        blend(self.uv, b)
    }

    /// The derivatives of [`Prism::point`] along `b.x`, `b.y` and `w`, as columns.
    pub fn jacobian(&self, b: DVec2, w: f64) -> DMat3 {
        let m = blend(self.normal, b);
        let len = m.length().max(1e-300);
        let n = m / len;
        let depth = blend(self.depth, b);
        let along = |k: usize| {
            let dm = self.normal[k] - self.normal[0];
            // d(m / |m|) = (dm - n (n . dm)) / |m|
            let dn = (dm - n * n.dot(dm)) / len;
            (self.top[k] - self.top[0]) - (n * (self.depth[k] - self.depth[0]) + dn * depth) * w
        };
        DMat3::from_cols(along(1), along(2), -n * depth)
    }

    /// The prism's eight boundary triangles with the face each belongs to. Each side quad is split
    /// along the diagonal from the top of its lower-identity corner to the bottom of the other,
    /// so the prism across the edge splits it alike and the two share the face exactly.
    pub fn faces(&self) -> [(PrismFace, [DVec3; 3]); 8] {
        let (t, d) = (self.top, self.bottom());
        let side = |i: usize, j: usize| {
            let (lo, hi) = if self.welds[i] <= self.welds[j] {
                (i, j)
            } else {
                (j, i)
            };
            [[t[lo], t[hi], d[hi]], [t[lo], d[hi], d[lo]]]
        };
        let [s01, s12, s20] = [side(0, 1), side(1, 2), side(2, 0)];
        [
            (PrismFace::Top, t),
            (PrismFace::Bottom, d),
            (PrismFace::Side, s01[0]),
            (PrismFace::Side, s01[1]),
            (PrismFace::Side, s12[0]),
            (PrismFace::Side, s12[1]),
            (PrismFace::Side, s20[0]),
            (PrismFace::Side, s20[1]),
        ]
    }
}

/// A mesh's relief shell: its prisms and the height field traced inside them.
#[derive(Debug, Clone)]
pub struct Shell {
    /// One prism per triangle whose corners have depth lengths, in the mesh's order.
    pub prisms: Vec<Prism>,
    /// The heights the rays are traced against.
    pub heights: HeightLookup,
    /// Each prism's bounding box, widened by its depth (its bottom bulges past the flat
    /// triangle of its corners where the normals part), so a ray can pass most prisms by.
    pub(super) bounds: Vec<[DVec3; 2]>,
}

impl Shell {
    /// The shell of `mesh` for relief `heights` at `depth_scale`: its prisms as [`extrude`]
    /// makes them, traced against `heights`.
    pub fn new(mesh: &Mesh, heights: &HeightLookup, depth_scale: f32) -> Result<Shell, ShellError> {
        let prisms: Vec<Prism> = extrude(mesh, &heights.uv, depth_scale)?
            .into_iter()
            .map(|(_, p)| p)
            .collect();
        let bounds = prisms
            .iter()
            .map(|p| {
                let bottom = p.bottom();
                let corners = p.top.iter().chain(bottom.iter()).copied();
                let (lo, hi) = corners.fold(
                    (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
                    |(lo, hi), q| (lo.min(q), hi.max(q)),
                );
                let pad = DVec3::splat(p.depth.iter().copied().fold(0.0, f64::max));
                [lo - pad, hi + pad]
            })
            .collect();
        Ok(Shell {
            prisms,
            heights: heights.clone(),
            bounds,
        })
    }
}

/// `mesh`'s prisms (in world space: its transform applied) for relief at `depth_scale` whose
/// height uv is `uv`, each with the mesh's vertex indices of its corners, extruded as
/// [`crate::displaced_reference::displace`] moves the vertices. A triangle gets a prism where
/// each of its corners has a depth length, from any triangle of that vertex with usable uvs: a
/// pole's fan, whose uvs collapse, is extruded like its neighbours, as the reference moves its
/// vertices. Only the uv map matters, not the heights, so the GPU's shell needs no decoded map.
pub fn extrude(
    mesh: &Mesh,
    uv: &HeightUv,
    depth_scale: f32,
) -> Result<Vec<([u32; 3], Prism)>, ShellError> {
    if !(depth_scale.is_finite() && depth_scale > 0.0) {
        return Err(ShellError::DepthScale {
            mesh: mesh.name.clone(),
            depth_scale,
        });
    }
    let linear = Mat3::from_mat4(mesh.transform);
    let normal_matrix = linear.inverse().transpose();
    let welded = welded_depth_lengths(mesh, uv);
    if welded.iter().all(|(_, length)| length.is_none()) {
        return Err(ShellError::NoUvs {
            mesh: mesh.name.clone(),
        });
    }
    let s = f64::from(depth_scale);
    let corner = |k: usize| {
        let v = &mesh.vertices[k];
        let top = mesh
            .transform
            .transform_point3(Vec3::from(v.position))
            .as_dvec3();
        let n = (normal_matrix * Vec3::from(v.normal))
            .normalize_or_zero()
            .as_dvec3();
        let (weld, length) = welded[k];
        // A vertex with only degenerate-uv triangles about it (a pole's fan on some exporters'
        // spheres) stays on its polygon, as the reference leaves it.
        let depth = s * length.unwrap_or(0.0);
        (top, n, depth, uv.of(v).as_dvec2(), weld)
    };
    let prisms: Vec<([u32; 3], Prism)> = mesh
        .indices
        .chunks_exact(3)
        .map(|t| {
            let c = [t[0], t[1], t[2]].map(|k| corner(k as usize));
            let prism = Prism {
                top: c.map(|c| c.0),
                normal: c.map(|c| c.1),
                depth: c.map(|c| c.2),
                uv: c.map(|c| c.3),
                welds: c.map(|c| c.4),
            };
            ([t[0], t[1], t[2]], prism)
        })
        .filter(|(_, p)| p.normal.iter().all(|n| *n != DVec3::ZERO))
        .collect();
    if prisms.is_empty() {
        return Err(ShellError::NoUvs {
            mesh: mesh.name.clone(),
        });
    }
    Ok(prisms)
}
