//! The push block every mesh draw sends: the model matrix, its normal matrix and the draw's ids.

use glam::{Mat3, Mat4, Vec3};

pub(in crate::render) use crate::render::shader_interface::DrawPush;

impl DrawPush {
    pub(in crate::render) fn of(model: Mat4) -> DrawPush {
        let linear = Mat3::from_mat4(model);
        let normal = linear.inverse().transpose();
        let mirror = if linear.determinant() < 0.0 {
            -1.0
        } else {
            1.0
        };
        let col = |c: Vec3, w: f32| [c.x, c.y, c.z, w];
        DrawPush {
            model: model.to_cols_array_2d(),
            normal: [
                col(normal.x_axis, mirror),
                col(normal.y_axis, 0.0),
                col(normal.z_axis, 0.0),
            ],
            extra: [0; 4],
        }
    }

    /// The same draw, of scene mesh `mesh`.
    pub(in crate::render) fn for_mesh(mut self, mesh: usize) -> DrawPush {
        self.extra[1] = mesh as u32 + 1;
        self
    }

    /// The same draw rendering into shadow view `tile`.
    pub(in crate::render) fn for_tile(mut self, tile: u32) -> DrawPush {
        self.extra[0] = tile;
        self
    }
}
