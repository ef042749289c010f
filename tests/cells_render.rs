//! Meshes drawn through their cell complexes (`--cells`, the cells pass) against the same meshes
//! rasterised: a textured sphere with a wrapping uv seam and a torus, each rendered both ways with
//! the same material, light and camera. The images must agree to a mean channel difference of 3,
//! over the whole image (the measure) and over the pixels the mesh covers; on failure both images and their difference are left under
//! `target/test-output/cells/`.

mod common;

use std::f32::consts::{PI, TAU};
use std::sync::Arc;

use glam::{Mat4, Vec3};
use image::{DynamicImage, Rgba, RgbaImage};
use relief::cells::MeshSelection;
use relief::render::{render, CellsOptions, Frame, Pass, RenderError, RenderOptions};
use relief::scene::{Camera, Material, Mesh, Scene, SceneImage, TextureRef, Vertex};

/// Mean channel difference allowed between the two images (the bound).
const MAX_MEAN_DIFF: f64 = 3.0;

/// A surface of revolution about y: `profile(v)` gives (radius from the axis, height) at v in
/// [0, 1]; u runs once around. The seam at u = 0 / 1 duplicates its vertices, as exporters do.
fn revolution(
    name: &str,
    rings: u32,
    segments: u32,
    profile: impl Fn(f32) -> (Vec3, Vec3),
) -> Mesh {
    let mut vertices = Vec::new();
    for i in 0..=rings {
        let v = i as f32 / rings as f32;
        for j in 0..=segments {
            let u = j as f32 / segments as f32;
            let (rz, normal_rz) = profile(v);
            // The seam's copies take the first column's angle, so that they weld exactly.
            let (s, c) = (TAU * (j % segments) as f32 / segments as f32).sin_cos();
            let around = |p: Vec3| Vec3::new(p.x * c, p.y, p.x * s);
            let position = around(rz);
            let normal = around(normal_rz).normalize();
            let tangent = Vec3::new(-s, 0.0, c);
            vertices.push(Vertex::new(
                position.to_array(),
                normal.to_array(),
                [u * 2.0, v],
                [tangent.x, tangent.y, tangent.z, 1.0],
            ));
        }
    }
    let mut indices = Vec::new();
    let row = segments + 1;
    for i in 0..rings {
        for j in 0..segments {
            let (a, b) = (i * row + j, i * row + j + 1);
            let (c, d) = (a + row, b + row);
            indices.extend([a, c, b, b, c, d]);
        }
    }
    Mesh {
        name: name.into(),
        vertices,
        indices,
        material: 0,
        transform: Mat4::IDENTITY,
    }
}

fn sphere() -> Mesh {
    // v from the south pole up; the poles' rings collapse to one point (degenerate triangles).
    revolution("sphere", 48, 96, |v| {
        let (s, c) = (PI * (v - 0.5)).sin_cos();
        let p = match v {
            0.0 => Vec3::NEG_Y,
            1.0 => Vec3::Y,
            _ => Vec3::new(c, s, 0.0),
        };
        (p, p)
    })
}

fn torus() -> Mesh {
    revolution("torus", 48, 128, |v| {
        // The tube's seam too takes its first ring's angle.
        let (s, c) = (TAU * if v == 1.0 { 0.0 } else { v }).sin_cos();
        let n = Vec3::new(c, s, 0.0);
        (Vec3::new(1.0, 0.0, 0.0) + 0.4 * n, n)
    })
}

/// A checker of two colours with a thin grid, 256^2, so that any uv error shows.
fn checker() -> SceneImage {
    let image = RgbaImage::from_fn(256, 256, |x, y| {
        if x % 32 == 0 || y % 32 == 0 {
            Rgba([30, 30, 40, 255])
        } else if (x / 32 + y / 32) % 2 == 0 {
            Rgba([220, 180, 60, 255])
        } else {
            Rgba([60, 140, 200, 255])
        }
    });
    SceneImage {
        name: "checker".into(),
        pixels: Arc::new(DynamicImage::ImageRgba8(image)),
    }
}

fn scene(mesh: Mesh, eye: Vec3) -> Scene {
    let material = Material {
        name: "checker".into(),
        base_color_texture: Some(TextureRef {
            image: 0,
            tex_coord: 0,
            transform: Default::default(),
            sampler: Default::default(),
        }),
        roughness: 0.5,
        ..Material::default()
    };
    Scene {
        meshes: vec![mesh],
        materials: vec![material],
        images: vec![checker()],
        camera: Some(Camera::look_at(eye, Vec3::ZERO, 0.8, 0.1, 20.0)),
        ..Scene::default()
    }
}

fn draw(ctx: &Arc<relief::vk::Context>, scene: &Scene, cells: bool) -> Frame {
    let opts = RenderOptions::default()
        .with_width(192)
        .with_height(144)
        .with_cells(cells.then(|| CellsOptions::new(MeshSelection::All)));
    render(ctx, scene, None, &opts).expect("renders")
}

/// Renders `scene` both ways and compares.
fn compare(ctx: &Arc<relief::vk::Context>, name: &str, scene: &Scene) {
    let raster = draw(ctx, scene, false);
    let cells = draw(ctx, scene, true);
    assert!(raster.plan.cells.is_empty());
    assert_eq!(cells.plan.cells.len(), 1);
    assert!(
        cells.plan.draws.is_empty(),
        "the mesh left the surface pass"
    );
    assert_eq!(cells.cells.len(), 1);
    assert!(cells.timings.iter().any(|t| t.pass == Pass::Cells));
    assert!(!raster.timings.iter().any(|t| t.pass == Pass::Cells));
    let background = &raster.rgba[..4];
    let covered = raster
        .rgba
        .chunks_exact(4)
        .filter(|p| p != &background)
        .count();
    let pixels = raster.rgba.len() / 4;
    assert!(
        covered * 5 > pixels,
        "{name}: the mesh covers {covered} of {pixels} pixels"
    );
    let (mean, p99, diff) = common::golden::compare(&cells.rgba, &raster.rgba);
    // Over the pixels the mesh covers in either image: a stricter view of the same difference.
    let object_total: u64 = cells
        .rgba
        .chunks_exact(4)
        .zip(raster.rgba.chunks_exact(4))
        .filter(|(a, b)| a != &background || b != &background)
        .map(|(a, b)| (0..3).map(|c| u64::from(a[c].abs_diff(b[c]))).sum::<u64>())
        .sum();
    let object_mean = object_total as f64 / (covered * 3) as f64;
    eprintln!(
        "{name}: mean channel difference {mean:.3} over the image, {object_mean:.3} over the mesh, p99 {p99}; {:?}",
        cells.cells[0]
    );
    if mean > MAX_MEAN_DIFF || object_mean > MAX_MEAN_DIFF {
        let dir = common::evidence_dir("cells");
        let save = |what: &str, rgba: &[u8]| {
            let path = dir.join(format!("{name}_{what}.png"));
            image::save_buffer(&path, rgba, 192, 144, image::ColorType::Rgba8).expect("writes");
        };
        save("cells", &cells.rgba);
        save("raster", &raster.rgba);
        save("diff", &diff);
        panic!(
            "{name}: through its cell complex the mesh differs from the rasterised one by a mean of {mean:.3} over the image and {object_mean:.3} over the mesh (max {MAX_MEAN_DIFF}); images in {}",
            dir.display()
        );
    }
    common::assert_no_validation_errors(ctx);
}

#[test]
fn a_textured_sphere_through_its_cells_matches_the_rasterised_sphere() {
    let Some(ctx) = common::device("cells_render_sphere") else {
        return;
    };
    // The seam (u = 0) faces the camera.
    compare(&ctx, "sphere", &scene(sphere(), Vec3::new(3.2, 1.0, 0.4)));
}

#[test]
fn a_torus_through_its_cells_matches_the_rasterised_torus() {
    let Some(ctx) = common::device("cells_render_torus") else {
        return;
    };
    // From above at a slant: the hole and the inner wall are in view.
    compare(&ctx, "torus", &scene(torus(), Vec3::new(0.0, 2.6, 2.4)));
}

#[test]
fn an_open_mesh_or_an_unknown_name_is_refused_in_one_line() {
    let Some(ctx) = common::device("cells_render_refusals") else {
        return;
    };
    let mut open = sphere();
    // A triangle off the equator (the poles' triangles are degenerate and dropped anyway).
    let middle = open.indices.len() / 2 / 3 * 3;
    open.indices.drain(middle..middle + 3);
    let opts = |selection: &str| {
        RenderOptions::default().with_cells(Some(CellsOptions::new(selection.parse().unwrap())))
    };
    let err = render(
        &ctx,
        &scene(open, Vec3::new(3.0, 0.0, 0.0)),
        None,
        &opts("all"),
    )
    .expect_err("an open mesh is refused");
    assert!(matches!(err, RenderError::Cells(_)), "{err:?}");
    let message = err.to_string();
    assert!(
        message.contains("sphere") && message.contains("open") && !message.contains('\n'),
        "{message}"
    );
    let err = render(
        &ctx,
        &scene(sphere(), Vec3::new(3.0, 0.0, 0.0)),
        None,
        &opts("teapot"),
    )
    .expect_err("no mesh of that name");
    let message = err.to_string();
    assert!(
        message.contains("teapot") && message.contains("sphere"),
        "{message}"
    );
    common::assert_no_validation_errors(&ctx);
}
