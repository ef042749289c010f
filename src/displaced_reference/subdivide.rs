//! Uniform subdivision: every triangle split into four at its edges' midpoints, each midpoint
//! shared by the two triangles of its edge so the mesh stays connected. Positions, uvs, colours
//! and tangents are interpolated linearly and the normal renormalized, so the subdivided mesh is
//! the same polyhedron with the same interpolated attributes the rasteriser gives the original:
//! what relief traces under, sampled finer.

use std::collections::HashMap;

use glam::{Vec2, Vec3, Vec4};

use crate::geometry::{Mesh, Vertex};
use crate::scene::HeightUv;

/// `mesh` split `levels` times (four times the triangles each time).
pub fn subdivide(mesh: &Mesh, levels: u32) -> Mesh {
    let mut vertices = mesh.vertices.clone();
    let mut indices = mesh.indices.clone();
    for _ in 0..levels {
        indices = split_once(&mut vertices, &indices);
    }
    Mesh {
        vertices,
        indices,
        ..mesh.clone()
    }
}

/// Subdivision levels that bring `mesh`'s longest edge, measured in texels of a `size` map read
/// through `uv`, to at most `texels_per_edge`; with the longest edge before, in texels.
pub fn levels_for(mesh: &Mesh, uv: &HeightUv, size: [u32; 2], texels_per_edge: f64) -> (u32, f64) {
    let texels = Vec2::new(size[0] as f32, size[1] as f32);
    let longest = mesh
        .indices
        .chunks_exact(3)
        .flat_map(|t| [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])])
        .map(|(a, b)| {
            let (a, b) = (&mesh.vertices[a as usize], &mesh.vertices[b as usize]);
            f64::from(((uv.of(a) - uv.of(b)) * texels).length())
        })
        .fold(0.0, f64::max);
    let levels = if longest <= texels_per_edge {
        0
    } else {
        (longest / texels_per_edge).log2().ceil() as u32
    };
    (levels, longest)
}

fn split_once(vertices: &mut Vec<Vertex>, indices: &[u32]) -> Vec<u32> {
    let mut midpoints: HashMap<(u32, u32), u32> = HashMap::new();
    let mut midpoint = |a: u32, b: u32, vertices: &mut Vec<Vertex>| {
        *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
            vertices.push(between(&vertices[a as usize], &vertices[b as usize]));
            (vertices.len() - 1) as u32
        })
    };
    let mut out = Vec::with_capacity(indices.len() * 4);
    for t in indices.chunks_exact(3) {
        let (a, b, c) = (t[0], t[1], t[2]);
        let ab = midpoint(a, b, vertices);
        let bc = midpoint(b, c, vertices);
        let ca = midpoint(c, a, vertices);
        out.extend([a, ab, ca, ab, b, bc, ca, bc, c, ab, bc, ca]);
    }
    out
}

/// The vertex halfway along the edge from `a` to `b`.
fn between(a: &Vertex, b: &Vertex) -> Vertex {
    let mid3 = |x: [f32; 3], y: [f32; 3]| ((Vec3::from(x) + Vec3::from(y)) * 0.5).to_array();
    let mid2 = |x: [f32; 2], y: [f32; 2]| ((Vec2::from(x) + Vec2::from(y)) * 0.5).to_array();
    let normal = (Vec3::from(a.normal) + Vec3::from(b.normal)).normalize_or(Vec3::from(a.normal));
    let tangent = (Vec3::from_slice(&a.tangent[..3]) + Vec3::from_slice(&b.tangent[..3]))
        .normalize_or(Vec3::from_slice(&a.tangent[..3]));
    Vertex {
        position: mid3(a.position, b.position),
        normal: normal.to_array(),
        uv: mid2(a.uv, b.uv),
        uv1: mid2(a.uv1, b.uv1),
        tangent: tangent.extend(a.tangent[3]).to_array(),
        color: ((Vec4::from(a.color) + Vec4::from(b.color)) * 0.5).to_array(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::quad_mesh;

    #[test]
    fn each_level_quadruples_the_triangles_and_shares_midpoints() {
        let quad = quad_mesh("q", 1.0, 1.0, 1.0, 0);
        let once = subdivide(&quad, 1);
        assert_eq!(once.indices.len(), quad.indices.len() * 4);
        // Two triangles share the diagonal: 4 corners + 5 midpoints.
        assert_eq!(once.vertices.len(), 9);
        let twice = subdivide(&quad, 2);
        assert_eq!(twice.indices.len(), quad.indices.len() * 16);
        assert_eq!(twice.vertices.len(), 25);
    }

    #[test]
    fn levels_bring_the_longest_edge_under_the_limit() {
        let quad = quad_mesh("q", 1.0, 1.0, 1.0, 0);
        // The quad spans the whole map: its diagonal crosses sqrt(2) * 64 texels.
        let (levels, longest) = levels_for(&quad, &HeightUv::IDENTITY, [64, 64], 1.0);
        assert!((longest - 64.0 * 2f64.sqrt()).abs() < 1e-3, "{longest}");
        assert_eq!(levels, 7);
        assert_eq!(levels_for(&quad, &HeightUv::IDENTITY, [64, 64], 100.0).0, 0);
    }
}
