//! The relief stack: relief quads one behind the other, facing the camera, the nearest filling
//! its view. The scene of hidden relief: the frame-cost bench times it, and the occluder tests
//! check that skipping hidden fragments leaves its image as it was.

use glam::{Mat4, Vec3};

use super::{quad_mesh, Camera, Light, Material, Relief, Scene};
use crate::method::Method;

/// A stack quad's side, in world units.
pub const STACK_QUAD_SIDE: f32 = 6.0;
/// Their depth scale in uv: 0.3 world units of relief on a 6-unit quad.
pub const STACK_DEPTH_SCALE: f32 = 0.05;
/// The camera's distance to the nearest quad: close enough that it fills a 16:9 view at a
/// 40-degree vertical field of view.
const STACK_CAMERA_DISTANCE: f32 = 4.0;

/// `quads` relief quads traced with `method`, facing the camera, `spacing` apart along the view
/// axis, the nearest at the origin; `nearest_first` orders the meshes (and so the draws) from
/// the camera outwards. A sun casts shadows, so a look with shadow maps builds one. Relief
/// materials read the frame's height map.
pub fn relief_stack_scene(
    quads: usize,
    spacing: f32,
    nearest_first: bool,
    method: Method,
) -> Scene {
    let material = Material {
        name: "stack".into(),
        base_color: [0.6, 0.5, 0.4, 1.0],
        roughness: 0.7,
        relief: Some(Relief::new(STACK_DEPTH_SCALE, method)),
        ..Material::default()
    };
    let mut meshes: Vec<_> = (0..quads)
        .map(|k| {
            let side = STACK_QUAD_SIDE;
            let mut quad = quad_mesh(&format!("quad {k}"), side, side, 1.0, 0);
            // The XZ quad turned to face +Z (the camera), then pushed back k steps.
            quad.transform = Mat4::from_translation(Vec3::new(0.0, 0.0, -spacing * k as f32))
                * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
            quad
        })
        .collect();
    if !nearest_first {
        meshes.reverse();
    }
    Scene {
        meshes,
        materials: vec![material],
        camera: Some(Camera::look_at(
            Vec3::new(0.0, 0.0, STACK_CAMERA_DISTANCE),
            Vec3::ZERO,
            40f32.to_radians(),
            0.05,
            100.0,
        )),
        lights: vec![Light {
            casts_shadows: true,
            direction: -Vec3::new(-0.4, 0.5, 0.8).normalize(),
            radius: 2f32.to_radians(),
            ..Light::default_light()
        }],
        images: Vec::new(),
        camera_path: None,
    }
}
