//! Geometry shared by the layers above it: the vertex the mesh shader reads and indexed meshes of
//! those vertices. [`crate::terrain`] builds its ground meshes from these and [`crate::scene`]
//! draws them (re-exported as `relief::scene::{Mesh, Vertex}`), so neither depends on the other.
//! Plain data, no Vulkan.

mod mesh;

pub use mesh::{Mesh, Vertex};
