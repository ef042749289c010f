//! The view frustum as six planes, to skip meshes a frame cannot see (terrain tiles off screen).

use glam::{Mat4, Vec3, Vec4};

/// The six planes of a view-projection's clip volume (Vulkan's: depth 0 to 1), each `n.xyz . p +
/// n.w >= 0` inside (Gribb and Hartmann's extraction from the matrix's rows).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frustum {
    planes: [Vec4; 6],
}

impl Frustum {
    /// The planes of the clip volume of view-projection `m`.
    pub fn from_view_projection(m: Mat4) -> Frustum {
        let row = |k: usize| m.row(k);
        let (r0, r1, r2, r3) = (row(0), row(1), row(2), row(3));
        Frustum {
            planes: [r3 + r0, r3 - r0, r3 + r1, r3 - r1, r2, r3 - r2],
        }
    }

    /// Whether any of the box from `lo` to `hi` may be inside: false only when the whole box lies
    /// behind one plane (a box near a corner can pass while outside; it is then drawn and clipped).
    pub fn may_see_box(&self, lo: Vec3, hi: Vec3) -> bool {
        self.planes.iter().all(|p| {
            let n = p.truncate();
            // The box's corner farthest along the plane's normal.
            let far = Vec3::select(n.cmpge(Vec3::ZERO), hi, lo);
            n.dot(far) + p.w >= 0.0
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Camera;

    #[test]
    fn boxes_in_front_are_seen_and_those_behind_or_aside_are_not() {
        let camera = Camera::look_at(Vec3::new(0.0, 0.0, 5.0), Vec3::ZERO, 0.8, 0.1, 50.0);
        let f = Frustum::from_view_projection(camera.view_projection(1.5));
        let unit = |c: Vec3| (c - Vec3::splat(0.5), c + Vec3::splat(0.5));
        let seen = |c: Vec3| {
            let (lo, hi) = unit(c);
            f.may_see_box(lo, hi)
        };
        assert!(seen(Vec3::ZERO));
        assert!(seen(Vec3::new(0.0, 0.0, 4.0)), "straddles the near plane");
        assert!(!seen(Vec3::new(0.0, 0.0, 8.0)), "behind the camera");
        assert!(!seen(Vec3::new(40.0, 0.0, 0.0)), "far to the right");
        assert!(!seen(Vec3::new(0.0, -30.0, 0.0)), "far below");
        assert!(!seen(Vec3::new(0.0, 0.0, -60.0)), "past the far plane");
        // A box around the camera is always seen.
        assert!(f.may_see_box(Vec3::splat(-100.0), Vec3::splat(100.0)));
    }
}
