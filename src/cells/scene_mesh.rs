//! A scene's meshes as the closed mesh a cell complex is built from, in world space (the complex's grid is
//! aligned with the world's axes), with each triangle's vertices kept to interpolate the shading attributes at
//! the surface points of the maps ([`super::attributes`]). Meshes are chosen by name, as `--cells NODE` and
//! `relief cells --node` name them: every primitive of a glTF node carries the node's name.

use std::collections::HashMap;

use glam::{Mat3, Mat4, Vec3, Vec4};

use super::attributes::CornerAttributes;
use super::mesh::{ClosedMesh, MeshError};
use crate::scene::{Scene, Vertex};

/// Which meshes of a scene become cell complexes.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum MeshSelection {
    /// Every mesh, one complex per name.
    All,
    /// The meshes with this name, as one complex.
    Named(String),
}

impl std::str::FromStr for MeshSelection {
    type Err = std::convert::Infallible;

    fn from_str(text: &str) -> Result<MeshSelection, Self::Err> {
        Ok(match text {
            "all" => MeshSelection::All,
            name => MeshSelection::Named(name.to_owned()),
        })
    }
}

impl MeshSelection {
    /// The scene's meshes it selects, grouped by name in first-seen order; meshes without triangles are left out.
    pub fn groups(&self, scene: &Scene) -> Vec<(String, Vec<usize>)> {
        let mut groups: Vec<(String, Vec<usize>)> = Vec::new();
        for (k, mesh) in scene.meshes.iter().enumerate() {
            if mesh.indices.is_empty() {
                continue;
            }
            if let MeshSelection::Named(name) = self {
                if *name != mesh.name {
                    continue;
                }
            }
            match groups.iter_mut().find(|(name, _)| *name == mesh.name) {
                Some((_, members)) => members.push(k),
                None => groups.push((mesh.name.clone(), vec![k])),
            }
        }
        groups
    }
}

/// One group of a scene's meshes welded and checked closed, with the world-space vertices of each of its
/// triangles, which the cells pass shades from.
pub struct SceneMesh {
    /// The group's welded, checked mesh, in world space.
    pub mesh: ClosedMesh,
    /// Per triangle given to [`ClosedMesh::new`] (in mesh, then index order), its corners in world space.
    corners: Vec<[Vertex; 3]>,
}

impl SceneMesh {
    /// The meshes `members` of `scene` as one closed mesh; `origin` names it in errors.
    pub fn gather(scene: &Scene, members: &[usize], origin: &str) -> Result<SceneMesh, MeshError> {
        let mut positions = Vec::new();
        let mut triangles = Vec::new();
        let mut corners = Vec::new();
        for mesh in members.iter().map(|&k| &scene.meshes[k]) {
            let to_world = ToWorld::new(mesh.transform);
            let world: Vec<Vertex> = mesh.vertices.iter().map(|v| to_world.vertex(v)).collect();
            let base = positions.len() as u32;
            positions.extend(world.iter().map(|v| v.position.map(f64::from)));
            for t in mesh.indices.chunks_exact(3) {
                triangles.push([t[0] + base, t[1] + base, t[2] + base]);
                corners
                    .push([0, 1, 2].map(|c| world.get(t[c] as usize).copied().unwrap_or(world[0])));
            }
        }
        let mesh = ClosedMesh::new(origin, &positions, &triangles)?;
        Ok(SceneMesh { mesh, corners })
    }

    /// Every triangle's three corners as the cells pass shades from them, in the order [`SceneMesh::source`]
    /// numbers the triangles, each with the triangle across the edge opposite it.
    pub fn corners(&self) -> Vec<CornerAttributes> {
        let mut records: Vec<CornerAttributes> = self
            .corners
            .iter()
            .flatten()
            .map(|v| {
                CornerAttributes::pack(
                    v.position,
                    Vec3::from(v.normal).normalize_or(Vec3::Z).to_array(),
                    v.tangent,
                    v.uv,
                    v.uv1,
                    v.color,
                )
            })
            .collect();
        let triangles = self.mesh.triangles();
        let mut sharing: HashMap<[u32; 2], Vec<usize>> = HashMap::new();
        for (t, &[a, b, c]) in triangles.iter().enumerate() {
            for edge in [[b, c], [c, a], [a, b]] {
                sharing.entry(edge_key(edge)).or_default().push(t);
            }
        }
        for (t, &[a, b, c]) in triangles.iter().enumerate() {
            for (k, edge) in [[b, c], [c, a], [a, b]].into_iter().enumerate() {
                let across = sharing[&edge_key(edge)].iter().find(|&&u| u != t);
                if let Some(&u) = across {
                    records[3 * self.mesh.source_triangle(t) + k].opposite = self.source(u as u32);
                }
            }
        }
        records
    }

    /// The index in [`SceneMesh::corners`]' order (a third of the corner's) of the closed mesh's triangle
    /// `triangle`, which a [`super::SurfacePoint`] names.
    pub fn source(&self, triangle: u32) -> u32 {
        self.mesh.source_triangle(triangle as usize) as u32
    }
}

/// An edge's two welded vertices in either direction.
fn edge_key([a, b]: [u32; 2]) -> [u32; 2] {
    [a.min(b), a.max(b)]
}

/// How a mesh's vertices go to world space, as `mesh.vert` carries them: positions by the transform,
/// normals by the inverse transpose of its linear part, tangents by the linear part, the bitangent's sign
/// flipped by a mirroring transform. Made once per mesh.
struct ToWorld {
    transform: Mat4,
    linear: Mat3,
    normal: Mat3,
    mirror: f32,
}

impl ToWorld {
    fn new(transform: Mat4) -> ToWorld {
        let linear = Mat3::from_mat4(transform);
        ToWorld {
            transform,
            linear,
            normal: linear.inverse().transpose(),
            mirror: if linear.determinant() < 0.0 {
                -1.0
            } else {
                1.0
            },
        }
    }

    fn vertex(&self, v: &Vertex) -> Vertex {
        let tangent = self.linear * Vec3::new(v.tangent[0], v.tangent[1], v.tangent[2]);
        Vertex {
            position: self
                .transform
                .transform_point3(Vec3::from(v.position))
                .to_array(),
            normal: (self.normal * Vec3::from(v.normal))
                .normalize_or(Vec3::Z)
                .to_array(),
            tangent: Vec4::from((tangent, v.tangent[3] * self.mirror)).to_array(),
            ..*v
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::attributes::decode_octahedral;
    use super::*;
    use crate::scene::{box_mesh, Material, Mesh};

    fn corners_of(gathered: &SceneMesh, source: usize) -> Vec<CornerAttributes> {
        gathered.corners()[3 * source..3 * source + 3].to_vec()
    }

    fn scene_of(meshes: Vec<Mesh>) -> Scene {
        Scene {
            meshes,
            materials: vec![Material::default()],
            ..Scene::default()
        }
    }

    fn cube(name: &str, transform: Mat4) -> Mesh {
        Mesh {
            transform,
            ..box_mesh(name, Vec3::splat(0.5), 0)
        }
    }

    #[test]
    fn selections_group_meshes_by_name() {
        let scene = scene_of(vec![
            cube("a", Mat4::IDENTITY),
            cube("b", Mat4::IDENTITY),
            cube("a", Mat4::IDENTITY),
        ]);
        let all: MeshSelection = "all".parse().unwrap();
        assert_eq!(
            all.groups(&scene),
            vec![("a".into(), vec![0, 2]), ("b".into(), vec![1])]
        );
        let b: MeshSelection = "b".parse().unwrap();
        assert_eq!(b.groups(&scene), vec![("b".into(), vec![1])]);
        let none: MeshSelection = "c".parse().unwrap();
        assert!(none.groups(&scene).is_empty());
    }

    #[test]
    fn corners_are_the_triangles_in_world_space() {
        let turn = Mat4::from_translation(Vec3::new(3.0, 0.0, 0.0))
            * Mat4::from_rotation_z(std::f32::consts::FRAC_PI_2);
        let scene = scene_of(vec![cube("box", turn)]);
        let gathered = SceneMesh::gather(&scene, &[0], "box").expect("a box is closed");
        let (lo, hi) = gathered.mesh.bounds();
        assert!(
            (lo[0] - 2.5).abs() < 1e-6 && (hi[0] - 3.5).abs() < 1e-6,
            "{lo:?} {hi:?}"
        );
        for t in 0..gathered.mesh.triangles().len() {
            let corners = gathered.mesh.triangle(t);
            // The face's world normal: every corner of a box face shares it.
            let e1 = Vec3::from_array(std::array::from_fn(|k| {
                (corners[1][k] - corners[0][k]) as f32
            }));
            let e2 = Vec3::from_array(std::array::from_fn(|k| {
                (corners[2][k] - corners[0][k]) as f32
            }));
            let face_normal = e1.cross(e2).normalize();
            let source = gathered.source(t as u32) as usize;
            for (k, corner) in corners_of(&gathered, source).iter().enumerate() {
                let at: [f64; 3] = corner.position.map(f64::from);
                assert!(
                    (0..3).all(|c| (at[c] - corners[k][c]).abs() < 1e-6),
                    "triangle {t} corner {k}: {at:?} against {:?}",
                    corners[k]
                );
                let n = Vec3::from(corner.decoded_normal());
                assert!(
                    n.dot(face_normal) > 0.999,
                    "triangle {t}: {n} against {face_normal}"
                );
                let tangent = Vec3::from(decode_octahedral(corner.tangent));
                assert!(tangent.dot(n).abs() < 1e-3, "the tangent lies in the face");
                // The triangle across holds both corners of the edge opposite this one.
                let across = corners_of(&gathered, corner.opposite as usize);
                let edge = [(k + 1) % 3, (k + 2) % 3].map(|e| corners[e].map(|c| c as f32));
                for end in edge {
                    assert!(
                        across.iter().any(|c| c.position == end),
                        "triangle {t}: {end:?} is not on the triangle across corner {k}"
                    );
                }
            }
        }
    }
}
