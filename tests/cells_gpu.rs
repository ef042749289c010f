//! The GPU march through cell complexes (`cells_trace.comp`) against exact ray/triangle hits and
//! against the CPU march it mirrors, on the procedural test shapes.

mod common;

use relief::cells::{
    choose_grid, compare_hits, parallel_rays, shapes, CellComplex, CellGrid, CellMaps, ClosedMesh,
    MarchSettings, PackedComplex,
};
use relief::render::march_cells_on_gpu;

fn mesh(shape: (Vec<[f64; 3]>, Vec<[u32; 3]>), name: &str) -> ClosedMesh {
    ClosedMesh::new(name, &shape.0, &shape.1).expect("closed")
}

/// Marches 32x32 rays along `dir` on the GPU and on the CPU; checks the GPU's hits against the exact
/// ones (as the CPU tests do) and against the CPU's.
fn check(
    ctx: &std::sync::Arc<relief::vk::Context>,
    what: &str,
    shape: &ClosedMesh,
    grid: &CellGrid,
    maps: &CellMaps,
    dir: [f64; 3],
) {
    let rays = parallel_rays(shape, dir, 32);
    let settings = MarchSettings::default();
    let gpu = march_cells_on_gpu(ctx, &PackedComplex::new(grid, maps), &rays, settings)
        .expect("gpu march");
    let (m, _) = compare_hits(
        shape,
        grid,
        maps.resolution,
        &rays,
        &gpu.hits,
        gpu.gpu_ms / 1e3,
    );
    eprintln!("{what}: {m:?}");
    assert!(m.solid > 100, "{what}: {m:?}");
    assert_eq!(m.missed_solid, 0, "{what}: rays through the solid missed");
    assert!(
        m.mean_error < 0.01,
        "{what}: mean error {} cell sides",
        m.mean_error
    );
    assert!(
        m.max_error < 1.0,
        "{what}: a hit {} cell sides off",
        m.max_error
    );
    assert!(m.false_hit_max_distance < 0.1, "{what}: {m:?}");
    // The CPU march, in f64 over f32 maps, against the GPU's in f32 over 15-bit maps.
    let complex = CellComplex::new(grid, maps);
    let mut differ = 0;
    for (&(origin, dir), gpu_hit) in rays.iter().zip(&gpu.hits) {
        let cpu = complex.march(origin, dir, settings);
        match (cpu, gpu_hit) {
            (Some(c), Some((t, _))) if (c.t - t).abs() <= 0.01 * grid.cell_size() => {}
            (None, None) => {}
            _ => differ += 1,
        }
    }
    assert!(
        differ * 100 <= rays.len(),
        "{what}: {differ} of {} rays differ from the CPU march",
        rays.len()
    );
}

#[test]
fn gpu_march_meets_the_shapes_as_the_cpu_march_does() {
    let Some(ctx) = common::device("cells_gpu") else {
        return;
    };
    let sphere = mesh(shapes::icosphere([0.1, -0.2, 0.3], 1.0, 3), "sphere");
    for n in [1, 4] {
        let grid = CellGrid::classify(&sphere, n);
        let maps = CellMaps::sample(&sphere, &grid, 24);
        check(
            &ctx,
            &format!("sphere, n = {n}"),
            &sphere,
            &grid,
            &maps,
            [0.3, -0.5, -1.0],
        );
    }
    let ring = mesh(shapes::torus([0.0, 0.2, 0.0], 1.0, 0.4, 32, 16), "torus");
    let (grid, maps) = choose_grid(&ring, 24, 0.05, 16);
    for dir in [[0.1, -0.2, -1.0], [1.0, 0.3, 0.2]] {
        check(
            &ctx,
            &format!("torus, n = {}, {dir:?}", grid.n()),
            &ring,
            &grid,
            &maps,
            dir,
        );
    }
    let blob = mesh(
        shapes::bumpy_sphere([0.0; 3], 1.0, 4, 0.2, 6.0),
        "bumpy sphere",
    );
    let grid = CellGrid::classify(&blob, 4);
    let maps = CellMaps::sample(&blob, &grid, 24);
    check(
        &ctx,
        "bumpy sphere, n = 4",
        &blob,
        &grid,
        &maps,
        [-0.4, 0.2, -1.0],
    );
    common::assert_no_validation_errors(&ctx);
}
