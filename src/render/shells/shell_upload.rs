//! A relief mesh drawn as prism shells: its shell built on the CPU ([`ShellMesh`]) and uploaded
//! for the surface pass's `:shells` pipelines, with what `--explain` says of it.

use std::sync::Arc;

use glam::Vec3;

use crate::heightfield::Address;
use crate::render::kit::mesh_buffers::{mesh_buffers, points_bounds};
use crate::scene::{MaterialHeights, Mesh, Scene};
use crate::shells::{ShellMesh, ShellVertex};
use crate::vk::{Buffer, Context, VkError, VkResult};

/// The most a mesh's prism shell may take: six 232-byte corners a triangle make 1 GiB at about
/// 770,000 triangles.
const MAX_SHELL_BYTES: u64 = 1 << 30;

/// A mesh drawn as prism shells, as `--explain` reports it.
#[derive(Debug, Clone, serde::Serialize)]
pub struct BuiltShell {
    /// The mesh's name.
    pub mesh: String,
    /// Prisms drawn (triangles of the mesh with area).
    pub prisms: usize,
    /// Bytes of its vertex and index buffers.
    pub bytes: u64,
}

/// A shell on the device: its buffers, its world bounds and its description.
pub(in crate::render) struct ShellUpload {
    pub vertices: Buffer,
    pub indices: Buffer,
    pub index_count: u32,
    pub bounds: (Vec3, Vec3),
    pub built: BuiltShell,
}

/// Builds and uploads the prism shell of `mesh`, drawn with relief material `material`; refuses a
/// shell over [`MAX_SHELL_BYTES`] by the mesh's name.
pub(in crate::render) fn upload_shell(
    ctx: &Arc<Context>,
    scene: &Scene,
    mesh: &Mesh,
    material: usize,
) -> VkResult<ShellUpload> {
    let invalid = |why: String| VkError::Invalid(format!("mesh {:?}: {why}", mesh.name));
    let relief = scene.materials[material]
        .relief
        .ok_or_else(|| invalid("prism shells need a relief material".into()))?;
    let (_, uv) = MaterialHeights::new(scene, None, Address::Repeat)
        .placement(relief.height)
        .ok_or_else(|| invalid("prism shells have no blended-layers variant".into()))?;
    let corners = mesh.indices.len() as u64 * 2;
    let bytes = corners * std::mem::size_of::<ShellVertex>() as u64;
    if bytes > MAX_SHELL_BYTES {
        return Err(invalid(format!(
            "its prism shell would take {} MiB ({} triangles at {} bytes each), more than {} \
             MiB; draw it with flat or curved silhouettes, or with fewer triangles",
            bytes >> 20,
            mesh.indices.len() / 3,
            6 * std::mem::size_of::<ShellVertex>() + 24 * 4,
            MAX_SHELL_BYTES >> 20
        )));
    }
    let shell = ShellMesh::new(mesh, &uv, relief.depth_scale)
        .map_err(|e| VkError::Invalid(e.to_string()))?;
    let bounds = points_bounds(shell.vertices.iter().map(|v| Vec3::from(v.position)));
    let built = BuiltShell {
        mesh: mesh.name.clone(),
        prisms: shell.prisms,
        bytes: (std::mem::size_of_val(shell.vertices.as_slice())
            + std::mem::size_of_val(shell.indices.as_slice())) as u64,
    };
    let (vertices, indices) = mesh_buffers(
        ctx,
        bytemuck::cast_slice(&shell.vertices),
        &shell.indices,
        &format!("{} shell", mesh.name),
    )?;
    Ok(ShellUpload {
        vertices,
        indices,
        index_count: shell.indices.len() as u32,
        bounds,
        built,
    })
}
