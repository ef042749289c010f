//! Tangents for meshes that come without them: MikkTSpace, the tangent space glTF normal maps
//! are baked against (the spec asks for it when TANGENT is absent).

use std::collections::HashMap;

use glam::Vec3;

use super::Vertex;

/// Replaces the tangents of `vertices` with MikkTSpace's from positions, normals and uv set 0;
/// without uvs every tangent is just some unit vector perpendicular to the normal. Vertices
/// MikkTSpace splits (a mirrored seam through a shared vertex) are duplicated, so `indices`
/// may change.
pub(super) fn generate(vertices: &mut Vec<Vertex>, indices: &mut Vec<u32>, has_uv: bool) {
    for v in vertices.iter_mut() {
        v.tangent = fallback(Vec3::from(v.normal));
    }
    if !has_uv || indices.is_empty() {
        return;
    }
    // MikkTSpace works per face corner; unweld, generate, then weld identical corners again.
    let mut corners = Corners {
        vertices: indices.iter().map(|&i| vertices[i as usize]).collect(),
    };
    if welding_grid_ok(&corners.vertices) {
        mikktspace::generate_tangents(&mut corners);
    }
    let mut welded: Vec<Vertex> = Vec::with_capacity(vertices.len());
    let mut seen: HashMap<[u32; 18], u32> = HashMap::with_capacity(vertices.len());
    let mut new_indices = Vec::with_capacity(indices.len());
    for mut v in corners.vertices {
        let t = Vec3::from_slice(&v.tangent[..3]);
        if !t.is_finite() || t.length_squared() < 1e-12 || v.tangent[3].abs() != 1.0 {
            v.tangent = fallback(Vec3::from(v.normal));
        }
        let key: [u32; 18] = bytemuck::cast(v);
        let index = *seen.entry(key).or_insert_with(|| {
            welded.push(v);
            (welded.len() - 1) as u32
        });
        new_indices.push(index);
    }
    *vertices = welded;
    *indices = new_indices;
}

/// mikktspace 0.3 (a mechanical C port) buckets vertices into a grid along the axis of largest
/// extent and indexes one past its table when that extent is zero or overflows to infinity
/// (every corner at one point, or coordinates near f32::MAX): it panics. Such meshes are
/// degenerate anyway and keep the fallback tangents.
fn welding_grid_ok(vertices: &[Vertex]) -> bool {
    let (lo, hi) = vertices
        .iter()
        .fold((Vec3::INFINITY, Vec3::NEG_INFINITY), |(lo, hi), v| {
            let p = Vec3::from(v.position);
            (lo.min(p), hi.max(p))
        });
    let extent = (hi - lo).max_element();
    extent.is_finite() && extent > 0.0
}

/// A unit tangent perpendicular to `normal` (any, when the normal is degenerate), w = +1.
pub(super) fn fallback(normal: Vec3) -> [f32; 4] {
    let n = normal.try_normalize().unwrap_or(Vec3::Z);
    let t = n.any_orthonormal_vector();
    [t.x, t.y, t.z, 1.0]
}

struct Corners {
    vertices: Vec<Vertex>,
}

impl mikktspace::Geometry for Corners {
    fn num_faces(&self) -> usize {
        self.vertices.len() / 3
    }
    fn num_vertices_of_face(&self, _face: usize) -> usize {
        3
    }
    fn position(&self, face: usize, vert: usize) -> [f32; 3] {
        self.vertices[face * 3 + vert].position
    }
    fn normal(&self, face: usize, vert: usize) -> [f32; 3] {
        self.vertices[face * 3 + vert].normal
    }
    fn tex_coord(&self, face: usize, vert: usize) -> [f32; 2] {
        self.vertices[face * 3 + vert].uv
    }
    fn set_tangent_encoded(&mut self, tangent: [f32; 4], face: usize, vert: usize) {
        let t = Vec3::from_slice(&tangent[..3]).normalize_or_zero();
        let w = if tangent[3] < 0.0 { -1.0 } else { 1.0 };
        self.vertices[face * 3 + vert].tangent = [t.x, t.y, t.z, w];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(flip_v: bool) -> (Vec<Vertex>, Vec<u32>) {
        let v = |x: f32, y: f32| {
            let uv = [x, if flip_v { 1.0 - y } else { y }];
            Vertex::new([x, y, 0.0], [0.0, 0.0, 1.0], uv, [0.0; 4])
        };
        (
            vec![v(0.0, 0.0), v(1.0, 0.0), v(1.0, 1.0), v(0.0, 1.0)],
            vec![0, 1, 2, 0, 2, 3],
        )
    }

    #[test]
    fn quad_tangent_follows_u() {
        let (mut verts, mut idx) = quad(false);
        generate(&mut verts, &mut idx, true);
        assert_eq!(verts.len(), 4, "a flat quad welds back to four vertices");
        assert_eq!(idx.len(), 6);
        for v in &verts {
            let t = Vec3::from_slice(&v.tangent[..3]);
            assert!((t - Vec3::X).length() < 1e-5, "{:?}", v.tangent);
            assert_eq!(v.tangent[3], 1.0);
        }
    }

    #[test]
    fn flipped_v_gives_negative_bitangent_sign() {
        let (mut verts, mut idx) = quad(true);
        generate(&mut verts, &mut idx, true);
        for v in &verts {
            let t = Vec3::from_slice(&v.tangent[..3]);
            assert!((t - Vec3::X).length() < 1e-5, "{:?}", v.tangent);
            assert_eq!(v.tangent[3], -1.0);
        }
    }

    #[test]
    fn no_uvs_or_degenerate_faces_still_give_unit_tangents() {
        let (mut verts, mut idx) = quad(false);
        generate(&mut verts, &mut idx, false);
        let p = Vertex::new([1.0; 3], [0.0, 1.0, 0.0], [0.5; 2], [0.0; 4]);
        let mut degenerate = vec![p, p, p];
        let mut di = vec![0, 1, 2];
        generate(&mut degenerate, &mut di, true);
        for v in verts.iter().chain(&degenerate) {
            let t = Vec3::from_slice(&v.tangent[..3]);
            let n = Vec3::from(v.normal);
            assert!((t.length() - 1.0).abs() < 1e-5 && t.dot(n).abs() < 1e-5);
            assert_eq!(v.tangent[3].abs(), 1.0);
        }
    }
}
