//! The boxes the surface pass culls its draws by: a mesh's, and the world box around a
//! transformed one.

use glam::{Mat4, Vec3};

use crate::render::kit::mesh_buffers::points_bounds;
use crate::scene::Vertex;

/// The world-space box around the local box `lo`..`hi` under `transform`.
pub(super) fn world_bounds(transform: Mat4, lo: Vec3, hi: Vec3) -> (Vec3, Vec3) {
    (0..8).fold(
        (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
        |(a, b), k| {
            let corner = Vec3::new(
                if k & 1 == 0 { lo.x } else { hi.x },
                if k & 2 == 0 { lo.y } else { hi.y },
                if k & 4 == 0 { lo.z } else { hi.z },
            );
            let p = transform.transform_point3(corner);
            (a.min(p), b.max(p))
        },
    )
}

/// The box around a mesh's vertices, in its own space.
pub(super) fn mesh_bounds(vertices: &[Vertex]) -> (Vec3, Vec3) {
    points_bounds(vertices.iter().map(|v| Vec3::from(v.position)))
}
