//! Geometry shared by the layers above it: the vertex the mesh shader reads and indexed meshes of
//! those vertices. [`crate::terrain`] builds its ground meshes from these and [`crate::scene`]
//! draws them (re-exported as `relief::scene::{Mesh, Vertex}`), so neither depends on the other.
//! Plain data, no Vulkan.

mod mesh;
mod uv_frame;

pub use mesh::{Mesh, Vertex};
pub use uv_frame::{depth_length, uv_per_uv, world_per_uv};
