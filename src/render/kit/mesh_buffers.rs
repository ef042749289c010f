//! A mesh's buffers on the device and its bounds: what the frame's draws and the prism shells
//! upload and cull by alike.

use std::sync::Arc;

use glam::Vec3;

use crate::vk::{raw as vk, Buffer, Context, VkResult};

/// A draw's vertex buffer (`vertices`, as bytes) and index buffer, named after `name`.
pub(in crate::render) fn mesh_buffers(
    ctx: &Arc<Context>,
    vertices: &[u8],
    indices: &[u32],
    name: &str,
) -> VkResult<(Buffer, Buffer)> {
    Ok((
        Buffer::with_data(
            ctx,
            vertices,
            vk::BufferUsageFlags::VERTEX_BUFFER,
            &format!("{name} vertices"),
        )?,
        Buffer::with_data(
            ctx,
            bytemuck::cast_slice(indices),
            vk::BufferUsageFlags::INDEX_BUFFER,
            &format!("{name} indices"),
        )?,
    ))
}

/// The box around `points`.
pub(in crate::render) fn points_bounds(points: impl Iterator<Item = Vec3>) -> (Vec3, Vec3) {
    points.fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(lo, hi), p| (lo.min(p), hi.max(p)),
    )
}
