//! A mesh drawn through its cell complex takes part in scene shadows like a rasterised one: it
//! casts into the shadow maps (its own triangles stand in for the complex) and receives other
//! objects' shadows at its hits. The same scene rendered with the sphere rasterised and through
//! its complex must show the same shadows: the sphere's on the ground, and the ground lit around
//! it. At least 95% of the raster's shadowed pixels stay shadowed (the pebble's outline through
//! its complex differs from the raster's by a pixel in places), and at most 1% of all pixels
//! differ by 40 levels or more. On failure the images are left under `target/test-output/cells-shadows/`.

mod common;

use std::sync::Arc;

use glam::{Mat4, Vec3};
use relief::cells::MeshSelection;
use relief::render::{render, CellsOptions, RenderOptions};
use relief::scene::{quad_mesh, Camera, Light, Material, Mesh, Scene, Vertex};

const WIDTH: u32 = 240;
const HEIGHT: u32 = 160;

/// A closed lat-long sphere (one vertex per pole, no seam: a cell complex needs a closed mesh)
/// of `radius` about `centre`, with smooth normals.
fn ball(name: &str, radius: f32, centre: Vec3) -> Mesh {
    let (rings, segments) = (24u32, 48u32);
    let mut normals = vec![Vec3::Y];
    for i in 1..rings {
        let theta = std::f32::consts::PI * i as f32 / rings as f32;
        for j in 0..segments {
            let phi = std::f32::consts::TAU * j as f32 / segments as f32;
            normals.push(Vec3::new(
                theta.sin() * phi.cos(),
                theta.cos(),
                -theta.sin() * phi.sin(),
            ));
        }
    }
    normals.push(Vec3::NEG_Y);
    let south = normals.len() as u32 - 1;
    let at = |i: u32, j: u32| 1 + (i - 1) * segments + j % segments;
    let mut indices = Vec::new();
    for j in 0..segments {
        indices.extend([0, at(1, j), at(1, j + 1)]);
        indices.extend([south, at(rings - 1, j + 1), at(rings - 1, j)]);
    }
    for i in 1..rings - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            indices.extend([a, b, c, a, c, d]);
        }
    }
    let vertices = normals
        .iter()
        .map(|n| {
            let t = n.any_orthonormal_vector();
            Vertex::new(
                (*n * radius).to_array(),
                n.to_array(),
                [0.0; 2],
                [t.x, t.y, t.z, 1.0],
            )
        })
        .collect();
    Mesh {
        name: name.into(),
        vertices,
        indices,
        material: 0,
        transform: Mat4::from_translation(centre),
    }
}

fn scene() -> Scene {
    let ball_mesh = ball("ball", 0.6, Vec3::new(0.0, 1.0, 0.0));
    // A second, smaller ball under the first's shadow: a complex that receives.
    let pebble = ball("pebble", 0.25, Vec3::new(0.55, 0.25, 0.4));
    let ground = quad_mesh("ground", 6.0, 6.0, 1.0, 1);
    let grey = |name: &str| Material {
        name: name.into(),
        roughness: 0.7,
        ..Material::default()
    };
    let sun = Light {
        direction: Vec3::new(-0.5, -1.0, -0.35).normalize(),
        color: Vec3::splat(3.0),
        casts_shadows: true,
        ..Light::default_light()
    };
    Scene {
        meshes: vec![ball_mesh, pebble, ground],
        materials: vec![grey("balls"), grey("ground")],
        lights: vec![sun],
        camera: Some(Camera::look_at(
            Vec3::new(2.2, 2.6, 3.4),
            Vec3::new(0.0, 0.5, 0.0),
            0.8,
            0.1,
            30.0,
        )),
        ..Scene::default()
    }
}

fn draw(ctx: &Arc<relief::vk::Context>, scene: &Scene, cells: Option<&str>) -> Vec<u8> {
    let opts = RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT)
        .with_cells(cells.map(|name| CellsOptions::new(MeshSelection::Named(name.into()))));
    let frame = render(ctx, scene, None, &opts).expect("renders");
    common::assert_no_validation_errors(ctx);
    frame.rgba
}

fn luminance(rgba: &[u8], x: u32, y: u32) -> f64 {
    let i = 4 * (y * WIDTH + x) as usize;
    (0..3).map(|c| f64::from(rgba[i + c])).sum::<f64>() / 3.0
}

#[test]
fn a_cells_mesh_casts_and_receives_scene_shadows() {
    let Some(ctx) = common::device("a_cells_mesh_casts_and_receives_scene_shadows") else {
        return;
    };
    let scene = scene();
    let raster = draw(&ctx, &scene, None);
    let no_shadows = {
        let mut lit = scene.clone();
        lit.lights[0].casts_shadows = false;
        draw(&ctx, &lit, None)
    };
    let cells = draw(&ctx, &scene, Some("ball"));
    let both = {
        let mut renamed = scene.clone();
        renamed.meshes[1].name = "ball".into();
        draw(&ctx, &renamed, Some("ball"))
    };
    // Pixels the sphere's shadow darkens in the raster: much darker than without shadows.
    let shadowed: Vec<(u32, u32)> = (0..HEIGHT)
        .flat_map(|y| (0..WIDTH).map(move |x| (x, y)))
        .filter(|&(x, y)| luminance(&raster, x, y) < 0.6 * luminance(&no_shadows, x, y))
        .collect();
    assert!(
        shadowed.len() > 500,
        "only {} pixels in shadow: the scene no longer tests shadows",
        shadowed.len()
    );
    let mut failures = Vec::new();
    for (image, what) in [
        (&cells, "the ball through cells"),
        (&both, "both balls through cells"),
    ] {
        let kept = shadowed
            .iter()
            .filter(|&&(x, y)| luminance(image, x, y) < 0.6 * luminance(&no_shadows, x, y))
            .count();
        let wrong = raster
            .chunks_exact(4)
            .zip(image.chunks_exact(4))
            .filter(|(a, b)| (0..3).any(|c| a[c].abs_diff(b[c]) >= 40))
            .count();
        eprintln!(
            "{what}: {kept} of {} shadowed pixels still shadowed; {wrong} pixels differ by 40 levels or more from the raster",
            shadowed.len()
        );
        if kept * 100 < shadowed.len() * 95 || wrong * 100 > (WIDTH * HEIGHT) as usize {
            failures.push(what);
        }
    }
    if !failures.is_empty() {
        let dir = common::evidence_dir("cells-shadows");
        for (image, name) in [
            (&raster, "raster"),
            (&cells, "cells"),
            (&both, "both_cells"),
            (&no_shadows, "no_shadows"),
        ] {
            image::save_buffer(
                dir.join(format!("{name}.png")),
                image,
                WIDTH,
                HEIGHT,
                image::ColorType::Rgba8,
            )
            .expect("writes");
        }
        panic!(
            "shadows differ through cells: {failures:?}; images in {}",
            dir.display()
        );
    }
}
