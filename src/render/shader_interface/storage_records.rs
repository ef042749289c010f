//! The structs of storage buffers shared by Rust and GLSL (std430): build.rs writes each into
//! "interface.glsl" as a GLSL `struct`.

use super::ShaderLayout;

shader_layout! {
    /// One relief prism as a ray query meets it (`shaders/include/relief_prism.glsl`): the
    /// frame of one relief triangle, 80 bytes.
    #[derive(Debug, PartialEq)]
    record std430 PrismRecord {
        /// Rows of the affine map from a world point to (height u, height v, depth).
        to_local: [[f32; 4]; 3] => "vec4" [3],
        /// Columns of the map from a height-uv offset to the weights of corners 1 and 2 (xy,
        /// zw).
        to_bary: [f32; 4] => "vec4",
        /// xy: height uv of corner 0; z: the depth scale (uv units); w: unused.
        anchor: [f32; 4] => "vec4",
    }
}

/// Every storage record above, for build.rs's header.
#[allow(dead_code)] // Read by build.rs.
pub const RECORD_LAYOUTS: &[ShaderLayout] = &[PrismRecord::LAYOUT];
