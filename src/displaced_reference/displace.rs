//! Moving a (subdivided) mesh's vertices onto its relief: each vertex goes down its interpolated
//! normal by the depth the height map gives at its height uv, `s * (1 - h)` in height-uv units,
//! times the world length of one depth unit there ([`crate::geometry::depth_length`], averaged
//! over the vertex's triangles by area).
//!
//! Shading takes the normal relief's surface pass computes at a hit: the interpolated normal
//! tilted by the height map's slope (central differences one texel apart on the bilinear
//! surface, carried into world space through the same frame). The displaced facets' own normals
//! would show the coarse mesh's flat faces, which relief's smooth normals never show; with the
//! same normal model the two images differ only where the geometry does: which point a pixel
//! sees, and whether it sees the surface at all.
//!
//! Vertices a mesh repeats at one point with one normal (a uv seam, a pole) are moved as one, so
//! the displaced surface does not tear there; vertices that repeat a point with different normals
//! (a hard edge) move apart, as the relief drawn on each face does.

use std::collections::HashMap;

use glam::{DMat2, DVec2, Mat3, Vec2, Vec3};

use crate::geometry::{depth_length, uv_per_uv, world_per_uv, Mesh, Vertex};
use crate::heightfield::reference::{surface_depth, SurfaceModel};
use crate::scene::{HeightLookup, HeightUv};

/// A vertex's identity across repeats: its original position and normal, bit for bit.
type Weld = [u32; 6];

fn weld(v: &Vertex) -> Weld {
    let [x, y, z] = v.position.map(f32::to_bits);
    let [a, b, c] = v.normal.map(f32::to_bits);
    [x, y, z, a, b, c]
}

/// The texture frame at a vertex, area-averaged over its triangles: world lengths of one uv0
/// unit along u and v, the map from uv0 to height uv, and the world length of one depth unit.
#[derive(Debug, Clone, Copy)]
struct Frame {
    scale: DVec2,
    to_height: DMat2,
    depth_len: f64,
}

impl Frame {
    // Not `Default`: glam's default matrix is the identity, and these are sums.
    const ZERO: Frame = Frame {
        scale: DVec2::ZERO,
        to_height: DMat2::ZERO,
        depth_len: 0.0,
    };
}

/// `mesh` displaced by `heights` at `depth_scale`, in world space (its transform applied, the
/// result's transform the identity).
pub fn displace(mesh: &Mesh, heights: &HeightLookup, depth_scale: f32) -> Mesh {
    let linear = Mat3::from_mat4(mesh.transform);
    let normal_matrix = linear.inverse().transpose();
    let world: Vec<Vec3> = mesh
        .vertices
        .iter()
        .map(|v| mesh.transform.transform_point3(Vec3::from(v.position)))
        .collect();
    let welds: Vec<Weld> = mesh.vertices.iter().map(weld).collect();
    let frames = frames(mesh, &heights.uv, &world, &welds);
    let s = f64::from(depth_scale);
    let vertices = mesh
        .vertices
        .iter()
        .zip(&world)
        .zip(&welds)
        .map(|((v, &p), w)| {
            let n = (normal_matrix * Vec3::from(v.normal)).normalize_or_zero();
            let tangent = linear * Vec3::from_slice(&v.tangent[..3]);
            let huv = heights.uv.of(v).as_dvec2();
            let Some(f) = frames.get(w) else {
                // Only degenerate triangles around it: no frame, left on its polygon.
                return Vertex {
                    position: p.to_array(),
                    normal: n.to_array(),
                    tangent: tangent.extend(v.tangent[3]).to_array(),
                    ..*v
                };
            };
            let depth = surface_depth(
                &heights.heights,
                huv.x,
                huv.y,
                s,
                SurfaceModel::Bilinear,
                heights.address,
            );
            let moved = p.as_dvec3() - n.as_dvec3() * (depth * f.depth_len);
            let (normal, tangent) = relief_normal(n, tangent, v.tangent[3], f, s, heights, huv);
            Vertex {
                position: moved.as_vec3().to_array(),
                normal: normal.to_array(),
                tangent: tangent.extend(v.tangent[3]).to_array(),
                ..*v
            }
        })
        .collect();
    Mesh {
        name: format!("{} (displaced)", mesh.name),
        vertices,
        indices: mesh.indices.clone(),
        material: mesh.material,
        transform: glam::Mat4::IDENTITY,
    }
}

/// Per vertex: the index of the first vertex it repeats (the same for every repeat the displaced
/// mesh moves as one), and the world length of one depth unit there, `None` where only degenerate
/// triangles meet. What a shell around the mesh needs to extrude its triangles exactly as
/// [`displace`] moves the vertices.
pub(crate) fn welded_depth_lengths(mesh: &Mesh, uv: &HeightUv) -> Vec<(u32, Option<f64>)> {
    let world: Vec<Vec3> = mesh
        .vertices
        .iter()
        .map(|v| mesh.transform.transform_point3(Vec3::from(v.position)))
        .collect();
    let welds: Vec<Weld> = mesh.vertices.iter().map(weld).collect();
    let frames = frames(mesh, uv, &world, &welds);
    let mut first: HashMap<Weld, u32> = HashMap::new();
    welds
        .iter()
        .enumerate()
        .map(|(k, w)| {
            let id = *first.entry(*w).or_insert(k as u32);
            (id, frames.get(w).map(|f| f.depth_len))
        })
        .collect()
}

/// The surface pass's shading normal at height uv `huv` on a surface of normal `n` and tangent
/// `tangent` (bitangent sign `sign`), and the tangent turned into its plane.
fn relief_normal(
    n: Vec3,
    tangent: Vec3,
    sign: f32,
    f: &Frame,
    depth_scale: f64,
    heights: &HeightLookup,
    huv: DVec2,
) -> (Vec3, Vec3) {
    let n = n.as_dvec3();
    let t = (tangent.as_dvec3() - n * n.dot(tangent.as_dvec3())).normalize_or_zero();
    let b = n.cross(t) * if sign < 0.0 { -1.0 } else { 1.0 };
    let g0 = f.to_height.transpose() * (height_gradient(heights, huv) * depth_scale);
    let normal = (n - t * (f.depth_len * g0.x / f.scale.x) - b * (f.depth_len * g0.y / f.scale.y))
        .normalize_or(n);
    let turned = (t - normal * normal.dot(t)).normalize_or(t);
    (normal.as_vec3(), turned.as_vec3())
}

/// The height's slope per height-uv unit, by central differences one texel apart on the bilinear
/// surface (as `height_gradient` in the shaders).
fn height_gradient(heights: &HeightLookup, huv: DVec2) -> DVec2 {
    let hf = &heights.heights;
    let texel = DVec2::new(1.0 / f64::from(hf.width()), 1.0 / f64::from(hf.height()));
    let h = |d: DVec2| {
        let q = huv + d;
        1.0 - surface_depth(hf, q.x, q.y, 1.0, SurfaceModel::Bilinear, heights.address)
    };
    let hx = h(DVec2::new(texel.x, 0.0)) - h(DVec2::new(-texel.x, 0.0));
    let hy = h(DVec2::new(0.0, texel.y)) - h(DVec2::new(0.0, -texel.y));
    DVec2::new(hx, hy) / (2.0 * texel)
}

/// Each welded vertex's frame, the area-weighted mean over its triangles with a frame.
fn frames(mesh: &Mesh, uv: &HeightUv, world: &[Vec3], welds: &[Weld]) -> HashMap<Weld, Frame> {
    let mut sums: HashMap<Weld, (Frame, f64)> = HashMap::new();
    for t in mesh.indices.chunks_exact(3) {
        let [a, b, c] = [t[0], t[1], t[2]].map(|k| k as usize);
        let (e1, e2) = (
            (world[b] - world[a]).as_dvec3(),
            (world[c] - world[a]).as_dvec3(),
        );
        let area = e1.cross(e2).length() * 0.5;
        let huv = [a, b, c].map(|k| uv.of(&mesh.vertices[k]));
        let uv0 = [a, b, c].map(|k| Vec2::from(mesh.vertices[k].uv));
        let (Some(per_uv0), Some(to_height), Some(depth_len)) = (
            world_per_uv(e1, e2, uv0),
            uv_per_uv(huv, uv0),
            depth_length(e1, e2, huv, uv0),
        ) else {
            continue;
        };
        let scale = DVec2::new(per_uv0[0].length(), per_uv0[1].length());
        for k in [a, b, c] {
            let (sum, weight) = sums.entry(welds[k]).or_insert((Frame::ZERO, 0.0));
            sum.scale += scale * area;
            sum.to_height += to_height * area;
            sum.depth_len += depth_len * area;
            *weight += area;
        }
    }
    sums.into_iter()
        .filter(|(_, (_, weight))| *weight > 0.0)
        .map(|(w, (sum, weight))| {
            let frame = Frame {
                scale: sum.scale / weight,
                to_height: sum.to_height * (1.0 / weight),
                depth_len: sum.depth_len / weight,
            };
            (w, frame)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use std::sync::Arc;

    use super::*;
    use crate::heightfield::{Address, Heightfield};
    use crate::scene::{quad_mesh, HeightUv};

    fn lookup(heights: Heightfield) -> HeightLookup {
        HeightLookup {
            heights: Arc::new(heights),
            address: Address::Repeat,
            uv: HeightUv::IDENTITY,
        }
    }

    #[test]
    fn a_level_field_sinks_a_stretched_quad_by_its_depth_in_world_units() {
        // 4 x 1 world units, the map once across: one depth unit is sqrt(4 * 1) = 2 long.
        let mut quad = quad_mesh("q", 4.0, 1.0, 1.0, 0);
        quad.transform = glam::Mat4::from_translation(Vec3::new(0.0, 3.0, 0.0));
        let flat = Heightfield::new(2, 2, vec![0.25; 4]).expect("a field");
        let out = displace(&quad, &lookup(flat), 0.1);
        for v in &out.vertices {
            let expected = 3.0 - 0.1 * 0.75 * 2.0;
            assert!((v.position[1] - expected).abs() < 1e-5, "{:?}", v.position);
            assert!((Vec3::from(v.normal) - Vec3::Y).length() < 1e-5);
        }
        assert_eq!(out.transform, glam::Mat4::IDENTITY);
    }

    #[test]
    fn the_top_of_the_field_stays_on_the_polygon() {
        let quad = quad_mesh("q", 1.0, 1.0, 1.0, 0);
        let top = Heightfield::new(1, 1, vec![1.0]).expect("a field");
        let out = displace(&quad, &lookup(top), 0.5);
        for (a, b) in quad.vertices.iter().zip(&out.vertices) {
            assert_eq!(a.position, b.position);
        }
    }
}
