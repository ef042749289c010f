//! A shell as triangles a rasterizer can draw: each prism's six corners (the triangle and its
//! extrusion) and its eight faces, wound to face out of the prism, every vertex carrying the
//! whole prism (corners, normals, depths and uvs) so that a fragment on any face can trace the
//! relief inside it without looking anything up. World space, like [`super::Prism`].

use glam::{DVec3, Mat3, Vec3};

use super::prism::{extrude, Prism, ShellError};
use crate::geometry::Mesh;
use crate::scene::HeightUv;

/// One corner of a prism as the shells pipeline reads it (`shaders/passes/shell.vert`): the
/// first six fields are a mesh vertex's, in world space; the rest are the same on all six
/// corners of a prism. 232 bytes.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct ShellVertex {
    /// World position: the triangle's corner or its extrusion.
    pub position: [f32; 3],
    /// World unit normal of the mesh vertex.
    pub normal: [f32; 3],
    /// Texture coordinate set 0.
    pub uv: [f32; 2],
    /// Texture coordinate set 1.
    pub uv1: [f32; 2],
    /// World tangent; w: bitangent sign (mirroring transforms folded in).
    pub tangent: [f32; 4],
    /// Linear RGBA vertex colour.
    pub color: [f32; 4],
    /// Prism coordinates of this corner: barycentric weights of corners 1 and 2, depth fraction
    /// (0 on the triangle, 1 at the relief's full depth); w: which sides are the shell's open
    /// boundary, no prism across them (bit k for side k, corners k and k + 1).
    pub prism: [f32; 4],
    /// The prism's three top corners (xyz) and the world depth of each (w).
    pub top: [[f32; 4]; 3],
    /// The prism's three corner normals (xyz) and how side k (corners k and k + 1) is split
    /// (w: 1 along the diagonal from corner k's top, 0 from the other corner's).
    pub normals: [[f32; 4]; 3],
    /// Texture coordinates of the three corners: uv0 of corners 0 and 1, uv0 of corner 2 and
    /// uv1 of corner 0, uv1 of corners 1 and 2.
    pub uvs: [[f32; 4]; 3],
}

const _: () = assert!(std::mem::size_of::<ShellVertex>() == 232);

/// A mesh's shell, ready to upload: six vertices and 24 indices per prism.
#[derive(Debug, Clone)]
pub struct ShellMesh {
    /// Each prism's corners: the triangle's three, then their extrusions.
    pub vertices: Vec<ShellVertex>,
    /// Eight outward-facing triangles per prism.
    pub indices: Vec<u32>,
    /// How many prisms (triangles of the mesh) it holds.
    pub prisms: usize,
}

impl ShellMesh {
    /// The shell of `mesh` for a relief at `depth_scale` mapped by `uv`, as [`extrude`] builds
    /// its prisms.
    pub fn new(mesh: &Mesh, uv: &HeightUv, depth_scale: f32) -> Result<ShellMesh, ShellError> {
        // A triangle of no area (a pole's fan on a lat-long sphere) makes a prism of no volume,
        // which no ray can enter and whose coordinates no fragment could solve for.
        let prisms: Vec<_> = extrude(mesh, uv, depth_scale)?
            .into_iter()
            .filter(|(_, p)| {
                let [a, b, c] = p.top;
                let longest = (b - a).length().max((c - b).length()).max((a - c).length());
                (b - a).cross(c - a).length() > 1e-6 * longest * longest
            })
            .collect();
        let linear = Mat3::from_mat4(mesh.transform);
        let mirror = if linear.determinant() < 0.0 {
            -1.0
        } else {
            1.0
        };
        let open = open_sides(&prisms);
        let mut vertices = Vec::with_capacity(prisms.len() * 6);
        let mut indices = Vec::with_capacity(prisms.len() * 24);
        for ((corners, prism), open) in prisms.iter().zip(open) {
            let source = corners.map(|k| &mesh.vertices[k as usize]);
            let shared = Shared::of(prism, source.map(|v| (v.uv, v.uv1)));
            let base = vertices.len() as u32;
            let bottom = prism.bottom();
            for (level, points) in [(0.0, prism.top), (1.0, bottom)] {
                for (k, (point, v)) in points.iter().zip(source).enumerate() {
                    let tangent = linear * Vec3::from_slice(&v.tangent[..3]);
                    let b = [[0.0, 0.0], [1.0, 0.0], [0.0, 1.0]][k];
                    vertices.push(ShellVertex {
                        position: point.as_vec3().to_array(),
                        normal: prism.normal[k].as_vec3().to_array(),
                        uv: v.uv,
                        uv1: v.uv1,
                        tangent: tangent
                            .normalize_or_zero()
                            .extend(v.tangent[3] * mirror)
                            .to_array(),
                        color: v.color,
                        prism: [b[0], b[1], level, open],
                        top: shared.top,
                        normals: shared.normals,
                        uvs: shared.uvs,
                    });
                }
            }
            let points: Vec<DVec3> = prism.top.iter().chain(&bottom).copied().collect();
            for face in faces(prism) {
                indices.extend(outward(face, &points).map(|k| base + k));
            }
        }
        Ok(ShellMesh {
            vertices,
            indices,
            prisms: prisms.len(),
        })
    }
}

/// Per prism, its sides that no other prism shares (bit k: corners k and k + 1), as a float.
fn open_sides(prisms: &[([u32; 3], Prism)]) -> Vec<f32> {
    let side = |p: &Prism, k: usize| {
        let (a, b) = (p.welds[k], p.welds[(k + 1) % 3]);
        (a.min(b), a.max(b))
    };
    let mut count = std::collections::HashMap::new();
    for (_, p) in prisms {
        for k in 0..3 {
            *count.entry(side(p, k)).or_insert(0u32) += 1;
        }
    }
    prisms
        .iter()
        .map(|(_, p)| {
            (0..3)
                .filter(|&k| count[&side(p, k)] < 2)
                .map(|k| 1u8 << k)
                .sum::<u8>()
                .into()
        })
        .collect()
}

/// The per-prism fields every corner repeats.
struct Shared {
    top: [[f32; 4]; 3],
    normals: [[f32; 4]; 3],
    uvs: [[f32; 4]; 3],
}

impl Shared {
    fn of(prism: &Prism, uv: [([f32; 2], [f32; 2]); 3]) -> Shared {
        let top = [0, 1, 2].map(|k| {
            prism.top[k]
                .as_vec3()
                .extend(prism.depth[k] as f32)
                .to_array()
        });
        // Which way each side (corners k, k + 1) is split, as `faces` splits it: 1 from corner
        // k's top, 0 from the other's.
        let split = |k: usize| f32::from(u8::from(prism.welds[k] <= prism.welds[(k + 1) % 3]));
        let normals = [0, 1, 2].map(|k| prism.normal[k].as_vec3().extend(split(k)).to_array());
        let [(a0, a1), (b0, b1), (c0, c1)] = uv;
        Shared {
            top,
            normals,
            uvs: [
                [a0[0], a0[1], b0[0], b0[1]],
                [c0[0], c0[1], a1[0], a1[1]],
                [b1[0], b1[1], c1[0], c1[1]],
            ],
        }
    }
}

/// The prism's eight triangles over its corners (0-2 the top, 3-5 the bottom), split as
/// [`Prism::faces`] splits them, so the prism across each side shares the side exactly.
fn faces(prism: &Prism) -> [[u32; 3]; 8] {
    let side = |i: u32, j: u32| {
        let (lo, hi) = if prism.welds[i as usize] <= prism.welds[j as usize] {
            (i, j)
        } else {
            (j, i)
        };
        [[lo, hi, hi + 3], [lo, hi + 3, lo + 3]]
    };
    let [s01, s12, s20] = [side(0, 1), side(1, 2), side(2, 0)];
    [
        [0, 1, 2],
        [3, 4, 5],
        s01[0],
        s01[1],
        s12[0],
        s12[1],
        s20[0],
        s20[1],
    ]
}

/// `face` wound so that its normal (right-handed, as glTF's front faces) points away from the
/// prism's centre: the rasterizer then culls the faces a ray leaves through and keeps the ones
/// it enters by.
fn outward(face: [u32; 3], points: &[DVec3]) -> [u32; 3] {
    let centre = points.iter().copied().sum::<DVec3>() / points.len() as f64;
    let [a, b, c] = face.map(|k| points[k as usize]);
    let normal = (b - a).cross(c - a);
    if normal.dot((a + b + c) / 3.0 - centre) < 0.0 {
        [face[0], face[2], face[1]]
    } else {
        face
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::sphere_mesh;

    #[test]
    fn every_face_of_a_sphere_shell_faces_out_and_every_side_is_shared() {
        let sphere = sphere_mesh("sphere", 1.0, 8, 16, 0);
        let shell = ShellMesh::new(&sphere, &HeightUv::IDENTITY, 0.01).unwrap();
        assert_eq!(shell.vertices.len(), shell.prisms * 6);
        assert_eq!(shell.indices.len(), shell.prisms * 24);
        let point = |k: u32| Vec3::from(shell.vertices[k as usize].position).as_dvec3();
        let mut sides = std::collections::HashMap::new();
        let key = |p: DVec3| (p * 1e6).round().as_i64vec3().to_array();
        for (t, tri) in shell.indices.chunks_exact(3).enumerate() {
            let [a, b, c] = [tri[0], tri[1], tri[2]].map(point);
            let normal = (b - a).cross(c - a);
            if normal.length() < 1e-12 {
                continue;
            }
            let prism = t / 8;
            let centre = (0..6).map(|k| point((prism * 6 + k) as u32)).sum::<DVec3>() / 6.0;
            assert!(
                normal.dot((a + b + c) / 3.0 - centre) > 0.0,
                "face {t} points into its prism"
            );
            if t % 8 >= 2 {
                // A side seen from the prism across it is the same triangle, wound the other way.
                let mut corners = [key(a), key(b), key(c)];
                corners.sort();
                *sides.entry(corners).or_insert(0) += 1;
            }
        }
        // A closed sphere has no open boundary: the prism across every side draws it too.
        let shared = sides.values().filter(|&&n| n == 2).count();
        assert_eq!(
            shared,
            sides.len(),
            "{shared} of {} side triangles shared",
            sides.len()
        );
    }
}
