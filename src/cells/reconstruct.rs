//! A triangle mesh rebuilt from the distance maps (Apaza and Andujar, section 5): each texel whose line crosses the surface
//! gives the point where it does, and every 2x2 block of such texels two triangles. Coarser levels come from the
//! maps' mips (each level averages 2x2 texels whose lines all cross), so a level trades triangles for detail the
//! way a texture's mip chain does. It checks a construction (every point must lie on the mesh) and is what
//! `relief cells --mesh-out` writes.

use std::io::Write;

use super::distance_map::{CellMaps, FaceMap};
use super::grid::CellGrid;
use super::projection::{Image, Projection};

/// Triangles in mesh space; positions shared by the triangles of one face map.
#[derive(Debug, Clone, Default)]
pub struct RebuiltMesh {
    /// Vertex positions in mesh space (the source mesh's units), one per texel whose line crosses the surface.
    pub positions: Vec<[f64; 3]>,
    /// Triangles as indices into `positions`, two per 2x2 block of crossing texels.
    pub triangles: Vec<[u32; 3]>,
}

/// One face map at a mip level: per texel the surface's distance, or `None` where the line crosses nothing.
struct Level {
    side: u32,
    distances: Vec<Option<f64>>,
}

impl Level {
    /// Level 0 of `map`: a texel crosses the surface when its distance is shorter than its whole line.
    fn base(map: &FaceMap, resolution: u32, projection: &Projection) -> Level {
        let distances = (0..resolution * resolution)
            .map(|i| {
                let d = f64::from(map.distances[i as usize]);
                let uv = texel_uv(i % resolution, i / resolution, resolution);
                let full = projection.line_length(map.face, uv);
                (d < full * (1.0 - 1e-6)).then_some(d)
            })
            .collect();
        Level {
            side: resolution,
            distances,
        }
    }

    /// The next mip: the mean of 2x2 texels that all cross (an odd side keeps its last row and column alone).
    fn halve(&self) -> Level {
        let side = self.side.div_ceil(2);
        let mut distances = Vec::with_capacity((side * side) as usize);
        for b in 0..side {
            for a in 0..side {
                let texels: Vec<Option<f64>> = [(0, 0), (1, 0), (0, 1), (1, 1)]
                    .into_iter()
                    .map(|(i, j)| {
                        (
                            (2 * a + i).min(self.side - 1),
                            (2 * b + j).min(self.side - 1),
                        )
                    })
                    .map(|(x, y)| self.distances[(y * self.side + x) as usize])
                    .collect();
                let all: Option<Vec<f64>> = texels.into_iter().collect();
                distances.push(all.map(|d| d.iter().sum::<f64>() / 4.0));
            }
        }
        Level { side, distances }
    }
}

fn texel_uv(a: u32, b: u32, side: u32) -> [f64; 2] {
    [a, b].map(|x| (f64::from(x) + 0.5) / f64::from(side))
}

/// Rebuilds the surface from every face map of `maps` (sampled on `grid`) at mip `level` (0: full resolution).
pub fn rebuild(grid: &CellGrid, maps: &CellMaps, level: u32) -> RebuiltMesh {
    let mut out = RebuiltMesh::default();
    for map in &maps.faces {
        let projection = Projection::for_cell(grid.internal_faces(map.cell));
        let mut mip = Level::base(map, maps.resolution, &projection);
        for _ in 0..level {
            if mip.side == 1 {
                break;
            }
            mip = mip.halve();
        }
        let side = mip.side;
        let mut index = vec![u32::MAX; (side * side) as usize];
        for (i, d) in mip.distances.iter().enumerate() {
            if let Some(distance) = *d {
                let uv = texel_uv(i as u32 % side, i as u32 / side, side);
                let image = Image {
                    face: map.face,
                    uv,
                    distance,
                };
                index[i] = out.positions.len() as u32;
                out.positions
                    .push(grid.from_cell(map.cell, projection.unproject(&image)));
            }
        }
        // Two triangles per 2x2 block of crossing texels: (a, b), (a + 1, b), (a + 1, b + 1) turns from u to v, so it
        // faces along the face's axis where (u, v, axis) is right-handed; the surface faces the face it is seen from.
        let facing = face_frame_is_right_handed(map.face.axis) ^ map.face.positive;
        for b in 0..side.saturating_sub(1) {
            for a in 0..side.saturating_sub(1) {
                let at = |x: u32, y: u32| index[(y * side + x) as usize];
                let quad = [at(a, b), at(a + 1, b), at(a + 1, b + 1), at(a, b + 1)];
                if quad.contains(&u32::MAX) {
                    continue;
                }
                let [p, q, r, s] = quad;
                // An interior cell's face point may lie inside; the surface then faces away from the face.
                let inside = map
                    .inside_at_face
                    .get((b * side + a) as usize)
                    .copied()
                    .unwrap_or(false)
                    && level == 0;
                if facing != inside {
                    out.triangles.extend([[p, r, q], [p, s, r]]);
                } else {
                    out.triangles.extend([[p, q, r], [p, r, s]]);
                }
            }
        }
    }
    out
}

/// Whether a face's span axes (u, v) and its axis, in that order, form a right-handed frame: (y, z, x) and
/// (x, y, z) do, (x, z, y) does not.
fn face_frame_is_right_handed(axis: usize) -> bool {
    axis != 1
}

impl RebuiltMesh {
    /// Writes the mesh as Wavefront OBJ (positions and faces, 1-based).
    pub fn write_obj(&self, out: &mut impl Write, comment: &str) -> std::io::Result<()> {
        writeln!(out, "# {comment}")?;
        for p in &self.positions {
            writeln!(out, "v {} {} {}", p[0], p[1], p[2])?;
        }
        for t in &self.triangles {
            writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1)?;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::super::mesh::shapes::icosphere;
    use super::super::mesh::{norm, sub, ClosedMesh};
    use super::*;

    #[test]
    fn sphere_maps_rebuild_the_sphere_at_every_level() {
        let centre = [0.1, 0.2, -0.1];
        let (positions, triangles) = icosphere(centre, 1.0, 3);
        let sphere = ClosedMesh::new("sphere", &positions, &triangles).expect("closed");
        let grid = CellGrid::classify(&sphere, 4);
        let maps = CellMaps::sample(&sphere, &grid, 16);
        let mut counts = Vec::new();
        for level in 0..3 {
            let rebuilt = rebuild(&grid, &maps, level);
            assert!(!rebuilt.triangles.is_empty(), "level {level}");
            // Every point is a crossing of the polyhedron, which lies between its inscribed sphere and the sphere;
            // a coarser level averages neighbours along a convex surface, so it may sink a little below it.
            let slack = 0.02 * f64::from(level);
            for p in &rebuilt.positions {
                let r = norm(sub(*p, centre));
                assert!(r > 0.98 - slack && r < 1.0 + 1e-6, "level {level}: r = {r}");
            }
            // Outward winding: each triangle's normal points away from the centre.
            for t in &rebuilt.triangles {
                let [a, b, c] = t.map(|i| rebuilt.positions[i as usize]);
                let normal = super::super::mesh::cross(sub(b, a), sub(c, a));
                assert!(
                    super::super::mesh::dot(normal, sub(a, centre)) > 0.0,
                    "level {level}: inward triangle"
                );
            }
            counts.push(rebuilt.triangles.len());
        }
        assert!(
            counts[0] > 3 * counts[1] && counts[1] > 3 * counts[2],
            "{counts:?}"
        );
    }
}
