//! Depth out, per material (`Relief::write_depth`, `extras.relief.write_depth`,
//! `relief render --write-depth`): a relief quad with a plain quad inside its depth range. With
//! the displaced depth written, the plain quad shows through where the relief lies deeper than
//! it (the mortar) and the G-buffer's depth is the hit's; with it off, the relief's polygon
//! hides the plain quad everywhere and the depth is the polygon's. Both come from one shader.

mod common;

use glam::{Mat4, Vec3};
use relief::heightfield::Generator;
use relief::method::Method;
use relief::render::{render, GBufferChannels, RenderOptions};
use relief::scene::{quad_mesh, Camera, Material, Relief, Scene};

const DISTANCE: f32 = 5.0;
/// 0.05 of the 6-unit quad: the relief reaches 0.3 units behind its polygon.
const DEPTH_SCALE: f32 = 0.05;

fn scene(write_depth: bool) -> Scene {
    let facing = Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    let mut relief = quad_mesh("relief", 6.0, 6.0, 1.0, 0);
    relief.transform = facing;
    // 0.15 behind the relief's polygon: in front of its mortar, behind its bricks' tops.
    let mut plain = quad_mesh("plain", 2.0, 2.0, 1.0, 1);
    plain.transform = Mat4::from_translation(Vec3::new(0.0, 0.0, -0.15)) * facing;
    Scene {
        meshes: vec![relief, plain],
        materials: vec![
            Material {
                name: "relief".into(),
                relief: Some(Relief {
                    write_depth,
                    ..Relief::new(DEPTH_SCALE, Method::QDM)
                }),
                ..Material::default()
            },
            Material::default(),
        ],
        camera: Some(Camera::look_at(
            Vec3::new(0.0, 0.0, DISTANCE),
            Vec3::ZERO,
            40f32.to_radians(),
            0.05,
            100.0,
        )),
        ..Scene::default()
    }
}

fn gbuffer(ctx: &std::sync::Arc<relief::vk::Context>, write_depth: bool) -> GBufferChannels {
    let heights = Generator::Bricks.generate(128, 128, 7).quantized_unorm16();
    let opts = RenderOptions::default()
        .with_width(96)
        .with_height(64)
        .with_gbuffer(true);
    let frame = render(ctx, &scene(write_depth), Some(&heights), &opts).expect("renders");
    frame.gbuffer.expect("G-buffer")
}

#[test]
fn the_displaced_depth_is_written_only_where_the_material_says() {
    let Some(ctx) = common::device("the_displaced_depth_is_written_only_where_the_material_says")
    else {
        return;
    };
    let on = gbuffer(&ctx, true);
    let through = on.mesh.iter().filter(|&&m| m == 2).count();
    let deeper = on
        .depth
        .iter()
        .zip(&on.mesh)
        .filter(|(d, &m)| m == 1 && **d > DISTANCE + 0.2)
        .count();
    assert!(
        through > 20,
        "the plain quad shows through the mortar: {through}"
    );
    assert!(deeper > 100, "relief depths are the hits': {deeper}");
    let off = gbuffer(&ctx, false);
    assert!(
        off.mesh.iter().all(|&m| m == 1),
        "the relief's polygon hides the plain quad"
    );
    let worst = off
        .depth
        .iter()
        .map(|d| (d - DISTANCE).abs())
        .fold(0f32, f32::max);
    assert!(worst < 1e-3, "the depth is the polygon's: off by {worst}");
    // The hits themselves are traced alike: the uv of a pixel the relief shows either way.
    let k = on
        .mesh
        .iter()
        .position(|&m| m == 1)
        .expect("a relief pixel");
    assert_eq!(on.uv[k], off.uv[k]);
    common::assert_no_validation_errors(&ctx);
}
