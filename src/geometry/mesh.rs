//! The vertex layout the mesh shader reads and the indexed meshes made of it.

use glam::Mat4;

/// One vertex as the mesh shader reads it (locations 0..=5). Mirrors `mesh.vert`.
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
