//! Terrain tiles drawn with view culling: a frame skips the tiles its view cannot see, and the
//! image is the one the same ground drawn as a single mesh (never culled) gives.

mod common;

use glam::{Mat4, Vec3};
use relief::heightfield::Generator;
use relief::render::{FrameRequest, RenderOptions, Renderer};
use relief::scene::{Camera, Material, Mesh, Scene};
use relief::terrain::{terrain_tiles, GridOptions};

fn scene(meshes: Vec<Mesh>, camera: Camera) -> Scene {
    Scene {
        meshes,
        materials: vec![Material {
            name: "ground".into(),
            base_color: [0.45, 0.55, 0.35, 1.0],
            roughness: 0.8,
            ..Material::default()
        }],
        camera: Some(camera),
        ..Scene::default()
    }
}

/// Every tile's triangles as one mesh.
fn merged(tiles: &[Mesh]) -> Mesh {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    for t in tiles {
        let base = vertices.len() as u32;
        vertices.extend_from_slice(&t.vertices);
        indices.extend(t.indices.iter().map(|i| i + base));
    }
    Mesh {
        name: "ground".into(),
        vertices,
        indices,
        material: 0,
        transform: Mat4::IDENTITY,
    }
}

#[test]
fn tiles_out_of_view_are_skipped_without_changing_the_image() {
    let Some(ctx) = common::device("tiles_out_of_view_are_skipped") else {
        return;
    };
    let elevation = Generator::Fbm.generate(64, 64, 7);
    let options = GridOptions {
        extent: 16.0,
        height: 2.0,
        tile_quads: 8,
        step: 1,
    };
    let tiles = terrain_tiles(&elevation, &options, "ground", 0);
    assert_eq!(tiles.len(), 64);
    // Over the ground near one corner, looking down toward that corner: most tiles lie behind
    // the view.
    let camera = Camera::look_at(
        Vec3::new(-3.0, 4.0, -3.0),
        Vec3::new(-7.0, 0.5, -7.0),
        0.9,
        0.05,
        100.0,
    );
    let draw = |meshes: Vec<Mesh>| {
        let opts = RenderOptions::default().with_width(160).with_height(96);
        let mut renderer =
            Renderer::new(&ctx, &scene(meshes, camera), None, &opts).expect("renderer");
        renderer.draw(&FrameRequest::new(camera)).expect("frame")
    };
    let tiled = draw(tiles.clone());
    let whole = draw(vec![merged(&tiles)]);
    assert!(
        tiled.culled_draws > 20 && tiled.culled_draws < 60,
        "{} of 64 tiles culled",
        tiled.culled_draws
    );
    assert_eq!(whole.culled_draws, 0);
    let (a, b) = (tiled.rgba.unwrap(), whole.rgba.unwrap());
    let background = a[..4].to_vec();
    let covered = a
        .chunks_exact(4)
        .filter(|p| *p != background.as_slice())
        .count();
    assert!(covered > 160 * 96 / 3, "the ground covers {covered} pixels");
    let (mean, p99, _) = common::golden::compare(&a, &b);
    assert!(
        mean < 0.01 && p99 == 0,
        "culling changed the image: mean {mean}, p99 {p99}"
    );
    common::assert_no_validation_errors(&ctx);
}
