//! `relief cells`: a closed mesh (the meshes of a glTF file, or a procedural shape) replaced by a cubic cell
//! complex (Apaza and Andujar): the grid chosen as the paper does, the grey cells' distance maps, statistics like the
//! paper's Table 1, and the complex's hits measured against exact ray/triangle intersection: the CPU march, and
//! with `--gpu` the GPU's (its rays per second, as the paper's Table 2 reports them).

use std::io::BufWriter;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::time::Instant;

use anyhow::Context as _;
use clap::{Args, ValueEnum};
use relief::bench::write_npy_f32;
use relief::cells::{
    choose_grid_within, compare_hits, fixed_grid, measure_hits, parallel_rays, rebuild, shapes,
    CellGrid, CellMaps, ClosedMesh, GridStop, HitAgreement, MarchSettings, MeshSelection,
    PackedComplex, SceneMesh, MAP_MEMORY_LIMIT,
};
use relief::render::march_cells_on_gpu;
use relief::scene::{load_gltf, Mesh, Scene, SceneOptions};
use relief::vk::Context;
use serde_json::json;

use super::cells_compare::RenderComparison;
use super::{cells_compare, cells_lookup};

/// Procedural closed meshes with known shapes.
#[derive(Clone, Copy, ValueEnum)]
enum Shape {
    /// A subdivided icosahedron (5120 triangles) of radius 1.
    Sphere,
    /// A ring of radius 1 around the z axis, its tube 0.4 thick (2048 triangles).
    Torus,
    /// A sphere with bumps and folds of a fifth of its radius (20480 triangles).
    BumpySphere,
}

#[derive(Args)]
pub struct CellsArgs {
    /// A glTF file whose meshes (in world space, merged) form one closed surface.
    #[arg(required_unless_present = "shape", conflicts_with = "shape")]
    mesh: Option<PathBuf>,
    /// A procedural mesh instead of a file.
    #[arg(long, value_enum)]
    shape: Option<Shape>,
    /// Only the glTF meshes with this name.
    #[arg(long, value_name = "NAME")]
    node: Option<String>,
    /// Folder for cells.json (statistics), maps.png (every distance map, 16-bit), lookup.json
    /// (each grey cell's case, projection and maps in the atlas) and, with --dump, rays.npy.
    #[arg(long)]
    out: PathBuf,
    /// Texels on a side of each distance map.
    #[arg(long, default_value_t = 64)]
    resolution: u32,
    /// The grid doubles from 1 while the maps' overlap ratio (hidden crossings over all) is above this.
    #[arg(long, default_value_t = 0.05)]
    overlap: f64,
    /// Largest grid size the doubling may reach.
    #[arg(long, default_value_t = 64)]
    max_grid: u32,
    /// A fixed grid size instead of the paper's choice.
    #[arg(long)]
    grid: Option<u32>,
    /// Side of the square of parallel rays measured against the exact hits (0: none).
    #[arg(long, default_value_t = 128)]
    rays: u32,
    /// Direction of those rays, "x,y,z".
    #[arg(long, default_value = "0.3,-0.5,-1")]
    dir: String,
    /// Write every ray (exact t, chord, marched t, samples) to OUT/rays.npy, shape (rays, rays, 4).
    #[arg(long)]
    dump: bool,
    /// Write the surface rebuilt from the distance maps as a Wavefront OBJ file.
    #[arg(long, value_name = "FILE")]
    mesh_out: Option<PathBuf>,
    /// Mip level of the maps the rebuilt mesh is made from (0: full resolution).
    #[arg(long, default_value_t = 0)]
    mesh_level: u32,
    /// Also march the rays on the GPU: the same measurement, and the GPU's rays per second.
    #[arg(long)]
    gpu: bool,
    /// Also render the mesh through its cells and rasterised at this size (WxH), from the camera
    /// that frames it: OUT/cells.png, raster.png, diff.png, the mean channel difference and the
    /// cells pass's GPU time. The meshes must share one material.
    #[arg(long, value_name = "WxH")]
    render: Option<String>,
    /// Pick the Vulkan device whose name contains this text (with --gpu or --render).
    #[arg(long, value_name = "SUBSTRING")]
    device: Option<String>,
}

/// Reads the mesh the arguments name, checked closed, with the scene that draws it (its meshes
/// under one name, so that `--render` builds one complex of them as this command does).
fn load_mesh(args: &CellsArgs) -> anyhow::Result<(String, ClosedMesh, Scene)> {
    if let Some(shape) = args.shape {
        let (name, (positions, triangles)) = match shape {
            Shape::Sphere => ("sphere", shapes::icosphere([0.0; 3], 1.0, 4)),
            Shape::Torus => ("torus", shapes::torus([0.0; 3], 1.0, 0.4, 64, 16)),
            Shape::BumpySphere => (
                "bumpy sphere",
                shapes::bumpy_sphere([0.0; 3], 1.0, 5, 0.2, 6.0),
            ),
        };
        let mesh = ClosedMesh::new(name, &positions, &triangles)?;
        let scene = cells_compare::shape_scene(name, &mesh);
        return Ok((name.into(), mesh, scene));
    }
    let path = args.mesh.as_deref().context("no mesh given")?;
    let scene = load_gltf(path, &SceneOptions::default())?;
    // Without --node every mesh of the file is one complex.
    let selection = args
        .node
        .clone()
        .map_or(MeshSelection::All, MeshSelection::Named);
    let members: Vec<usize> = selection
        .groups(&scene)
        .into_iter()
        .flat_map(|(_, members)| members)
        .collect();
    let origin = match &args.node {
        Some(name) => format!("{} (meshes named {name:?})", path.display()),
        None => path.display().to_string(),
    };
    if members.is_empty() {
        anyhow::bail!("{origin}: no triangles to build cells from");
    }
    let gathered = SceneMesh::gather(&scene, &members, &origin)?;
    let meshes = members
        .iter()
        .map(|&k| Mesh {
            name: origin.clone(),
            ..scene.meshes[k].clone()
        })
        .collect();
    Ok((origin, gathered.mesh, Scene { meshes, ..scene }))
}

fn parse_dir(text: &str) -> anyhow::Result<[f64; 3]> {
    let parts: Vec<f64> = text
        .split(',')
        .map(|p| p.trim().parse::<f64>())
        .collect::<Result<_, _>>()
        .with_context(|| format!("--dir {text:?}: expected three numbers, \"x,y,z\""))?;
    match parts[..] {
        [x, y, z] if [x, y, z].iter().all(|c| c.is_finite()) && (x, y, z) != (0.0, 0.0, 0.0) => {
            Ok([x, y, z])
        }
        _ => anyhow::bail!("--dir {text:?}: expected a finite, non-zero direction \"x,y,z\""),
    }
}

/// Every distance map as one 16-bit grey atlas: tiles of `resolution`^2 in rows, distances over the longest
/// possible line (a cell's diagonal, sqrt 3 sides) scaled to 0..65535 as the paper's 16-bit maps store them.
fn write_atlas(path: &Path, maps: &CellMaps) -> anyhow::Result<(u32, u32)> {
    let r = maps.resolution;
    let count = maps.faces.len().max(1) as u32;
    let columns = cells_lookup::atlas_columns(maps.faces.len());
    let rows = count.div_ceil(columns);
    let (w, h) = (columns * r, rows * r);
    let mut atlas = image::ImageBuffer::<image::Luma<u16>, Vec<u16>>::new(w, h);
    let full = 3f64.sqrt();
    for (i, map) in maps.faces.iter().enumerate() {
        let (tx, ty) = ((i as u32 % columns) * r, (i as u32 / columns) * r);
        for (t, &d) in map.distances.iter().enumerate() {
            let value = (f64::from(d) / full * 65535.0).round().clamp(0.0, 65535.0) as u16;
            atlas.put_pixel(tx + t as u32 % r, ty + t as u32 / r, image::Luma([value]));
        }
    }
    atlas
        .save(path)
        .with_context(|| format!("writing {}", path.display()))?;
    Ok((w, h))
}

pub fn run(args: &CellsArgs) -> anyhow::Result<()> {
    check_args(args)?;
    let dir = parse_dir(&args.dir)?;
    let render_size = match &args.render {
        Some(text) => Some(super::parse_size("--render", text)?),
        None => None,
    };
    let (name, mesh, scene) = load_mesh(args)?;
    std::fs::create_dir_all(&args.out)
        .with_context(|| format!("creating {}", args.out.display()))?;
    let started = Instant::now();
    let (grid, maps) = build_complex(args, &name, &mesh)?;
    let build_ms = started.elapsed().as_secs_f64() * 1e3;
    let atlas = write_atlas(&args.out.join("maps.png"), &maps)?;
    cells_lookup::write_lookup(&args.out.join("lookup.json"), &grid, &maps)?;
    let measured = if args.rays > 0 {
        Some(measure_on_cpu(args, &mesh, &grid, &maps, dir)?)
    } else {
        None
    };
    let ctx = if (args.gpu && args.rays > 0) || render_size.is_some() {
        Some(super::open_device(args.device.as_deref(), false)?)
    } else {
        None
    };
    let gpu_measured = match (args.gpu, args.rays > 0, &ctx) {
        (true, true, Some(ctx)) => Some(measure_on_gpu(args, ctx, &mesh, &grid, &maps, dir)?),
        _ => None,
    };
    let rendered = match (render_size, &ctx) {
        (Some(size), Some(ctx)) => {
            let options = cells_compare::options(
                args.resolution,
                args.overlap,
                args.max_grid.max(1),
                args.grid,
            );
            let compared = cells_compare::compare(ctx, &scene, options, size, &args.out)?;
            super::check_validation(ctx)?;
            Some(compared)
        }
        _ => None,
    };
    if let Some(path) = &args.mesh_out {
        write_rebuilt_mesh(path, args.mesh_level, &name, &grid, &maps)?;
    }
    let (white, grey, black) = grid.counts();
    let stats = json!({
        "mesh": name,
        "triangles": mesh.triangles().len(),
        "grid": grid.n(),
        "grey_cells": grey,
        "white_cells": white,
        "black_cells": black,
        "domain_faces": maps.faces.len(),
        "map_resolution": maps.resolution,
        "atlas": [atlas.0, atlas.1],
        "bytes": maps.bytes(),
        "overlap_ratio": maps.overlap_ratio,
        "build_ms": build_ms,
        "hits": measured,
        "gpu_hits": gpu_measured,
        "render": rendered,
    });
    let path = args.out.join("cells.json");
    std::fs::write(&path, serde_json::to_string_pretty(&stats)?)
        .with_context(|| format!("writing {}", path.display()))?;
    print_summary(&name, &mesh, &grid, &maps, build_ms, measured.as_ref());
    print_gpu_results(gpu_measured.as_ref(), rendered.as_ref());
    println!("wrote {}", path.display());
    Ok(())
}

/// Refuses flags out of range before anything is loaded.
fn check_args(args: &CellsArgs) -> anyhow::Result<()> {
    if args.resolution == 0 || args.resolution > 4096 {
        anyhow::bail!(
            "--resolution {}: a map needs 1 to 4096 texels a side",
            args.resolution
        );
    }
    if !(args.overlap >= 0.0 && args.overlap <= 1.0) {
        anyhow::bail!("--overlap {}: a ratio from 0 to 1", args.overlap);
    }
    if let Some(n) = args.grid {
        if n == 0 || n > 256 {
            anyhow::bail!("--grid {n}: from 1 to 256 cells a side");
        }
    }
    Ok(())
}

/// The cell grid and its distance maps: `--grid` when given, else the grid refined until the
/// maps overlap less than `--overlap`, with a note when it stopped short of that.
fn build_complex(
    args: &CellsArgs,
    name: &str,
    mesh: &ClosedMesh,
) -> anyhow::Result<(CellGrid, CellMaps)> {
    Ok(match args.grid {
        Some(n) => fixed_grid(mesh, n, args.resolution)
            .map_err(|e| anyhow::anyhow!("{name}: {e}; lower --grid or --resolution"))?,
        None => {
            let (grid, maps, why) = choose_grid_within(
                mesh,
                args.resolution,
                args.overlap,
                f64::INFINITY,
                args.max_grid.max(1),
                MAP_MEMORY_LIMIT,
            );
            match why {
                GridStop::Settled => {}
                GridStop::MaxGrid => eprintln!(
                    "note: the grid stopped at --max-grid {} with overlap {:.3} above --overlap {}",
                    grid.n(),
                    maps.overlap_ratio,
                    args.overlap
                ),
                GridStop::Memory { next_n, bytes } => eprintln!(
                    "note: the grid stopped at {}^3 with overlap {:.3}: a {next_n}^3 grid's maps would take {} MiB (at most {} MiB)",
                    grid.n(),
                    maps.overlap_ratio,
                    bytes >> 20,
                    MAP_MEMORY_LIMIT >> 20
                ),
            }
            (grid, maps)
        }
    })
}

/// Marches `--rays` squared parallel rays through the complex on the CPU against every triangle,
/// dumping each ray's outcome with `--dump`.
fn measure_on_cpu(
    args: &CellsArgs,
    mesh: &ClosedMesh,
    grid: &CellGrid,
    maps: &CellMaps,
    dir: [f64; 3],
) -> anyhow::Result<HitAgreement> {
    eprintln!(
        "marching {0}x{0} rays through the complex and against every triangle...",
        args.rays
    );
    let (agreement, outcomes) = measure_hits(mesh, grid, maps, dir, args.rays);
    if args.dump {
        let values: Vec<f32> = outcomes
            .iter()
            .flat_map(|o| [o.exact, o.chord, o.marched, f64::from(o.samples)].map(|v| v as f32))
            .collect();
        let path = args.out.join("rays.npy");
        let side = args.rays as usize;
        write_npy_f32(&path, &[side, side, 4], &values)
            .with_context(|| format!("writing {}", path.display()))?;
    }
    Ok(agreement)
}

/// The same rays marched by `cells_march.comp`, compared with the exact hits.
fn measure_on_gpu(
    args: &CellsArgs,
    ctx: &Arc<Context>,
    mesh: &ClosedMesh,
    grid: &CellGrid,
    maps: &CellMaps,
    dir: [f64; 3],
) -> anyhow::Result<HitAgreement> {
    let rays = parallel_rays(mesh, dir, args.rays);
    let packed = PackedComplex::new(grid, maps);
    let traced = march_cells_on_gpu(ctx, &packed, &rays, MarchSettings::default())
        .context("marching the rays on the GPU")?;
    super::check_validation(ctx)?;
    let (agreement, _) = compare_hits(
        mesh,
        grid,
        maps.resolution,
        &rays,
        &traced.hits,
        traced.gpu_ms / 1e3,
    );
    Ok(agreement)
}

/// `--mesh-out`: the surface rebuilt from the distance maps at mip `level`, as OBJ.
fn write_rebuilt_mesh(
    path: &Path,
    level: u32,
    name: &str,
    grid: &CellGrid,
    maps: &CellMaps,
) -> anyhow::Result<()> {
    let rebuilt = rebuild(grid, maps, level);
    let file =
        std::fs::File::create(path).with_context(|| format!("creating {}", path.display()))?;
    let comment = format!(
        "{name}: rebuilt from {} distance maps of {}^2 at mip {}",
        maps.faces.len(),
        maps.resolution,
        level
    );
    rebuilt
        .write_obj(&mut BufWriter::new(file), &comment)
        .with_context(|| format!("writing {}", path.display()))?;
    println!(
        "rebuilt mesh: {} triangles -> {}",
        rebuilt.triangles.len(),
        path.display()
    );
    Ok(())
}

/// The lines for the GPU march and the render comparison, when they ran.
fn print_gpu_results(gpu_measured: Option<&HitAgreement>, rendered: Option<&RenderComparison>) {
    if let Some(h) = gpu_measured {
        println!(
            "GPU march: {} of {} rays cross the solid, {} missed; error mean {:.5}, max {:.5} cell sides; {:.0} rays/s",
            h.solid, h.rays, h.missed_solid, h.mean_error, h.max_error, h.rays_per_second
        );
    }
    if let Some(r) = rendered {
        println!(
            "render {}x{}: mean channel difference {:.3} against the rasterised mesh ({:.3} over its {} pixels); cells pass {:.2} ms ({:.2} M pixels/s), rasterised {:.2} ms",
            r.width,
            r.height,
            r.mean_channel_difference,
            r.mean_channel_difference_on_mesh,
            r.covered_pixels,
            r.cells_ms,
            r.pixels_per_second / 1e6,
            r.raster_ms
        );
    }
}

fn print_summary(
    name: &str,
    mesh: &ClosedMesh,
    grid: &CellGrid,
    maps: &CellMaps,
    build_ms: f64,
    hits: Option<&HitAgreement>,
) {
    let (_, grey, _) = grid.counts();
    println!(
        "{name}: {} triangles, grid {n}^3 ({grey} grey cell{}), {} domain faces, maps {r}^2 ({:.0} KiB), overlap {:.3}, built in {build_ms:.0} ms",
        mesh.triangles().len(),
        if grey == 1 { "" } else { "s" },
        maps.faces.len(),
        maps.bytes() as f64 / 1024.0,
        maps.overlap_ratio,
        n = grid.n(),
        r = maps.resolution,
    );
    if let Some(h) = hits {
        println!(
            "hits: {} of {} rays cross the solid, {} missed; error mean {:.5}, p99 {:.5}, max {:.5} cell sides",
            h.solid, h.rays, h.missed_solid, h.mean_error, h.p99_error, h.max_error
        );
        println!(
            "silhouette: {} grazing rays missed, {} hits where the mesh has none (at most {:.4} cell sides from it); {:.1} samples a ray, {:.0} rays/s (CPU, one thread)",
            h.grazing_missed, h.false_hits, h.false_hit_max_distance, h.mean_samples, h.rays_per_second
        );
    }
}
