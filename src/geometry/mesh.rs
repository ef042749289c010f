//! The vertex layout the mesh shader reads and the indexed meshes made of it.

use glam::Mat4;

/// One vertex as the mesh shader reads it: the mesh pass takes each attribute's offset from this
/// struct and its location from `LOCATION_*` in the shader interface, which `mesh.vert` reads.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    /// Object-space position.
    pub position: [f32; 3],
    /// Object-space unit normal.
    pub normal: [f32; 3],
    /// Texture coordinate set 0.
    pub uv: [f32; 2],
    /// Texture coordinate set 1 (a copy of set 0 when the mesh has none).
    pub uv1: [f32; 2],
    /// xyz: tangent along +u of set 0; w: sign of the bitangent (+v) relative to normal x tangent.
    pub tangent: [f32; 4],
    /// Linear RGBA vertex colour (white when the mesh has none).
    pub color: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<Vertex>() == 72);

impl Vertex {
    /// A vertex with no second uv set (set 1 copies set 0) and a white colour.
    pub fn new(position: [f32; 3], normal: [f32; 3], uv: [f32; 2], tangent: [f32; 4]) -> Vertex {
        Vertex {
            position,
            normal,
            uv,
            uv1: uv,
            tangent,
            color: [1.0; 4],
        }
    }
}

/// Indexed triangles in object space, with the material they use and their placement.
#[derive(Debug, Clone)]
pub struct Mesh {
    /// Where it came from, for messages: the glTF mesh's name, `"ground tile 0,1"`, ...
    pub name: String,
    /// The vertices `indices` point into.
    pub vertices: Vec<Vertex>,
    /// Counter-clockwise front faces in world space (a mirroring transform is already
    /// compensated by reversed winding).
    pub indices: Vec<u32>,
    /// Index of the material it is drawn with, in the scene's materials.
    pub material: usize,
    /// Object to world.
    pub transform: Mat4,
}

impl Mesh {
    /// The world length of one unit of relief depth over the whole mesh, with the height map on
    /// uv set 0: [`super::depth_length`] averaged over its triangles by world area (the
    /// reference and the surface pass use each point's own). `None` when no triangle has
    /// usable uvs.
    pub fn mean_depth_length(&self) -> Option<f64> {
        let world: Vec<glam::DVec3> = self
            .vertices
            .iter()
            .map(|v| {
                self.transform
                    .transform_point3(v.position.into())
                    .as_dvec3()
            })
            .collect();
        let (mut sum, mut area_sum) = (0.0, 0.0);
        for t in self.indices.chunks_exact(3) {
            let [a, b, c] = [t[0], t[1], t[2]].map(|k| k as usize);
            let (e1, e2) = (world[b] - world[a], world[c] - world[a]);
            let uv = [a, b, c].map(|k| glam::Vec2::from(self.vertices[k].uv));
            let area = e1.cross(e2).length() * 0.5;
            if let Some(len) = super::depth_length(e1, e2, uv, uv) {
                sum += len * area;
                area_sum += area;
            }
        }
        (area_sum > 0.0).then(|| sum / area_sum)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn quad(width: f32, height: f32, uv_scale: f32) -> Mesh {
        let n = [0.0, 0.0, 1.0];
        let t = [1.0, 0.0, 0.0, 1.0];
        let corner = |x: f32, y: f32| {
            Vertex::new(
                [x * width, y * height, 0.0],
                n,
                [x * uv_scale, y * uv_scale],
                t,
            )
        };
        Mesh {
            name: "quad".into(),
            vertices: vec![
                corner(0.0, 0.0),
                corner(1.0, 0.0),
                corner(1.0, 1.0),
                corner(0.0, 1.0),
            ],
            indices: vec![0, 1, 2, 0, 2, 3],
            material: 0,
            transform: Mat4::from_scale(glam::Vec3::splat(3.0)),
        }
    }

    #[test]
    fn a_depth_unit_is_the_geometric_mean_of_the_world_uv_lengths() {
        // 3 x (2 by 1) world units under uvs 0..2: one uv unit spans 3 along u and 1.5 along v.
        let len = quad(2.0, 1.0, 2.0).mean_depth_length().expect("has uvs");
        assert!((len - (3.0f64 * 1.5).sqrt()).abs() < 1e-6, "{len}");
        let mut flat_uvs = quad(2.0, 1.0, 2.0);
        flat_uvs.vertices.iter_mut().for_each(|v| v.uv = [0.5, 0.5]);
        assert_eq!(flat_uvs.mean_depth_length(), None);
    }
}
