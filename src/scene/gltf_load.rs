//! glTF 2.0 (.gltf with external or embedded buffers, .glb) to a [`Scene`]: the default scene's
//! node tree with transforms, triangle primitives (positions, normals, uv 0, tangents), base
//! colour factors, metallic-roughness factors, the first camera and directional lights.
//! Missing normals and tangents are derived per triangle.

use std::path::{Path, PathBuf};

use glam::{Mat4, Vec3};

use super::camera::Projection;
use super::{Camera, Material, Mesh, Scene, Vertex};

/// Why a scene file could not be used.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    #[error("scene {path:?}: {source}")]
    Gltf { path: PathBuf, source: gltf::Error },
    #[error("scene {path:?}: {what}")]
    Invalid { path: PathBuf, what: String },
}

/// Loads a glTF file and its buffers and images.
/// Which scene and camera of a file to use.
#[derive(Debug, Clone, Copy, Default)]
pub struct SceneOptions {
    pub scene: Option<usize>,
    pub camera: Option<usize>,
}

pub fn load_gltf(path: &Path, _opts: &SceneOptions) -> Result<Scene, SceneError> {
    let (doc, buffers, _images) = gltf::import(path).map_err(|source| SceneError::Gltf {
        path: path.to_owned(),
        source,
    })?;
    let invalid = |what: String| SceneError::Invalid {
        path: path.to_owned(),
        what,
    };
    let mut scene = Scene {
        materials: doc.materials().map(convert_material).collect(),
        ..Scene::default()
    };
    let default_material = scene.materials.len();
    scene.materials.push(Material::default());
    let Some(root) = doc.default_scene().or_else(|| doc.scenes().next()) else {
        return Ok(scene);
    };
    let mut stack: Vec<(gltf::Node, Mat4, usize)> =
        root.nodes().map(|n| (n, Mat4::IDENTITY, 0)).collect();
    while let Some((node, parent, depth)) = stack.pop() {
        if depth > 256 {
            return Err(invalid(
                "node hierarchy deeper than 256 levels (a cycle?)".into(),
            ));
        }
        let world = parent * Mat4::from_cols_array_2d(&node.transform().matrix());
        if let Some(mesh) = node.mesh() {
            for prim in mesh.primitives() {
                let name = mesh.name().unwrap_or("mesh").to_owned();
                let material = prim.material().index().unwrap_or(default_material);
                let m =
                    convert_primitive(&prim, &buffers, name, material, world).map_err(invalid)?;
                scene.meshes.push(m);
            }
        }
        if let (Some(cam), None) = (node.camera(), &scene.camera) {
            scene.camera = Some(convert_camera(&cam, world));
        }
        stack.extend(node.children().map(|c| (c, world, depth + 1)));
    }
    Ok(scene)
}

fn convert_material(m: gltf::Material) -> Material {
    let pbr = m.pbr_metallic_roughness();
    Material {
        name: m.name().unwrap_or("material").to_owned(),
        base_color: pbr.base_color_factor(),
        roughness: pbr.roughness_factor(),
        metallic: pbr.metallic_factor(),
        double_sided: m.double_sided(),
        ..Material::default()
    }
}

fn convert_camera(cam: &gltf::Camera, world: Mat4) -> Camera {
    let view = world.inverse();
    let projection = match cam.projection() {
        gltf::camera::Projection::Perspective(p) => Projection::Perspective {
            yfov: p.yfov(),
            aspect: p.aspect_ratio(),
            znear: p.znear(),
            zfar: p.zfar().unwrap_or(p.znear() * 1e4),
        },
        gltf::camera::Projection::Orthographic(o) => Projection::Orthographic {
            xmag: o.xmag(),
            ymag: o.ymag(),
            znear: o.znear(),
            zfar: o.zfar(),
        },
    };
    Camera { view, projection }
}

fn convert_primitive(
    prim: &gltf::Primitive,
    buffers: &[gltf::buffer::Data],
    name: String,
    material: usize,
    transform: Mat4,
) -> Result<Mesh, String> {
    if prim.mode() != gltf::mesh::Mode::Triangles {
        return Err(format!("mesh {name:?}: only triangle primitives are drawn"));
    }
    let reader = prim.reader(|b| buffers.get(b.index()).map(|d| &d.0[..]));
    let positions: Vec<[f32; 3]> = reader
        .read_positions()
        .ok_or_else(|| format!("mesh {name:?} has no POSITION"))?
        .collect();
    let count = positions.len();
    let indices: Vec<u32> = match reader.read_indices() {
        Some(i) => i.into_u32().collect(),
        None => (0..count as u32).collect(),
    };
    if let Some(bad) = indices.iter().find(|&&i| i as usize >= count) {
        return Err(format!(
            "mesh {name:?}: index {bad} out of range for {count} vertices"
        ));
    }
    let indices: Vec<u32> = indices.chunks_exact(3).flatten().copied().collect();
    let uvs: Vec<[f32; 2]> = reader
        .read_tex_coords(0)
        .map(|t| t.into_f32().collect())
        .unwrap_or_else(|| vec![[0.0, 0.0]; count]);
    let normals: Option<Vec<[f32; 3]>> = reader.read_normals().map(|n| n.collect());
    let tangents: Option<Vec<[f32; 4]>> = reader.read_tangents().map(|t| t.collect());
    let mut vertices: Vec<Vertex> = (0..count)
        .map(|k| {
            Vertex::new(
                positions[k],
                normals
                    .as_ref()
                    .and_then(|n| n.get(k).copied())
                    .unwrap_or([0.0; 3]),
                uvs.get(k).copied().unwrap_or([0.0; 2]),
                tangents
                    .as_ref()
                    .and_then(|t| t.get(k).copied())
                    .unwrap_or([0.0; 4]),
            )
        })
        .collect();
    if normals.is_none() || tangents.is_none() {
        derive_frames(
            &mut vertices,
            &indices,
            normals.is_none(),
            tangents.is_none(),
        );
    }
    Ok(Mesh {
        name,
        vertices,
        indices,
        material,
        transform,
    })
}

/// Accumulates per-triangle normals and uv tangents onto vertices, then normalises.
fn derive_frames(vertices: &mut [Vertex], indices: &[u32], normals: bool, tangents: bool) {
    let mut n_acc = vec![Vec3::ZERO; vertices.len()];
    let mut t_acc = vec![Vec3::ZERO; vertices.len()];
    let mut b_acc = vec![Vec3::ZERO; vertices.len()];
    for tri in indices.chunks_exact(3) {
        let [a, b, c] = [0, 1, 2].map(|k| vertices[tri[k] as usize]);
        let (pa, pb, pc) = (
            Vec3::from(a.position),
            Vec3::from(b.position),
            Vec3::from(c.position),
        );
        let (e1, e2) = (pb - pa, pc - pa);
        let (du1, dv1) = (b.uv[0] - a.uv[0], b.uv[1] - a.uv[1]);
        let (du2, dv2) = (c.uv[0] - a.uv[0], c.uv[1] - a.uv[1]);
        let det = du1 * dv2 - du2 * dv1;
        let r = if det.abs() > 1e-20 { 1.0 / det } else { 0.0 };
        for &i in tri {
            n_acc[i as usize] += e1.cross(e2);
            t_acc[i as usize] += (e1 * dv2 - e2 * dv1) * r;
            b_acc[i as usize] += (e2 * du1 - e1 * du2) * r;
        }
    }
    for (k, v) in vertices.iter_mut().enumerate() {
        if normals {
            v.normal = n_acc[k].normalize_or(Vec3::Y).into();
        }
        if tangents {
            let n = Vec3::from(v.normal);
            let t = (t_acc[k] - n * n.dot(t_acc[k])).normalize_or(n.any_orthonormal_vector());
            let w = if n.cross(t).dot(b_acc[k]) < 0.0 {
                -1.0
            } else {
                1.0
            };
            v.tangent = [t.x, t.y, t.z, w];
        }
    }
}
