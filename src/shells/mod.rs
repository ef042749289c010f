//! Prism shells: relief that keeps a curved mesh's true outline. Each triangle is extruded down
//! its vertices' normals into a prism as deep as the material's relief; a ray is traced through
//! the height field inside every prism it crosses, in the prism's own coordinates (barycentric
//! position on the triangle and depth), so where the displaced surface falls away from the
//! polygon the ray passes it by and the outline follows the relief.
//!
//! This module holds the march on the CPU, in f64, with no Vulkan: the definition of the
//! `shells` option, which the ground truth (the mesh really displaced,
//! [`crate::displaced_reference`]) is compared against; and the shell as triangles the surface
//! pass draws ([`ShellMesh`]), whose fragments run the same march in f32
//! (`shaders/include/shells.glsl`).
//!
//! The prisms are extruded exactly as the reference moves vertices: down the vertex normal by the
//! depth scale times the world length of one depth unit, averaged over the vertex's triangles by
//! area, over the repeats a mesh writes at one point with one normal (uv seams, poles). So at a
//! vertex a prism's point at relief depth `d` is the displaced vertex, and two triangles sharing
//! an edge share its side face: each side quad is split along the diagonal from the end with the
//! lower vertex identity, which both prisms choose alike, and the shell has no cracks. Where a
//! mesh repeats a point with different normals (a hard edge) the prisms part, as the reference's
//! displaced faces do.

mod coverage;
mod march;
mod prism;
mod scene_shells;
mod shell_mesh;

pub use coverage::coverage;
pub use march::ShellHit;
pub use prism::{extrude, Prism, PrismFace, Shell, ShellError};
pub use scene_shells::{scene_shells, SceneShellsError};
pub use shell_mesh::{ShellMesh, ShellVertex};

#[cfg(test)]
mod march_tests;
