//! `relief cells --render WxH`: the mesh drawn through its cell complex against the same mesh
//! rasterised, from the same camera, with the same material and light (Apaza and Andujar compares its
//! renders with the rasterised mesh): both images, their difference, the mean channel
//! difference, and the cells pass's GPU time and pixels per second over a few frames.

use std::path::Path;

use anyhow::Context as _;
use glam::{Mat4, Vec3};
use relief::bench::{image_error, median};
use relief::cells::{ClosedMesh, MeshSelection};
use relief::render::{CellsOptions, FrameRequest, Pass, RenderOptions, Renderer};
use relief::scene::{Material, Mesh, Scene, Vertex};
use serde::Serialize;

/// Frames timed after the first (which compiles the shaders on llvmpipe).
const TIMED_FRAMES: usize = 5;

/// What the comparison measured.
#[derive(Debug, Serialize)]
pub struct RenderComparison {
    pub width: u32,
    pub height: u32,
    /// Mean over the image of the absolute difference per colour channel, in 8-bit steps.
    pub mean_channel_difference: f64,
    /// The same over the pixels either image covers with the mesh.
    pub mean_channel_difference_on_mesh: f64,
    /// Pixels the rasterised mesh covers.
    pub covered_pixels: usize,
    /// Median GPU time of the cells pass over the timed frames.
    pub cells_ms: f64,
    /// Covered pixels over that time: each marches at least one ray.
    pub pixels_per_second: f64,
    /// Median GPU time of the surface pass drawing the rasterised mesh.
    pub raster_ms: f64,
}

/// The scene `relief cells` measures for a procedural shape: the closed mesh with normals
/// averaged over its corners, a plain grey material, the default light.
pub fn shape_scene(name: &str, mesh: &ClosedMesh) -> Scene {
    let mut normals = vec![Vec3::ZERO; mesh.positions().len()];
    for t in mesh.triangles() {
        let [a, b, c] = t.map(|v| Vec3::from_array(mesh.positions()[v as usize].map(|x| x as f32)));
        // Area-weighted: the cross product's length is twice the area.
        let n = (b - a).cross(c - a);
        for &v in t {
            normals[v as usize] += n;
        }
    }
    let vertices = mesh
        .positions()
        .iter()
        .zip(&normals)
        .map(|(p, n)| {
            let n = n.normalize_or(Vec3::Y);
            let t = n.any_orthonormal_vector();
            Vertex::new(
                p.map(|x| x as f32),
                n.to_array(),
                [0.0; 2],
                [t.x, t.y, t.z, 1.0],
            )
        })
        .collect();
    Scene {
        meshes: vec![Mesh {
            name: name.to_owned(),
            vertices,
            indices: mesh.triangles().iter().flatten().copied().collect(),
            material: 0,
            transform: Mat4::IDENTITY,
        }],
        materials: vec![Material {
            name: "grey".into(),
            base_color: [0.7, 0.7, 0.7, 1.0],
            roughness: 0.5,
            ..Material::default()
        }],
        ..Scene::default()
    }
}

/// Renders `scene` rasterised and through the complexes `cells` asks for, writes `raster.png`,
/// `cells.png` and `diff.png` (4x the largest channel difference, in red) into `out`, and
/// measures both.
pub fn compare(
    ctx: &std::sync::Arc<relief::vk::Context>,
    scene: &Scene,
    cells: CellsOptions,
    (width, height): (u32, u32),
    out: &Path,
) -> anyhow::Result<RenderComparison> {
    let raster_opts = RenderOptions::default()
        .with_width(width)
        .with_height(height);
    let cells_opts = raster_opts.clone().with_cells(Some(cells));
    eprintln!("rendering the mesh rasterised and through its cells at {width}x{height}...");
    let (raster, raster_ms) = draw(ctx, scene, &raster_opts, Pass::Surface)?;
    let (through_cells, cells_ms) = draw(ctx, scene, &cells_opts, Pass::Cells)?;
    let background = raster.get(..4).unwrap_or(&[0; 4]).to_vec();
    let pairs = || through_cells.chunks_exact(4).zip(raster.chunks_exact(4));
    let diff: Vec<u8> = pairs()
        .flat_map(|(a, b)| {
            let max = (0..3).map(|c| a[c].abs_diff(b[c])).max().unwrap_or(0);
            [max.saturating_mul(4), 0, 0, 255]
        })
        .collect();
    let covered = pairs().filter(|(_, b)| *b != background.as_slice()).count();
    // The pixels either image covers with the mesh.
    let (on_cells, on_raster): (Vec<u8>, Vec<u8>) = pairs()
        .filter(|(a, b)| *a != background.as_slice() || *b != background.as_slice())
        .flat_map(|(a, b)| a.iter().copied().zip(b.iter().copied()))
        .unzip();
    for (name, rgba) in [
        ("raster.png", &raster),
        ("cells.png", &through_cells),
        ("diff.png", &diff),
    ] {
        let path = out.join(name);
        image::save_buffer(&path, rgba, width, height, image::ColorType::Rgba8)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(RenderComparison {
        width,
        height,
        mean_channel_difference: image_error(&through_cells, &raster).mean,
        mean_channel_difference_on_mesh: image_error(&on_cells, &on_raster).mean,
        covered_pixels: covered,
        cells_ms,
        pixels_per_second: covered as f64 / (cells_ms / 1e3).max(1e-9),
        raster_ms,
    })
}

/// One frame read back, then `TIMED_FRAMES` more timed; the pixels and the median GPU time of
/// `pass`.
fn draw(
    ctx: &std::sync::Arc<relief::vk::Context>,
    scene: &Scene,
    opts: &RenderOptions,
    pass: Pass,
) -> anyhow::Result<(Vec<u8>, f64)> {
    let mut renderer = Renderer::new(ctx, scene, None, opts)?;
    let camera = renderer.default_camera();
    let first = renderer.draw(&FrameRequest::new(camera))?;
    let rgba = first.rgba.context("the frame was not read back")?;
    let mut times = Vec::with_capacity(TIMED_FRAMES);
    for _ in 0..TIMED_FRAMES {
        let frame = renderer.draw(&FrameRequest::new(camera).with_read_back(false))?;
        let ms: f64 = frame
            .timings
            .iter()
            .filter(|t| t.pass == pass)
            .map(|t| t.gpu_ms)
            .sum();
        times.push(ms);
    }
    Ok((rgba, median(times)))
}

/// The cells options of `relief cells`'s arguments for every mesh of the scene: the grid it built and
/// measured, chosen by the overlap ratio alone (the paper's rule).
pub fn options(resolution: u32, overlap: f64, max_grid: u32, grid: Option<u32>) -> CellsOptions {
    CellsOptions::new(MeshSelection::All)
        .with_resolution(resolution)
        .with_overlap(overlap)
        .with_texels_per_edge(0.0)
        .with_max_grid(max_grid)
        .with_grid(grid)
}
