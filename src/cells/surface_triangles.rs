//! Which triangle of the mesh each texel's line meets: the index the cells pass looks the shading attributes up
//! by ([`super::attributes`]). Layers are in the maps' order, which is [`super::PackedComplex`]'s.
//!
//! Texels whose line crosses nothing take the triangle of the nearest texel that does: a ray that stops beside a
//! silhouette or in a corner of a cell still finds a triangle near it to shade from.

use super::distance_map::{CellMaps, FaceMap, SurfacePoint};
use super::parallel::map_in_parallel;

/// What a texel holds on a face whose lines all miss the surface; the pass then tries its neighbour cells.
pub const NO_TRIANGLE: u32 = u32::MAX;

/// Every domain face's texels, `resolution`^2 a layer: the index `source` gives the triangle each texel's line
/// meets (a [`SurfacePoint`]'s triangle is the closed mesh's; `source` maps it to the caller's order).
pub fn surface_triangle_maps(maps: &CellMaps, source: impl Fn(u32) -> u32 + Sync) -> Vec<u32> {
    let layers = map_in_parallel(&maps.faces, |map| layer(map, maps.resolution, &source));
    layers.into_iter().flatten().collect()
}

fn layer(map: &FaceMap, resolution: u32, source: &impl Fn(u32) -> u32) -> Vec<u32> {
    let r = resolution as usize;
    let mut texels: Vec<Option<u32>> = map
        .surface
        .iter()
        .map(|point: &SurfacePoint| point.is_hit().then(|| source(point.triangle)))
        .collect();
    if texels.iter().all(Option::is_none) {
        return vec![NO_TRIANGLE; r * r];
    }
    // Grown one ring of texels at a time from the ones that meet the surface.
    while texels.iter().any(Option::is_none) {
        let previous = texels.clone();
        for (i, texel) in texels.iter_mut().enumerate().filter(|(_, t)| t.is_none()) {
            let (a, b) = (i % r, i / r);
            let neighbours = [
                (a > 0).then(|| i - 1),
                (a + 1 < r).then(|| i + 1),
                (b > 0).then(|| i - r),
                (b + 1 < r).then(|| i + r),
            ];
            *texel = neighbours.into_iter().flatten().find_map(|k| previous[k]);
        }
    }
    texels.into_iter().flatten().collect()
}

#[cfg(test)]
mod tests {
    use super::super::distance_map::choose_grid;
    use super::super::mesh::shapes::icosphere;
    use super::super::mesh::ClosedMesh;
    use super::*;

    #[test]
    fn every_texel_that_meets_the_sphere_names_the_triangle_it_meets() {
        let (positions, triangles) = icosphere([0.0; 3], 1.0, 3);
        let mesh = ClosedMesh::new("sphere", &positions, &triangles).expect("closed");
        let (_, maps) = choose_grid(&mesh, 16, 0.05, 8);
        // An order of the caller's own: the closed mesh's triangles reversed.
        let count = mesh.triangles().len() as u32;
        let texels = surface_triangle_maps(&maps, |t| count - 1 - t);
        let per_layer = (maps.resolution as usize).pow(2);
        assert_eq!(texels.len(), maps.faces.len() * per_layer);
        let mut met = 0;
        for (map, layer) in maps.faces.iter().zip(texels.chunks(per_layer)) {
            for (point, &texel) in map.surface.iter().zip(layer) {
                assert!(texel < count || texel == NO_TRIANGLE, "{texel}");
                if point.is_hit() {
                    assert_eq!(texel, count - 1 - point.triangle);
                    met += 1;
                }
            }
        }
        assert!(met > 1000, "only {met} texels met the sphere");
    }

    #[test]
    fn texels_without_a_surface_point_take_their_nearest_neighbours() {
        let none = SurfacePoint {
            triangle: SurfacePoint::NONE,
            barycentric: [0.0; 2],
        };
        let hit = |t: u32| SurfacePoint {
            triangle: t,
            barycentric: [0.25, 0.5],
        };
        // 3x3: only the middle-left and the top-right texels meet the surface.
        let mut surface = vec![none; 9];
        surface[3] = hit(7);
        surface[2] = hit(9);
        let map = FaceMap {
            cell: [0, 0, 0],
            face: super::super::Face::ALL[0],
            distances: vec![0.5; 9],
            inside_at_face: Vec::new(),
            surface: surface.clone(),
        };
        // Row by row: each texel's nearest texel with a point (the first found in -x, +x, -y, +y order on a tie).
        assert_eq!(layer(&map, 3, &|t| t), vec![7, 9, 9, 7, 7, 9, 7, 7, 9]);
        let empty = FaceMap {
            surface: vec![none; 9],
            ..map
        };
        assert_eq!(layer(&empty, 3, &|t| t), vec![NO_TRIANGLE; 9]);
    }
}
