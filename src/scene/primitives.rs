//! Procedural meshes with correct uvs and tangents: quads and boxes built from planar faces, and a
//! smooth sphere.

use glam::{Mat4, Vec3};

use super::{Mesh, Vertex};

/// One planar rectangle: centre, outward normal, the +u and +v directions with half extents,
/// and how many times the texture repeats across it.
struct Face {
    center: Vec3,
    normal: Vec3,
    u_dir: Vec3,
    v_dir: Vec3,
    half: (f32, f32),
    uv_repeat: (f32, f32),
}

fn push_face(face: &Face, vertices: &mut Vec<Vertex>, indices: &mut Vec<u32>) {
    let base = vertices.len() as u32;
    let sign = if face.normal.cross(face.u_dir).dot(face.v_dir) >= 0.0 {
        1.0
    } else {
        -1.0
    };
    for (su, sv) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let p = face.center + face.u_dir * (su * face.half.0) + face.v_dir * (sv * face.half.1);
        vertices.push(Vertex::new(
            p.into(),
            face.normal.into(),
            [
                (su + 1.0) * 0.5 * face.uv_repeat.0,
                (sv + 1.0) * 0.5 * face.uv_repeat.1,
            ],
            [face.u_dir.x, face.u_dir.y, face.u_dir.z, sign],
        ));
    }
    // Counter-clockwise seen from the side the normal points to.
    let ccw = face.u_dir.cross(face.v_dir).dot(face.normal) > 0.0;
    let order: [u32; 6] = if ccw {
        [0, 1, 2, 0, 2, 3]
    } else {
        [0, 2, 1, 0, 3, 2]
    };
    indices.extend(order.iter().map(|k| base + k));
}

/// A `width` x `depth` quad in the XZ plane facing +Y; u runs along +x, v along +z, and the
/// texture repeats `uv_repeat` times across it.
pub fn quad_mesh(name: &str, width: f32, depth: f32, uv_repeat: f32, material: usize) -> Mesh {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let face = Face {
        center: Vec3::ZERO,
        normal: Vec3::Y,
        u_dir: Vec3::X,
        v_dir: Vec3::Z,
        half: (width * 0.5, depth * 0.5),
        uv_repeat: (uv_repeat, uv_repeat),
    };
    push_face(&face, &mut vertices, &mut indices);
    Mesh {
        name: name.into(),
        vertices,
        indices,
        material,
        transform: Mat4::IDENTITY,
    }
}

/// An axis-aligned box centred at the origin with half extents `half`; each face maps the whole
/// texture once per world unit.
pub fn box_mesh(name: &str, half: Vec3, material: usize) -> Mesh {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let axes = [
        (Vec3::X, Vec3::Z, Vec3::Y, half.z, half.y, half.x),
        (Vec3::Y, Vec3::X, Vec3::Z, half.x, half.z, half.y),
        (Vec3::Z, Vec3::X, Vec3::Y, half.x, half.y, half.z),
    ];
    for (n, u, v, hu, hv, hn) in axes {
        for s in [1.0f32, -1.0] {
            let face = Face {
                center: n * (s * hn),
                normal: n * s,
                u_dir: u * s,
                v_dir: v,
                half: (hu, hv),
                uv_repeat: (2.0 * hu, 2.0 * hv),
            };
            push_face(&face, &mut vertices, &mut indices);
        }
    }
    Mesh {
        name: name.into(),
        vertices,
        indices,
        material,
        transform: Mat4::IDENTITY,
    }
}

/// A sphere of `radius` about the origin with smooth (per-vertex) normals: `rings` bands from
/// pole to pole and `segments` around y; u runs once around, v from the south pole up. The seam
/// and the poles repeat their vertices, as exporters write them.
pub fn sphere_mesh(name: &str, radius: f32, rings: u32, segments: u32, material: usize) -> Mesh {
    let mut vertices = Vec::new();
    for i in 0..=rings {
        let v = i as f32 / rings as f32;
        let (sin_lat, cos_lat) = match i {
            // Exactly at the poles, so that a pole's repeats are one point, as the seam's are.
            0 => (-1.0, 0.0),
            _ if i == rings => (1.0, 0.0),
            _ => (std::f32::consts::PI * (v - 0.5)).sin_cos(),
        };
        for j in 0..=segments {
            let u = j as f32 / segments as f32;
            let (sin_lon, cos_lon) = turn(j, segments).sin_cos();
            let n = Vec3::new(cos_lat * cos_lon, sin_lat, -cos_lat * sin_lon);
            let tangent = Vec3::new(-sin_lon, 0.0, -cos_lon);
            vertices.push(Vertex::new(
                (n * radius).into(),
                n.into(),
                [u, v],
                [tangent.x, tangent.y, tangent.z, 1.0],
            ));
        }
    }
    grid_mesh(name, vertices, rings, segments, material)
}

/// An open cylinder (no caps) about the y axis, or a curved wall when `arc` is less than a turn:
/// `radius`, `height` centred on the origin, `segments` steps over `arc` radians (u from 0 to
/// 1 along them) and `rows` up (v from 0 at the bottom to 1), smooth normals pointing out.
pub fn cylinder_mesh(
    name: &str,
    radius: f32,
    height: f32,
    arc: f32,
    segments: u32,
    rows: u32,
    material: usize,
) -> Mesh {
    let mut vertices = Vec::new();
    for i in 0..=rows {
        let v = i as f32 / rows as f32;
        for j in 0..=segments {
            let u = j as f32 / segments as f32;
            let angle = if arc >= std::f32::consts::TAU {
                turn(j, segments)
            } else {
                arc * u
            };
            let (sin_a, cos_a) = angle.sin_cos();
            let n = Vec3::new(cos_a, 0.0, -sin_a);
            let tangent = Vec3::new(-sin_a, 0.0, -cos_a);
            vertices.push(Vertex::new(
                (n * radius + Vec3::Y * (height * (v - 0.5))).into(),
                n.into(),
                [u, v],
                [tangent.x, tangent.y, tangent.z, 1.0],
            ));
        }
    }
    grid_mesh(name, vertices, rows, segments, material)
}

/// A torus about the y axis with smooth normals: the tube's centre circle has radius `major`,
/// the tube radius `minor`; `rings` steps around the axis (u once around, as the sphere's) and
/// `segments` around the tube (v once around, starting at the outer equator and rising).
pub fn torus_mesh(
    name: &str,
    major: f32,
    minor: f32,
    rings: u32,
    segments: u32,
    material: usize,
) -> Mesh {
    let mut vertices = Vec::new();
    for i in 0..=segments {
        let v = i as f32 / segments as f32;
        let (sin_tube, cos_tube) = turn(i, segments).sin_cos();
        for j in 0..=rings {
            let u = j as f32 / rings as f32;
            let (sin_around, cos_around) = turn(j, rings).sin_cos();
            let n = Vec3::new(cos_tube * cos_around, sin_tube, -cos_tube * sin_around);
            let centre = Vec3::new(cos_around, 0.0, -sin_around) * major;
            let tangent = Vec3::new(-sin_around, 0.0, -cos_around);
            let rise = Vec3::new(-sin_tube * cos_around, cos_tube, sin_tube * sin_around);
            let sign = if n.cross(tangent).dot(rise) < 0.0 {
                -1.0
            } else {
                1.0
            };
            vertices.push(Vertex::new(
                (centre + n * minor).into(),
                n.into(),
                [u, v],
                [tangent.x, tangent.y, tangent.z, sign],
            ));
        }
    }
    grid_mesh(name, vertices, segments, rings, material)
}

/// The angle of step `k` of `steps` once around: the last step is the first again, bit for bit,
/// so a seam's repeated vertices are one point (sin of a float 2 pi is not 0).
fn turn(k: u32, steps: u32) -> f32 {
    std::f32::consts::TAU * (k % steps) as f32 / steps as f32
}

/// A mesh over a grid of vertices, `rows + 1` rows of `cols + 1`, each cell two triangles
/// wound counter-clockwise when +u runs along a row and +v up the rows around the normal.
fn grid_mesh(name: &str, vertices: Vec<Vertex>, rows: u32, cols: u32, material: usize) -> Mesh {
    let row = cols + 1;
    let mut indices = Vec::new();
    for i in 0..rows {
        for j in 0..cols {
            let (a, b) = (i * row + j, i * row + j + 1);
            let (c, d) = (a + row, b + row);
            indices.extend([a, b, d, a, d, c]);
        }
    }
    Mesh {
        name: name.into(),
        vertices,
        indices,
        material,
        transform: Mat4::IDENTITY,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::f32::consts::TAU;

    fn check_winding_and_tangents(mesh: &Mesh) {
        for tri in mesh.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.vertices[tri[k] as usize]);
            let (pa, pb, pc) = (
                Vec3::from(a.position),
                Vec3::from(b.position),
                Vec3::from(c.position),
            );
            let geometric = (pb - pa).cross(pc - pa);
            assert!(
                geometric.dot(Vec3::from(a.normal)) > 0.0,
                "{}: triangle winds CCW around its normal",
                mesh.name
            );
            // The tangent frame must agree with the uv gradient: +u along tangent, +v along bitangent.
            let (ua, ub, uc) = (a.uv, b.uv, c.uv);
            let (e1, e2) = (pb - pa, pc - pa);
            let (du1, dv1, du2, dv2) = (ub[0] - ua[0], ub[1] - ua[1], uc[0] - ua[0], uc[1] - ua[1]);
            let det = du1 * dv2 - du2 * dv1;
            let dpdu = (e1 * dv2 - e2 * dv1) / det;
            let dpdv = (e2 * du1 - e1 * du2) / det;
            let t = Vec3::new(a.tangent[0], a.tangent[1], a.tangent[2]);
            let bitangent = Vec3::from(a.normal).cross(t) * a.tangent[3];
            assert!(
                dpdu.normalize().dot(t) > 0.99,
                "{}: tangent follows +u",
                mesh.name
            );
            assert!(
                dpdv.normalize().dot(bitangent) > 0.99,
                "{}: bitangent follows +v",
                mesh.name
            );
        }
    }

    #[test]
    fn the_cylinder_and_its_wall_wind_outward_with_their_tangents_along_u() {
        check_winding_and_tangents(&cylinder_mesh("tube", 1.0, 2.0, TAU, 96, 4, 0));
        check_winding_and_tangents(&cylinder_mesh("wall", 2.0, 1.0, 1.5, 48, 2, 0));
    }

    #[test]
    fn the_torus_winds_outward_with_its_tangents_along_u() {
        // Fine enough that a triangle's edges follow its corners' tangent frame within 0.99.
        let torus = torus_mesh("torus", 1.0, 0.35, 96, 64, 0);
        assert_eq!(torus.vertices.len(), 65 * 97);
        check_winding_and_tangents(&torus);
    }

    #[test]
    fn quad_and_box_are_consistent() {
        check_winding_and_tangents(&quad_mesh("quad", 2.0, 1.0, 3.0, 0));
        let b = box_mesh("box", Vec3::new(1.0, 0.5, 0.25), 0);
        assert_eq!(b.vertices.len(), 24);
        assert_eq!(b.indices.len(), 36);
        check_winding_and_tangents(&b);
    }

    #[test]
    fn the_sphere_winds_outward_with_its_tangents_along_u() {
        let sphere = sphere_mesh("sphere", 2.0, 8, 16, 0);
        assert_eq!(sphere.vertices.len(), 9 * 17);
        let mut checked = 0;
        for tri in sphere.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| sphere.vertices[tri[k] as usize]);
            let [pa, pb, pc] = [a, b, c].map(|v| Vec3::from(v.position));
            for v in [a, b, c] {
                assert!((Vec3::from(v.position).length() - 2.0).abs() < 1e-5);
                let t = Vec3::new(v.tangent[0], v.tangent[1], v.tangent[2]);
                assert!(t.dot(Vec3::from(v.normal)).abs() < 1e-5);
            }
            let geometric = (pb - pa).cross(pc - pa);
            // The poles' fans hold one zero-area triangle per quad.
            if geometric.length() < 1e-6 {
                continue;
            }
            assert!(
                geometric.dot(Vec3::from(a.normal)) > 0.0,
                "{tri:?} winds inward"
            );
            if (b.uv[1] - a.uv[1]).abs() < 1e-6 {
                let t = Vec3::new(a.tangent[0], a.tangent[1], a.tangent[2]);
                assert!((pb - pa).normalize().dot(t) > 0.9, "+u follows the tangent");
            }
            checked += 1;
        }
        assert_eq!(checked, 8 * 16 * 2 - 2 * 16);
    }
}
