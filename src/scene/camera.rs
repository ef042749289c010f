//! Cameras: perspective or orthographic, with a default framing of a scene's bounds.

use glam::{Mat4, Vec3};

/// A camera placed in the world.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Camera {
    /// World to view.
    pub view: Mat4,
    /// View to clip space.
    pub projection: Projection,
}

/// How the camera projects.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Projection {
    /// Vertical field of view in radians; `aspect` of `None` follows the image.
    Perspective {
        /// Vertical field of view, radians.
        yfov: f32,
        /// Width over height, `None` to follow the image.
        aspect: Option<f32>,
        /// Distance of the near plane.
        znear: f32,
        /// Distance of the far plane.
        zfar: f32,
    },
    /// Half extents of the view volume.
    Orthographic {
        /// Half the view volume's width.
        xmag: f32,
        /// Half the view volume's height.
        ymag: f32,
        /// Distance of the near plane.
        znear: f32,
        /// Distance of the far plane.
        zfar: f32,
    },
}

impl Camera {
    /// A perspective camera at `eye` looking at `target`, +y up.
    pub fn look_at(eye: Vec3, target: Vec3, yfov: f32, znear: f32, zfar: f32) -> Camera {
        Camera {
            view: Mat4::look_at_rh(eye, target, Vec3::Y),
            projection: Projection::Perspective {
                yfov,
                aspect: None,
                znear,
                zfar,
            },
        }
    }

    /// A camera that sees the whole box `lo..hi` from above and to the front.
    pub fn framing(lo: Vec3, hi: Vec3) -> Camera {
        let center = (lo + hi) * 0.5;
        let radius = ((hi - lo).length() * 0.5).max(1e-3);
        let yfov = 45f32.to_radians();
        let distance = radius / (yfov * 0.5).sin();
        let dir = Vec3::new(0.35, 0.55, 1.0).normalize();
        let eye = center + dir * distance;
        Camera::look_at(eye, center, yfov, distance * 0.01, distance + radius * 2.0)
    }

    /// This camera turned by `angle` radians about the vertical (+y) axis through `center`: the
    /// eye circles `center` at its height and distance and keeps its view of it.
    pub fn orbited(&self, center: Vec3, angle: f32) -> Camera {
        let turn = Mat4::from_translation(center)
            * Mat4::from_rotation_y(angle)
            * Mat4::from_translation(-center);
        Camera {
            view: self.view * turn.inverse(),
            projection: self.projection,
        }
    }

    /// Camera position in world space.
    pub fn eye(&self) -> Vec3 {
        self.view.inverse().transform_point3(Vec3::ZERO)
    }

    /// Projection times view for an image of `aspect` (width / height), in Vulkan clip space
    /// (y down, depth 0..1).
    pub fn view_projection(&self, aspect: f32) -> Mat4 {
        self.clip_from_view(aspect) * self.view
    }

    /// The projection alone for an image of `aspect` (width / height): view space (right-handed,
    /// looking down -z) to Vulkan clip space (y down, depth 0..1).
    pub fn clip_from_view(&self, aspect: f32) -> Mat4 {
        let proj = match self.projection {
            Projection::Perspective {
                yfov,
                aspect: fixed,
                znear,
                zfar,
            } => Mat4::perspective_rh(yfov, fixed.unwrap_or(aspect), znear, zfar),
            Projection::Orthographic {
                xmag,
                ymag,
                znear,
                zfar,
            } => Mat4::orthographic_rh(-xmag, xmag, -ymag, ymag, znear, zfar),
        };
        // glTF and glam use y up; Vulkan's framebuffer y points down.
        let flip = Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0));
        flip * proj
    }

    /// The near and far plane distances.
    pub fn near_far(&self) -> (f32, f32) {
        match self.projection {
            Projection::Perspective { znear, zfar, .. }
            | Projection::Orthographic { znear, zfar, .. } => (znear, zfar),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn an_orbit_keeps_distance_and_height_and_looks_at_the_centre() {
        let center = Vec3::new(1.0, 0.5, -2.0);
        let cam = Camera::look_at(Vec3::new(1.0, 2.0, 3.0), center, 0.8, 0.1, 100.0);
        let quarter = cam.orbited(center, std::f32::consts::FRAC_PI_2);
        let eye = quarter.eye();
        assert!((eye - Vec3::new(6.0, 2.0, -2.0)).length() < 1e-4, "{eye}");
        // The centre stays on the view axis.
        let seen = quarter.view.transform_point3(center);
        assert!(
            seen.x.abs() < 1e-4 && seen.y.abs() < 1e-4 && seen.z < 0.0,
            "{seen}"
        );
        let full = cam.orbited(center, std::f32::consts::TAU).eye();
        assert!((full - cam.eye()).length() < 1e-4);
    }
}
