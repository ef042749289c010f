//! The built-in default scene: a displaced brick slab on a pedestal, seen at an oblique angle, with
//! a plain cube and a ground plane around it for context. `relief render` draws it with no input,
//! with QDM, cone soft shadows from a low sun of 2 degrees' angular radius, and horizon-8 AO.

use glam::{Mat4, Vec3};

use super::{
    box_mesh, quad_mesh, AoMode, Camera, Light, Material, Mesh, Relief, Scene, ShadowMode,
    ShadowSettings,
};
use crate::heightfield::{Generator, Heightfield};
use crate::method::Method;

/// Size, seed and depth scale of the default scene's height field.
pub const DEFAULT_HEIGHTFIELD: (Generator, u32, u64) = (Generator::Bricks, 256, 1);
const DEFAULT_DEPTH_SCALE: f32 = 0.06;
/// The default scene's method when none is asked for.
pub const DEFAULT_SCENE_METHOD: Method = Method::QDM;
/// The default light's angular radius: wide enough that the penumbrae show at this view.
const DEFAULT_LIGHT_RADIUS_DEG: f32 = 2.0;

/// The height field the default scene is displaced with.
pub fn default_heightfield() -> Heightfield {
    let (generator, size, seed) = DEFAULT_HEIGHTFIELD;
    generator.generate(size, size, seed)
}

fn material(name: &str, rgb: [f32; 3], roughness: f32, relief: Option<Relief>) -> Material {
    Material {
        name: name.into(),
        base_color: [rgb[0], rgb[1], rgb[2], 1.0],
        roughness,
        relief,
        ..Material::default()
    }
}

/// Removes the faces whose normal points up (the pedestal's top is the relief quad).
fn without_top(mut mesh: Mesh) -> Mesh {
    let vertices = &mesh.vertices;
    let kept: Vec<u32> = mesh
        .indices
        .chunks(3)
        .filter(|tri| vertices[tri[0] as usize].normal[1] < 0.5)
        .flatten()
        .copied()
        .collect();
    mesh.indices = kept;
    mesh
}

/// The default scene, displaced with `method`.
pub fn default_scene(method: Method) -> Scene {
    let relief = Relief {
        shadows: ShadowSettings::new(ShadowMode::Cone),
        ao: AoMode::Horizon {
            directions: 8,
            rotated: false,
        },
        ..Relief::new(DEFAULT_DEPTH_SCALE, method)
    };
    let materials = vec![
        material("bricks", [0.62, 0.26, 0.17], 0.7, Some(relief)),
        material("pedestal", [0.55, 0.55, 0.58], 0.5, None),
        material("ground", [0.35, 0.38, 0.33], 0.9, None),
        material("cube", [0.15, 0.3, 0.6], 0.35, None),
    ];
    let slab = quad_mesh("relief slab", 2.0, 2.0, 2.0, 0);
    let mut pedestal = without_top(box_mesh("pedestal", Vec3::new(1.0, 0.3, 1.0), 1));
    pedestal.transform = Mat4::from_translation(Vec3::new(0.0, -0.3, 0.0));
    let mut ground = quad_mesh("ground", 12.0, 12.0, 6.0, 2);
    ground.transform = Mat4::from_translation(Vec3::new(0.0, -0.6, 0.0));
    let mut cube = box_mesh("cube", Vec3::splat(0.3), 3);
    cube.transform =
        Mat4::from_translation(Vec3::new(1.7, -0.3, -0.6)) * Mat4::from_rotation_y(0.6);
    Scene {
        meshes: vec![slab, pedestal, ground, cube],
        materials,
        camera: Some(Camera::look_at(
            Vec3::new(1.6, 1.55, 2.6),
            Vec3::new(0.1, -0.15, 0.0),
            40f32.to_radians(),
            0.05,
            50.0,
        )),
        // The one light casts shadows, so the default scene shows relief self-shadowing.
        lights: vec![Light {
            casts_shadows: true,
            // Low (about 27 degrees), so the bricks cast shadows longer than the mortar is wide.
            direction: -Vec3::new(-0.8, 0.45, 0.2).normalize(),
            radius: DEFAULT_LIGHT_RADIUS_DEG.to_radians(),
            ..Light::default_light()
        }],
        images: Vec::new(),
        camera_path: None,
    }
}
