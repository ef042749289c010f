//! Scenes as plain Rust data: meshes with tangents, materials (with optional relief), a camera
//! and lights. No Vulkan types, so scenes are built and tested without a GPU.

mod builtin;
mod camera;
mod gltf_load;
mod primitives;

pub use builtin::{default_heightfield, default_scene, DEFAULT_HEIGHTFIELD};
pub use camera::Camera;
pub use gltf_load::{load_gltf, SceneError};
pub use primitives::{box_mesh, quad_mesh};

use glam::{Mat4, Vec3};

use crate::method::Method;

/// One vertex as the mesh shader reads it (location 0..3). Mirrors `mesh.vert`.
#[repr(C)]
#[derive(Debug, Clone, Copy, PartialEq, bytemuck::Pod, bytemuck::Zeroable)]
pub struct Vertex {
    pub position: [f32; 3],
    pub normal: [f32; 3],
    pub uv: [f32; 2],
    /// xyz: tangent along +u; w: sign of the bitangent (+v) relative to normal x tangent.
    pub tangent: [f32; 4],
}

const _: () = assert!(std::mem::size_of::<Vertex>() == 48);

/// Indexed triangles in object space, with the material they use and their placement.
#[derive(Debug, Clone)]
pub struct Mesh {
    pub name: String,
    pub vertices: Vec<Vertex>,
    pub indices: Vec<u32>,
    pub material: usize,
    pub transform: Mat4,
}

/// How a material is displaced.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Relief {
    /// Depth of height 0 below the polygon, in uv units (DESIGN.md section 2).
    pub depth_scale: f32,
    pub method: Method,
}

/// A surface's look.
#[derive(Debug, Clone, PartialEq)]
pub struct Material {
    pub name: String,
    /// Linear RGBA.
    pub base_color: [f32; 4],
    pub roughness: f32,
    pub metallic: f32,
    /// Relief from the frame's height field, or `None` for a plain surface.
    pub relief: Option<Relief>,
    pub double_sided: bool,
}

impl Default for Material {
    fn default() -> Self {
        Material {
            name: "default".into(),
            base_color: [0.8, 0.8, 0.8, 1.0],
            roughness: 0.6,
            metallic: 0.0,
            relief: None,
            double_sided: false,
        }
    }
}

/// A directional light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Light {
    /// Direction toward the light, world space.
    pub direction: Vec3,
    /// Linear RGB radiance times intensity.
    pub color: Vec3,
}

impl Light {
    /// The light a scene without lights gets: warm, from above and to the side.
    pub fn default_light() -> Light {
        Light {
            direction: Vec3::new(-0.45, 0.8, 0.4).normalize(),
            color: Vec3::new(3.0, 2.85, 2.6),
        }
    }
}

/// Everything a frame draws.
#[derive(Debug, Clone, Default)]
pub struct Scene {
    pub meshes: Vec<Mesh>,
    pub materials: Vec<Material>,
    pub camera: Option<Camera>,
    pub lights: Vec<Light>,
}

impl Scene {
    /// World-space bounds of every vertex, or `None` for an empty scene.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut points = self.meshes.iter().flat_map(|m| {
            m.vertices
                .iter()
                .map(move |v| m.transform.transform_point3(Vec3::from(v.position)))
        });
        let first = points.next()?;
        Some(points.fold((first, first), |(lo, hi), p| (lo.min(p), hi.max(p))))
    }

    /// Whether any material carries relief.
    pub fn has_relief(&self) -> bool {
        self.materials.iter().any(|m| m.relief.is_some())
    }

    /// Gives every material relief with `depth_scale` and `method` (the `--heightmap` path).
    pub fn apply_relief(&mut self, depth_scale: f32, method: Method) {
        for m in &mut self.materials {
            m.relief = Some(Relief {
                depth_scale,
                method,
            });
        }
    }
}
