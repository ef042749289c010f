//! What the displaced-reference tests share: a relief scene around one mesh, drawing it, its
//! displaced copy, the mean channel difference and written evidence.

use std::sync::Arc;

use glam::Vec3;
use relief::displaced_reference::displaced_scene;
use relief::heightfield::{Address, Heightfield};
use relief::method::Method;
use relief::render::{render, RenderOptions};
use relief::scene::{sphere_mesh, torus_mesh, Camera, Light, Material, Mesh, Relief, Scene};

/// The size the displaced-reference tests draw at.
pub const WIDTH: u32 = 200;
pub const HEIGHT: u32 = 150;

/// `mesh` under flat QDM relief at `depth_scale`, one light, a camera at `eye` looking at the origin.
pub fn scene(mesh: Mesh, depth_scale: f32, eye: Vec3) -> Scene {
    let material = Material {
        name: "relief".into(),
        roughness: 0.6,
        relief: Some(Relief::new(depth_scale, Method::QDM)),
        ..Material::default()
    };
    let light = Light {
        direction: Vec3::new(-0.5, -0.7, -0.5).normalize(),
        color: Vec3::splat(3.0),
        ..Light::default_light()
    };
    Scene {
        meshes: vec![mesh],
        materials: vec![material],
        lights: vec![light],
        camera: Some(Camera::look_at(eye, Vec3::ZERO, 0.8, 0.1, 20.0)),
        ..Scene::default()
    }
}

/// `scene` drawn at [`WIDTH`] x [`HEIGHT`], with no validation error.
pub fn draw(
    ctx: &Arc<relief::vk::Context>,
    scene: &Scene,
    heights: Option<&Heightfield>,
) -> Vec<u8> {
    let opts = RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT);
    let frame = render(ctx, scene, heights, &opts).expect("renders");
    super::assert_no_validation_errors(ctx);
    frame.rgba
}

/// `scene` with its relief meshes tessellated to `texels` per edge and displaced.
pub fn displaced(scene: &Scene, heights: &Heightfield, texels: f64) -> Scene {
    let out = displaced_scene(scene, Some(heights), Address::Repeat, texels).expect("displaces");
    assert_eq!(out.meshes.len(), 1);
    assert!(out.scene.materials.iter().all(|m| m.relief.is_none()));
    out.scene
}

/// Mean absolute channel difference (RGB) over the pixels `keep` selects.
pub fn mean_difference(a: &[u8], b: &[u8], keep: impl Fn(usize) -> bool) -> f64 {
    let (mut sum, mut n) = (0u64, 0u64);
    for (p, (x, y)) in a.chunks_exact(4).zip(b.chunks_exact(4)).enumerate() {
        if !keep(p) {
            continue;
        }
        sum += (0..3).map(|c| u64::from(x[c].abs_diff(y[c]))).sum::<u64>();
        n += 3;
    }
    sum as f64 / n.max(1) as f64
}

/// Writes `rgba` ([`WIDTH`] x [`HEIGHT`]) as evidence under `displaced-reference/`.
pub fn save(name: &str, rgba: &[u8]) {
    let path = super::evidence_dir("displaced-reference").join(format!("{name}.png"));
    image::save_buffer(&path, rgba, WIDTH, HEIGHT, image::ColorType::Rgba8).expect("writes");
}

/// A 16x32 sphere of radius 1 and a 48x24 torus (ring 1, tube 0.35), each with the depth scale
/// that sinks its relief by 0.05 of its radius (the torus's: of its tube at the outer equator,
/// where one depth unit is sqrt(2 pi (R + r) 2 pi r) long).
pub fn sphere_and_torus() -> [(&'static str, Mesh, f32); 2] {
    [
        (
            "sphere",
            sphere_mesh("sphere", 1.0, 16, 32, 0),
            0.05 / (std::f32::consts::PI * 2f32.sqrt()),
        ),
        (
            "torus",
            torus_mesh("torus", 1.0, 0.35, 48, 24, 0),
            0.05 / (std::f32::consts::TAU * (1.35f32 * 0.35).sqrt()),
        ),
    ]
}
