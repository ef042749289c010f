//! Where each shadow map looks from: cascades of a directional light fitted to slices of the
//! camera's frustum, one perspective view for a spot light, six for a point light. Pure math on
//! `glam` types, so it is tested without a device.
//!
//! Every view maps world space to Vulkan clip space the way the camera does (y flipped, depth
//! 0..1 growing away from the light), so a mesh's winding, and so its culling, is the same in
//! the shadow pass as in the surface pass.

use glam::{Mat4, Vec3, Vec4};

use crate::scene::{Camera, Projection};

/// One shadow map's view of the scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LightView {
    /// World to clip space.
    pub view_proj: Mat4,
    /// A perspective view (spot, point) rather than an orthographic one (directional).
    pub perspective: bool,
    /// Near plane distance (perspective views; 0 for orthographic ones).
    pub near: f32,
    /// Far plane distance (perspective), or the depth range in world units (orthographic).
    pub far: f32,
    /// World size of one texel: at unit distance along the axis for perspective views, everywhere
    /// for orthographic ones.
    pub texel: f32,
}

/// How the camera's depth range is split among cascades: 0 is uniform, 1 logarithmic. Between
/// the two, near cascades stay sharp without the far ones collapsing to slivers.
const SPLIT_BLEND: f32 = 0.7;

/// Extra texels around a perspective face (point lights), so that a filter reaching past the
/// face's 90 degrees still reads rendered depths.
pub const FACE_GUARD_TEXELS: f32 = 8.0;

/// Widest perspective map: spot cones wider than this are mapped only up to it.
const MAX_PERSPECTIVE_FOV: f32 = 170.0 * std::f32::consts::PI / 180.0;

/// Vulkan clip space's y points down; glam's projections point up.
fn flip_y() -> Mat4 {
    Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0))
}

/// An up vector not parallel to `forward`.
fn up_for(forward: Vec3) -> Vec3 {
    if forward.y.abs() > 0.99 {
        Vec3::Z
    } else {
        Vec3::Y
    }
}

/// The corners of a box.
fn corners(lo: Vec3, hi: Vec3) -> [Vec3; 8] {
    std::array::from_fn(|k| {
        Vec3::new(
            if k & 1 == 0 { lo.x } else { hi.x },
            if k & 2 == 0 { lo.y } else { hi.y },
            if k & 4 == 0 { lo.z } else { hi.z },
        )
    })
}

/// The camera's near and far distances, the far one pulled in to the farthest corner of the
/// scene's bounds (a cascade beyond the scene holds nothing).
fn depth_range(camera: &Camera, bounds: (Vec3, Vec3)) -> (f32, f32) {
    let (near, far) = camera.near_far();
    let farthest = corners(bounds.0, bounds.1)
        .iter()
        .map(|&c| -camera.view.transform_point3(c).z)
        .fold(0.0f32, f32::max);
    let far = far.min(farthest.max(near * 2.0));
    (near.max(1e-4), far.max(near * 2.0))
}

/// The split distances of `cascades` cascades over `near..far` (`cascades + 1` values).
pub fn cascade_splits(near: f32, far: f32, cascades: u32) -> Vec<f32> {
    let n = cascades.max(1);
    (0..=n)
        .map(|i| {
            let t = i as f32 / n as f32;
            let log = near * (far / near).powf(t);
            let uniform = near + (far - near) * t;
            SPLIT_BLEND * log + (1.0 - SPLIT_BLEND) * uniform
        })
        .collect()
}

/// The eight world-space corners of the camera's view volume between distances `d0` and `d1`.
fn slice_corners(camera: &Camera, aspect: f32, d0: f32, d1: f32) -> [Vec3; 8] {
    let to_world = camera.view.inverse();
    let half = |d: f32| match camera.projection {
        Projection::Perspective {
            yfov, aspect: a, ..
        } => {
            let y = d * (yfov * 0.5).tan();
            (y * a.unwrap_or(aspect), y)
        }
        Projection::Orthographic { xmag, ymag, .. } => (xmag, ymag),
    };
    std::array::from_fn(|k| {
        let d = if k & 4 == 0 { d0 } else { d1 };
        let (hx, hy) = half(d);
        let x = if k & 1 == 0 { -hx } else { hx };
        let y = if k & 2 == 0 { -hy } else { hy };
        to_world.transform_point3(Vec3::new(x, y, -d))
    })
}

/// The cascades of a directional light travelling along `direction`, each a square orthographic
/// map of `size` texels around a sphere holding one slice of the camera's view. The sphere's
/// radius depends only on the frustum's shape and its centre is snapped to whole texels in the
/// light's plane, so a moving or turning camera moves each map by whole texels and shadow edges
/// do not shimmer. Depth covers the whole scene along the light, so casters outside the view
/// still cast into it.
pub fn directional_cascades(
    direction: Vec3,
    camera: &Camera,
    aspect: f32,
    bounds: (Vec3, Vec3),
    cascades: u32,
    size: u32,
) -> Vec<LightView> {
    let forward = direction.normalize_or(Vec3::NEG_Y);
    // As look_at_rh builds a camera's axes, so the map's handedness matches the camera's.
    let right = forward.cross(up_for(forward)).normalize();
    let up = right.cross(forward);
    // Rows: light-plane x, light-plane y, depth along the light.
    let basis = Mat4::from_cols(
        Vec4::new(right.x, up.x, forward.x, 0.0),
        Vec4::new(right.y, up.y, forward.y, 0.0),
        Vec4::new(right.z, up.z, forward.z, 0.0),
        Vec4::W,
    );
    let scene = corners(bounds.0, bounds.1);
    let (zmin, zmax) = scene.iter().fold((f32::MAX, f32::MIN), |(lo, hi), &c| {
        let z = c.dot(forward);
        (lo.min(z), hi.max(z))
    });
    // Margins keep casters that touch the scene's bounds off the clip planes.
    let pad = ((zmax - zmin) * 0.01).max(1e-3);
    let (zmin, zmax) = (zmin - pad, zmax + pad);
    let (near, far) = depth_range(camera, bounds);
    let splits = cascade_splits(near, far, cascades);
    splits
        .windows(2)
        .map(|w| {
            let c = slice_corners(camera, aspect, w[0], w[1]);
            let center = c.iter().copied().sum::<Vec3>() / 8.0;
            let radius = c.iter().map(|p| p.distance(center)).fold(0.0f32, f32::max);
            // Rounded up so rounding noise in the corners never changes the texel size.
            let radius = (radius * 64.0).ceil() / 64.0;
            let texel = 2.0 * radius / size as f32;
            let snap = |v: f32| (v / texel).round() * texel;
            let (cx, cy) = (snap(center.dot(right)), snap(center.dot(up)));
            let ortho = Mat4::from_cols(
                Vec4::new(1.0 / radius, 0.0, 0.0, 0.0),
                Vec4::new(0.0, 1.0 / radius, 0.0, 0.0),
                Vec4::new(0.0, 0.0, 1.0 / (zmax - zmin), 0.0),
                Vec4::new(-cx / radius, -cy / radius, -zmin / (zmax - zmin), 1.0),
            );
            LightView {
                view_proj: flip_y() * ortho * basis,
                perspective: false,
                near: 0.0,
                far: zmax - zmin,
                texel,
            }
        })
        .collect()
}

/// Near and far planes of a perspective map at `position`: out to the scene's farthest corner
/// (or the light's range, when nearer), the near plane a small fraction of that.
fn perspective_range(position: Vec3, bounds: (Vec3, Vec3), range: Option<f32>) -> (f32, f32) {
    let farthest = corners(bounds.0, bounds.1)
        .iter()
        .map(|c| c.distance(position))
        .fold(0.0f32, f32::max);
    let far = range.map_or(farthest, |r| r.min(farthest)).max(1e-2) * 1.01;
    (far * 2e-3, far)
}

/// A perspective map at `position` looking along `forward`, `fov` wide, square.
fn perspective_view(
    position: Vec3,
    forward: Vec3,
    fov: f32,
    range: (f32, f32),
    size: u32,
) -> LightView {
    let (near, far) = range;
    let view = Mat4::look_to_rh(position, forward, up_for(forward));
    let proj = Mat4::perspective_rh(fov, 1.0, near, far);
    LightView {
        view_proj: flip_y() * proj * view,
        perspective: true,
        near,
        far,
        texel: 2.0 * (fov * 0.5).tan() / size as f32,
    }
}

/// The map of a spot light at `position` pointing along `direction` with outer cone angle
/// `outer_cone` (radians from the axis).
pub fn spot_view(
    position: Vec3,
    direction: Vec3,
    outer_cone: f32,
    range: Option<f32>,
    bounds: (Vec3, Vec3),
    size: u32,
) -> LightView {
    let guard = 2.0 * FACE_GUARD_TEXELS / size as f32;
    let fov = (2.0 * outer_cone * (1.0 + guard)).clamp(1e-3, MAX_PERSPECTIVE_FOV);
    let forward = direction.normalize_or(Vec3::NEG_Y);
    let depth = perspective_range(position, bounds, range);
    perspective_view(position, forward, fov, depth, size)
}

/// The six faces of a point light's cube map, in the order +x, -x, +y, -y, +z, -z (the shaders
/// pick a face by the dominant axis of the direction from the light in that order).
pub fn point_views(
    position: Vec3,
    range: Option<f32>,
    bounds: (Vec3, Vec3),
    size: u32,
) -> [LightView; 6] {
    // Wider than 90 degrees by the guard band on each side.
    let fov = 2.0 * (1.0 + 2.0 * FACE_GUARD_TEXELS / size as f32).atan();
    let depth = perspective_range(position, bounds, range);
    let axes = [
        Vec3::X,
        Vec3::NEG_X,
        Vec3::Y,
        Vec3::NEG_Y,
        Vec3::Z,
        Vec3::NEG_Z,
    ];
    axes.map(|axis| perspective_view(position, axis, fov, depth, size))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn clip(v: &LightView, p: Vec3) -> Vec3 {
        let c = v.view_proj * p.extend(1.0);
        c.truncate() / c.w
    }

    fn inside(c: Vec3) -> bool {
        c.x.abs() <= 1.0 && c.y.abs() <= 1.0 && (0.0..=1.0).contains(&c.z)
    }

    const BOUNDS: (Vec3, Vec3) = (Vec3::new(-2.0, -0.1, -2.0), Vec3::new(2.0, 1.0, 2.0));

    fn camera() -> Camera {
        Camera::look_at(Vec3::new(3.0, 2.0, 3.0), Vec3::ZERO, 0.8, 0.1, 50.0)
    }

    #[test]
    fn splits_run_from_near_to_far_and_grow() {
        let s = cascade_splits(0.1, 20.0, 4);
        assert_eq!(s.len(), 5);
        assert!((s[0] - 0.1).abs() < 1e-6 && (s[4] - 20.0).abs() < 1e-4);
        assert!(s.windows(2).all(|w| w[1] > w[0]));
    }

    #[test]
    fn each_cascade_holds_its_slice_and_depth_grows_along_the_light() {
        let cam = camera();
        let dir = Vec3::new(0.3, -1.0, 0.2).normalize();
        let views = directional_cascades(dir, &cam, 1.5, BOUNDS, 3, 1024);
        let (near, far) = depth_range(&cam, BOUNDS);
        let splits = cascade_splits(near, far, 3);
        for (k, v) in views.iter().enumerate() {
            for p in slice_corners(&cam, 1.5, splits[k], splits[k + 1]) {
                let c = clip(v, p);
                assert!(c.x.abs() <= 1.0 && c.y.abs() <= 1.0, "cascade {k}: {c}");
            }
            let a = clip(v, Vec3::new(0.0, 0.5, 0.0));
            let b = clip(v, Vec3::new(0.0, 0.5, 0.0) + dir * 0.1);
            assert!(b.z > a.z);
            // Depth spans the whole scene, whichever slice the cascade holds.
            assert!((0.0..=1.0).contains(&a.z) && (0.0..=1.0).contains(&b.z));
        }
        assert!(views[0].texel < views[2].texel);
    }

    #[test]
    fn moving_the_camera_moves_a_cascade_by_whole_texels() {
        let dir = Vec3::new(0.3, -1.0, 0.2).normalize();
        let a = directional_cascades(dir, &camera(), 1.5, BOUNDS, 2, 512);
        let moved = Camera::look_at(Vec3::new(3.013, 2.0, 2.991), Vec3::ZERO, 0.8, 0.1, 50.0);
        let b = directional_cascades(dir, &moved, 1.5, BOUNDS, 2, 512);
        for (va, vb) in a.iter().zip(&b) {
            assert_eq!(va.texel, vb.texel);
            let p = Vec3::new(0.2, 0.0, -0.4);
            let shift = (clip(vb, p) - clip(va, p)).truncate() * 0.5 * 512.0;
            let whole = shift.round();
            assert!((shift - whole).abs().max_element() < 1e-2, "{shift}");
        }
    }

    #[test]
    fn spot_and_point_views_see_what_lies_before_them() {
        let pos = Vec3::new(0.0, 3.0, 0.0);
        let spot = spot_view(pos, Vec3::NEG_Y, 0.6, None, BOUNDS, 512);
        assert!(inside(clip(&spot, Vec3::new(0.5, 0.0, 0.5))));
        assert!(clip(&spot, Vec3::new(0.0, 0.0, 0.0)).z > clip(&spot, Vec3::new(0.0, 1.0, 0.0)).z);
        let faces = point_views(Vec3::new(0.0, 0.5, 0.0), None, BOUNDS, 256);
        for (k, p) in [
            Vec3::new(1.5, 0.5, 0.1),
            Vec3::new(-1.5, 0.5, 0.1),
            Vec3::new(0.1, 0.95, 0.1),
            Vec3::new(0.1, 0.0, 0.1),
            Vec3::new(0.1, 0.5, 1.5),
            Vec3::new(0.1, 0.5, -1.5),
        ]
        .into_iter()
        .enumerate()
        {
            assert!(inside(clip(&faces[k], p)), "face {k}");
        }
    }
}
