//! The cells pass (Apaza and Andujar): meshes drawn through their cell complexes. Built once per scene:
//! for each complex the plan lists, the mesh is gathered in world space and checked closed, the
//! grid chosen by doubling (`cells::choose_grid_within`), the distance maps and each texel's
//! triangle sampled on the CPU and uploaded as storage buffers with the mesh's triangle corners and
//! the faces of the grey cells that border the outside; one pipeline (`cells.vert`, `cells.frag`) draws them all. Its set 0 and set 1 are the
//! surface pass's plain frame set and the mesh's material set.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::{Mat4, Vec3};
use serde::Serialize;

use super::cells_plan::CellsPlan;
use super::complex_buffers::ComplexBuffers;
use crate::cells::{
    choose_grid_within, fixed_grid, surface_triangle_maps, texel_size, CellGrid, CellMaps,
    ClosedMesh, Colour, Face, GridStop, MarchSettings, MeshSelection, PackedComplex, SceneMesh,
    MAP_MEMORY_LIMIT,
};
use crate::render::kit::draw_push::DrawPush;
use crate::render::kit::formats::scene_extra_formats;
use crate::render::kit::formats::DEPTH_FORMAT;
use crate::render::kit::formats::HDR_FORMAT;
use crate::render::kit::render_error::RenderError;
use crate::render::kit::set_layouts::{material_layout, plain_frame_layout};
use crate::render::plan::frame_plan::Plan;
use crate::render::shader_interface::{
    CellsUniform, BINDING_CELLS_CELLS, BINDING_CELLS_CORNERS, BINDING_CELLS_GREY,
    BINDING_CELLS_MAPS, BINDING_CELLS_PARAMS, BINDING_CELLS_SURFACE_TRIANGLES, LOCATION_POSITION,
    SPEC_SHADOW_FILTER,
};
use crate::render::shadows::shadow_plan::shadow_filter_max;
use crate::scene::Scene;
use crate::shaders;
use crate::vk::{
    graphics_pipeline, Bind, Buffer, Context, DescriptorLayout, DescriptorPool, DescriptorSet,
    GraphicsDesc, Pipeline, Recording, SpecConstants, VkError, VkResult,
};

/// How meshes become cell complexes (`relief render --cells`). Built from
/// [`CellsOptions::new`] and the `with_*` setters.
#[derive(Debug, Clone, PartialEq)]
#[non_exhaustive]
pub struct CellsOptions {
    /// Which meshes: all (one complex per mesh name) or those of one name.
    pub selection: MeshSelection,
    /// Texels a side of each domain face's maps.
    pub resolution: u32,
    /// The grid doubles while the maps' overlap ratio is above this.
    pub overlap: f64,
    /// The grid also doubles until the mesh's median edge spans at least this many map texels, so that the
    /// maps follow the mesh's own detail (0: the overlap ratio alone, as the paper chooses).
    pub texels_per_edge: f64,
    /// The largest grid (cells a side) the doubling may reach.
    pub max_grid: u32,
    /// A fixed grid (cells a side) instead of the doubling.
    pub grid: Option<u32>,
}

with_setters!(CellsOptions {
    with_selection => selection: MeshSelection,
    with_resolution => resolution: u32,
    with_overlap => overlap: f64,
    with_texels_per_edge => texels_per_edge: f64,
    with_max_grid => max_grid: u32,
    with_grid => grid: Option<u32>,
});

impl CellsOptions {
    /// Every mesh named `selection`, with the defaults of `relief cells`.
    pub fn new(selection: MeshSelection) -> CellsOptions {
        CellsOptions {
            selection,
            resolution: 32,
            overlap: 0.05,
            texels_per_edge: 2.0,
            max_grid: 32,
            grid: None,
        }
    }
}

/// What was built for one complex, for `--explain`.
#[derive(Debug, Clone, Serialize)]
pub struct BuiltComplex {
    /// The name of the meshes it replaces.
    pub name: String,
    /// Triangles of the mesh the complex was built from.
    pub triangles: usize,
    /// Cells a side.
    pub grid: u32,
    /// Cells the surface crosses; only these hold maps.
    pub grey_cells: usize,
    /// Domain faces of the grey cells, one distance map each.
    pub domain_faces: usize,
    /// Texels a side of each domain face's maps.
    pub resolution: u32,
    /// Why the grid's doubling stopped.
    pub grid_stop: String,
    /// The faces drawn: grey cells' faces on the complex's outside.
    pub faces_drawn: usize,
    /// Distance maps as the GPU reads them (16-bit texels).
    pub distance_bytes: u64,
    /// What the pass shades from: each texel's triangle (4 bytes a texel) and the mesh's triangle corners
    /// (48 bytes a corner).
    pub attribute_bytes: u64,
    /// CPU wall time of classifying, sampling and packing.
    pub build_ms: f64,
}

/// Halvings of the step in which a pixel's ray goes inside. A step is half a map texel, 1/128 of
/// a cell at 64^2 maps; 12 halvings leave 1/500,000 of a cell, far below any pixel, where the
/// march's own 24 (kept by `relief cells` and the ray pass, which measure the complex's hits in
/// f64 and f32) cost the render a quarter of its time on a one-cell sphere (250 against 186 ms
/// at 512^2 on lavapipe) for no change in the image (mean channel difference to the raster
/// 0.043 either way).
const RENDER_REFINEMENTS: u32 = 12;

impl CellsUniform {
    fn of(packed: &PackedComplex) -> CellsUniform {
        let settings = MarchSettings::default();
        CellsUniform {
            origin_size: [
                packed.origin[0],
                packed.origin[1],
                packed.origin[2],
                packed.cell_size,
            ],
            n: packed.n,
            resolution: packed.resolution,
            refinements: RENDER_REFINEMENTS.min(settings.refinements),
            samples_per_texel: settings.samples_per_texel as f32,
        }
    }
}

/// Set 2: the complex's arrays (bindings 0-2), its uniform (3), its texels' triangles (4) and the triangles'
/// corners (5).
const CELLS_SET_BINDINGS: [(u32, vk::DescriptorType); 6] = [
    (BINDING_CELLS_CELLS, vk::DescriptorType::STORAGE_BUFFER),
    (BINDING_CELLS_GREY, vk::DescriptorType::STORAGE_BUFFER),
    (BINDING_CELLS_MAPS, vk::DescriptorType::STORAGE_BUFFER),
    (BINDING_CELLS_PARAMS, vk::DescriptorType::UNIFORM_BUFFER),
    (
        BINDING_CELLS_SURFACE_TRIANGLES,
        vk::DescriptorType::STORAGE_BUFFER,
    ),
    (BINDING_CELLS_CORNERS, vk::DescriptorType::STORAGE_BUFFER),
];

struct ComplexDraw {
    faces: Buffer,
    indices: Buffer,
    /// Each outer face's centre (six indices a face, in order).
    face_centres: Vec<Vec3>,
    material: usize,
    set: DescriptorSet,
    _arrays: ComplexBuffers,
    _uniform: Buffer,
    _surface_triangles: Buffer,
    _corners: Buffer,
}

/// The complexes of a scene and the pipeline that draws them; empty when the plan has none.
pub struct CellsPass {
    pipeline: Option<Pipeline>,
    draws: Vec<ComplexDraw>,
    built: Vec<BuiltComplex>,
    _pool: Option<DescriptorPool>,
    _layouts: Vec<DescriptorLayout>,
}

impl CellsPass {
    /// Builds the complexes `plan.cells` lists with `options`; nothing at all when it lists none.
    pub fn new(
        ctx: &Arc<Context>,
        scene: &Scene,
        plan: &Plan,
        options: Option<&CellsOptions>,
    ) -> Result<CellsPass, RenderError> {
        let Some(options) = options.filter(|_| !plan.cells.is_empty()) else {
            return Ok(CellsPass {
                pipeline: None,
                draws: Vec::new(),
                built: Vec::new(),
                _pool: None,
                _layouts: Vec::new(),
            });
        };
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let cells_layout = DescriptorLayout::new(ctx, &CELLS_SET_BINDINGS, stages, "cells layout")?;
        let frame_layout = plain_frame_layout(ctx)?;
        let material_layout = material_layout(ctx)?;
        let sets = [&frame_layout, &material_layout, &cells_layout];
        let samples = plan.msaa.samples;
        let pipeline = create_pipeline(
            ctx,
            &sets,
            shadow_filter_max(plan),
            samples,
            scene_extra_formats(plan.gbuffer, plan.deferred),
        )?;
        let count = plan.cells.len() as u32;
        let pool = DescriptorPool::new(ctx, count, 4 * count, "cells sets")?;
        let mut draws = Vec::with_capacity(plan.cells.len());
        let mut built = Vec::with_capacity(plan.cells.len());
        for c in &plan.cells {
            let (draw, stats) = build_complex(ctx, scene, c, options, &pool, &cells_layout)?;
            draws.push(draw);
            built.push(stats);
        }
        Ok(CellsPass {
            pipeline: Some(pipeline),
            draws,
            built,
            _pool: Some(pool),
            _layouts: vec![cells_layout, frame_layout, material_layout],
        })
    }

    /// What was built, one entry per complex.
    pub fn built(&self) -> &[BuiltComplex] {
        &self.built
    }

    /// Whether there is anything to draw.
    pub fn is_empty(&self) -> bool {
        self.draws.is_empty()
    }

    /// Records every complex's draw with `frame_set` as set 0 and its material's set (from
    /// `material_set`) as set 1. Rendering must have begun with the targets' formats.
    ///
    /// Each complex's faces are drawn nearest `eye` first: a face behind a hit that a nearer face
    /// has written is then rejected by the early depth test instead of marching its ray again
    /// (on a 4^3 torus a pixel lies behind several outer faces).
    pub fn record(
        &self,
        rec: &Recording,
        frame_set: DescriptorSet,
        eye: Vec3,
        material_set: impl Fn(usize) -> Option<DescriptorSet>,
    ) -> VkResult<()> {
        let Some(pipeline) = &self.pipeline else {
            return Ok(());
        };
        for draw in &self.draws {
            let material = material_set(draw.material).ok_or_else(|| {
                VkError::Invalid(format!("material {} has no set", draw.material))
            })?;
            pipeline.bind(rec, Some(&frame_set));
            pipeline.bind_set(rec, 1, &material);
            pipeline.bind_set(rec, 2, &draw.set);
            // The complex is in world space: draw.glsl's push constants (unread) get the identity.
            pipeline.push(rec, bytemuck::bytes_of(&DrawPush::of(Mat4::IDENTITY)))?;
            rec.bind_mesh(&draw.faces, &draw.indices);
            let mut order: Vec<(f32, u32)> = draw
                .face_centres
                .iter()
                .enumerate()
                .map(|(k, c)| (c.distance_squared(eye), k as u32))
                .collect();
            order.sort_by(|a, b| a.0.total_cmp(&b.0));
            for (_, face) in order {
                rec.draw_indexed_range(6, face * 6);
            }
        }
        Ok(())
    }
}

/// Gathers, builds and uploads one complex.
fn build_complex(
    ctx: &Arc<Context>,
    scene: &Scene,
    plan: &CellsPlan,
    options: &CellsOptions,
    pool: &DescriptorPool,
    layout: &DescriptorLayout,
) -> Result<(ComplexDraw, BuiltComplex), RenderError> {
    let started = Instant::now();
    let gathered = SceneMesh::gather(scene, &plan.meshes, &format!("--cells {}", plan.name))?;
    let (grid, maps, stop) = complex_grid(&gathered.mesh, plan, options)?;
    let packed = PackedComplex::new(&grid, &maps);
    let surface_triangles = surface_triangle_maps(&maps, |t| gathered.source(t));
    let corners = gathered.corners();
    let (vertices, indices) = outer_faces(&grid);
    let build_ms = started.elapsed().as_secs_f64() * 1e3;
    let name = &plan.name;
    let surface_bytes: &[u8] = bytemuck::cast_slice(&surface_triangles);
    let corner_bytes: &[u8] = bytemuck::cast_slice(&corners);
    check_buffer_sizes(ctx, name, &[surface_bytes, corner_bytes], &packed)?;
    let arrays = ComplexBuffers::upload(ctx, &packed, name)?;
    let uniform = CellsUniform::of(&packed);
    let uniform = Buffer::with_data(
        ctx,
        bytemuck::bytes_of(&uniform),
        vk::BufferUsageFlags::UNIFORM_BUFFER,
        &format!("{name} cells uniform"),
    )?;
    let storage = |bytes: &[u8], what: &str| {
        Buffer::with_data(
            ctx,
            &ComplexBuffers::nonempty(bytes),
            vk::BufferUsageFlags::STORAGE_BUFFER,
            &format!("{name} {what}"),
        )
    };
    let surface_buffer = storage(surface_bytes, "cell texel triangles")?;
    let corner_buffer = storage(corner_bytes, "cell triangle corners")?;
    let mut binds = arrays.binds().to_vec();
    binds.push(Bind::Uniform(BINDING_CELLS_PARAMS, &uniform));
    binds.push(Bind::Storage(
        BINDING_CELLS_SURFACE_TRIANGLES,
        &surface_buffer,
    ));
    binds.push(Bind::Storage(BINDING_CELLS_CORNERS, &corner_buffer));
    let set = pool.allocate(layout, &binds)?;
    let faces = Buffer::with_data(
        ctx,
        bytemuck::cast_slice(&vertices),
        vk::BufferUsageFlags::VERTEX_BUFFER,
        &format!("{name} cell faces"),
    )?;
    let index_buffer = Buffer::with_data(
        ctx,
        bytemuck::cast_slice(&indices),
        vk::BufferUsageFlags::INDEX_BUFFER,
        &format!("{name} cell face indices"),
    )?;
    let stats = BuiltComplex {
        name: name.clone(),
        triangles: gathered.mesh.triangles().len(),
        grid: grid.n(),
        grey_cells: maps.grey_cells,
        domain_faces: maps.faces.len(),
        resolution: maps.resolution,
        grid_stop: grid_stop(
            stop,
            &maps,
            options,
            gathered.mesh.median_edge() / texel_size(&grid, maps.resolution),
        ),
        faces_drawn: indices.len() / 6,
        distance_bytes: (packed.maps.len() * 4) as u64,
        attribute_bytes: (surface_bytes.len() + corner_bytes.len()) as u64,
        build_ms,
    };
    // Four corners a face, in order (outer_faces).
    let face_centres = vertices
        .chunks_exact(4)
        .map(|quad| quad.iter().map(|&v| Vec3::from(v)).sum::<Vec3>() * 0.25)
        .collect();
    let draw = ComplexDraw {
        faces,
        face_centres,
        indices: index_buffer,
        material: plan.material,
        set,
        _arrays: arrays,
        _uniform: uniform,
        _surface_triangles: surface_buffer,
        _corners: corner_buffer,
    };
    Ok((draw, stats))
}

/// The complex's grid: `options.grid` cells a side when given, else refined until the maps overlap little
/// enough, with why it stopped.
fn complex_grid(
    mesh: &ClosedMesh,
    plan: &CellsPlan,
    options: &CellsOptions,
) -> Result<(CellGrid, CellMaps, Option<GridStop>), RenderError> {
    Ok(match options.grid {
        Some(n) => {
            let (grid, maps) = fixed_grid(mesh, n, options.resolution).map_err(|source| {
                RenderError::CellsTooLarge {
                    name: plan.name.clone(),
                    source,
                }
            })?;
            (grid, maps, None)
        }
        None => {
            let max_texel = if options.texels_per_edge > 0.0 {
                mesh.median_edge() / options.texels_per_edge
            } else {
                f64::INFINITY
            };
            let (grid, maps, stop) = choose_grid_within(
                mesh,
                options.resolution,
                options.overlap,
                max_texel,
                options.max_grid,
                MAP_MEMORY_LIMIT,
            );
            (grid, maps, Some(stop))
        }
    })
}

/// Refuses a complex whose largest storage buffer the device cannot bind.
fn check_buffer_sizes(
    ctx: &Context,
    name: &str,
    shading: &[&[u8]],
    packed: &PackedComplex,
) -> Result<(), RenderError> {
    let limit = u64::from(ctx.info().max_storage_buffer_range);
    let largest = shading.iter().map(|bytes| bytes.len() as u64).fold(
        std::mem::size_of_val(packed.maps.as_slice()) as u64,
        u64::max,
    );
    if largest > limit {
        return Err(RenderError::CellsBufferTooLarge {
            name: name.to_owned(),
            mib: largest >> 20,
            limit_mib: limit >> 20,
        });
    }
    Ok(())
}

/// Why the grid is the size it is, for the run's notes.
fn grid_stop(
    stop: Option<GridStop>,
    maps: &CellMaps,
    options: &CellsOptions,
    median_edge_texels: f64,
) -> String {
    match stop {
        None => "a fixed grid".to_owned(),
        Some(GridStop::Settled) => format!(
            "overlap ratio {:.3} at most {}, the median edge {:.1} texels (at least {})",
            maps.overlap_ratio, options.overlap, median_edge_texels, options.texels_per_edge
        ),
        Some(GridStop::MaxGrid) => format!(
            "largest grid {} reached (overlap ratio {:.3})",
            options.max_grid, maps.overlap_ratio
        ),
        Some(GridStop::Memory { next_n, bytes }) => {
            format!("a {next_n}^3 grid's maps would take {} MiB", bytes >> 20)
        }
    }
}

/// The faces of grey cells whose neighbour is white or beyond the grid, in world space, wound
/// counter-clockwise seen from outside: a ray from outside enters the complex's grey cells
/// through one of them (a black cell borders no white one).
fn outer_faces(grid: &CellGrid) -> (Vec<[f32; 3]>, Vec<u32>) {
    let mut vertices = Vec::new();
    let mut indices = Vec::new();
    let size = grid.cell_size();
    let origin = grid.origin();
    for cell in grid.grey_cells() {
        for face in Face::ALL {
            let open = grid
                .neighbour(cell, face)
                .is_none_or(|next| grid.colour(next) == Colour::White);
            if !open {
                continue;
            }
            let (a, u, v) = (face.axis, (face.axis + 1) % 3, (face.axis + 2) % 3);
            let corner = |s: u32, t: u32| {
                let mut local = [0u32; 3];
                local[a] = u32::from(face.positive);
                local[u] = s;
                local[v] = t;
                std::array::from_fn(|k| (origin[k] + size * f64::from(cell[k] + local[k])) as f32)
            };
            let base = vertices.len() as u32;
            // e_u x e_v = e_a: counter-clockwise about +a in (u, v) order.
            let quad = [corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)];
            vertices.extend(quad);
            let order: [u32; 6] = if face.positive {
                [0, 1, 2, 0, 2, 3]
            } else {
                [0, 2, 1, 0, 3, 2]
            };
            indices.extend(order.map(|k| base + k));
        }
    }
    (vertices, indices)
}

fn create_pipeline(
    ctx: &Arc<Context>,
    set_layouts: &[&DescriptorLayout],
    shadow_filter: u32,
    samples: u32,
    extra_colors: &[vk::Format],
) -> VkResult<Pipeline> {
    let missing = |k: &str| VkError::Invalid(format!("no compiled shader {k}"));
    let vertex = shaders::spirv("cells.vert").ok_or_else(|| missing("cells.vert"))?;
    let fragment = shaders::spirv("cells.frag").ok_or_else(|| missing("cells.frag"))?;
    let attributes = [vk::VertexInputAttributeDescription {
        location: LOCATION_POSITION,
        binding: 0,
        format: vk::Format::R32G32B32_SFLOAT,
        offset: 0,
    }];
    let desc = GraphicsDesc {
        vertex,
        fragment,
        fragment_spec: &SpecConstants::default().u32(SPEC_SHADOW_FILTER, shadow_filter),
        vertex_stride: 12,
        attributes: &attributes,
        color_format: HDR_FORMAT,
        // The cells pass leaves the G-buffer as cleared.
        extra_colors,
        writes_extra: false,
        depth_format: DEPTH_FORMAT,
        cull: vk::CullModeFlags::BACK,
        set_layouts,
        push_bytes: std::mem::size_of::<DrawPush>() as u32,
        blend: false,
        samples,
    };
    graphics_pipeline(ctx, &desc, "cells")
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::cells::{shapes, ClosedMesh};

    fn cell_of(grid: &CellGrid, p: glam::Vec3) -> [u32; 3] {
        let o = grid.origin();
        std::array::from_fn(|k| ((f64::from(p[k]) - o[k]) / grid.cell_size()).floor() as u32)
    }

    #[test]
    fn outer_faces_close_the_grey_shell_and_face_outward() {
        let (positions, triangles) = shapes::icosphere([0.0; 3], 1.0, 2);
        let mesh = ClosedMesh::new("sphere", &positions, &triangles).unwrap();
        let grid = CellGrid::classify(&mesh, 4);
        let (vertices, indices) = outer_faces(&grid);
        assert_eq!(indices.len() % 6, 0);
        assert!(!indices.is_empty());
        for tri in indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| glam::Vec3::from(vertices[tri[k] as usize]));
            let normal = (b - a).cross(c - a).normalize();
            // A step off the face along its winding's normal lands in the white cell or beyond
            // the grid: outside the sphere.
            let out = (a + b + c) / 3.0 + normal * 0.05;
            let winding = mesh.winding_number(out.to_array().map(f64::from));
            assert!(winding.abs() < 0.5, "{a} {b} {c}: {winding}");
            let inward = (a + b + c) / 3.0 - normal * 0.05;
            assert_ne!(
                grid.colour(cell_of(&grid, inward)),
                Colour::White,
                "the face belongs to a grey cell behind it"
            );
        }
    }
}
