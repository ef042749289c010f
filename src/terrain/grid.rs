//! Terrain geometry: a grid mesh over an elevation map, split into square tiles, each a mesh of
//! its own with its own bounds, so that a frame draws only the tiles its view can see (the
//! surface pass culls by bounds). Relief layers displace the detail on top of it.
//!
//! Axes: the map's u runs along +x and v along +z, centred on the origin; elevation 1 stands
//! `height` above elevation 0 along +y. One vertex sits on every `step`-th texel centre (and on
//! the last texel's, so the grid reaches the map's far edges); normals come from central
//! differences of the elevation in world units, tangents along +x; both uv sets run 0 to 1 over
//! the whole map (the splat map's coordinates; a material's texture transform tiles its layers).

use glam::Vec3;

use crate::geometry::{Mesh, Vertex};
use crate::heightfield::Heightfield;

/// How an elevation map becomes a grid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GridOptions {
    /// World size of the map's longer side.
    pub extent: f32,
    /// World height of elevation 1.
    pub height: f32,
    /// Quads along a tile's side.
    pub tile_quads: u32,
    /// Texels between neighbouring vertices.
    pub step: u32,
}

impl Default for GridOptions {
    fn default() -> GridOptions {
        GridOptions {
            extent: 10.0,
            height: 1.0,
            tile_quads: 32,
            step: 1,
        }
    }
}

/// The grid's tiles, row by row along +z, named `{name} tile {column},{row}`, all with
/// `material`.
pub fn terrain_tiles(
    elevation: &Heightfield,
    options: &GridOptions,
    name: &str,
    material: usize,
) -> Vec<Mesh> {
    let grid = TerrainGrid::new(elevation.width(), elevation.height(), options);
    (0..grid.tile_count())
        .map(|k| grid.tile_mesh(elevation, k, name, material))
        .collect()
}

/// Which texels carry the grid's vertices and which of them each tile takes, for an elevation
/// map of one size: tiles can be rebuilt one by one after an edit.
#[derive(Debug, Clone, PartialEq)]
pub struct TerrainGrid {
    options: GridOptions,
    width: u32,
    height: u32,
    /// Vertex columns and rows: every step-th texel, plus the last one.
    columns: Vec<u32>,
    rows: Vec<u32>,
}

impl TerrainGrid {
    /// The tiling of a `width` x `height` elevation map as `options` asks.
    pub fn new(width: u32, height: u32, options: &GridOptions) -> TerrainGrid {
        let step = options.step.max(1);
        TerrainGrid {
            options: *options,
            width,
            height,
            columns: axis_texels(width, step),
            rows: axis_texels(height, step),
        }
    }

    fn quads(&self) -> usize {
        self.options.tile_quads.max(1) as usize
    }

    /// Tiles along u and along v.
    pub fn tiles_across(&self) -> (usize, usize) {
        let q = self.quads();
        (
            (self.columns.len() - 1).div_ceil(q),
            (self.rows.len() - 1).div_ceil(q),
        )
    }

    /// How many tiles it has.
    pub fn tile_count(&self) -> usize {
        let (x, y) = self.tiles_across();
        x * y
    }

    /// The vertex texels of tile `k`'s columns and rows (its last ones shared with the next tile).
    fn tile_texels(&self, k: usize) -> (&[u32], &[u32]) {
        let (across, _) = self.tiles_across();
        let q = self.quads();
        let (cx, cz) = ((k % across) * q, (k / across) * q);
        (
            &self.columns[cx..(cx + q + 1).min(self.columns.len())],
            &self.rows[cz..(cz + q + 1).min(self.rows.len())],
        )
    }

    /// The tiles whose vertices read any texel of `x0..=x1` x `y0..=y1`: a vertex reads its own
    /// texel and its four neighbours (for its normal).
    pub fn tiles_reading(&self, (x0, y0): (u32, u32), (x1, y1): (u32, u32)) -> Vec<usize> {
        let hits = |texels: &[u32], lo: u32, hi: u32| {
            texels
                .iter()
                .any(|&t| t + 1 >= lo && t <= hi.saturating_add(1))
        };
        (0..self.tile_count())
            .filter(|&k| {
                let (xs, zs) = self.tile_texels(k);
                hits(xs, x0, x1) && hits(zs, y0, y1)
            })
            .collect()
    }

    /// Tile `k`'s mesh over `elevation` (of the grid's size).
    pub fn tile_mesh(
        &self,
        elevation: &Heightfield,
        k: usize,
        name: &str,
        material: usize,
    ) -> Mesh {
        let options = &self.options;
        let (w, h) = (self.width, self.height);
        let texel = options.extent / w.max(h) as f32;
        let origin = Vec3::new(-0.5 * texel * w as f32, 0.0, -0.5 * texel * h as f32);
        let at = |i: i64, j: i64| {
            let i = i.clamp(0, i64::from(w) - 1) as u32;
            let j = j.clamp(0, i64::from(h) - 1) as u32;
            elevation.get(i, j) * options.height
        };
        let vertex = |i: u32, j: u32| {
            let (ii, jj) = (i64::from(i), i64::from(j));
            let position = origin
                + Vec3::new(
                    (i as f32 + 0.5) * texel,
                    at(ii, jj),
                    (j as f32 + 0.5) * texel,
                );
            // Central differences, one-sided at the edges (the clamp repeats the edge texel).
            let span = |a: i64, b: i64, n: u32| (b.min(i64::from(n) - 1) - a.max(0)).max(1) as f32;
            let dx = (at(ii + 1, jj) - at(ii - 1, jj)) / (span(ii - 1, ii + 1, w) * texel);
            let dz = (at(ii, jj + 1) - at(ii, jj - 1)) / (span(jj - 1, jj + 1, h) * texel);
            let normal = Vec3::new(-dx, 1.0, -dz).normalize();
            let tangent = Vec3::new(1.0, dx, 0.0).normalize();
            let uv = [(i as f32 + 0.5) / w as f32, (j as f32 + 0.5) / h as f32];
            // u along +x and v along +z: normal x tangent points along -z, against +v.
            Vertex::new(
                position.to_array(),
                normal.to_array(),
                uv,
                [tangent.x, tangent.y, tangent.z, -1.0],
            )
        };
        let (xs, zs) = self.tile_texels(k);
        let mut vertices = Vec::with_capacity(xs.len() * zs.len());
        for &j in zs {
            for &i in xs {
                vertices.push(vertex(i, j));
            }
        }
        let stride = xs.len() as u32;
        let mut indices = Vec::with_capacity((xs.len() - 1) * (zs.len() - 1) * 6);
        for b in 0..zs.len() as u32 - 1 {
            for a in 0..stride - 1 {
                let v = b * stride + a;
                // Counter-clockwise seen from +y.
                indices.extend([v, v + stride, v + 1, v + 1, v + stride, v + stride + 1]);
            }
        }
        let (across, _) = self.tiles_across();
        Mesh {
            name: format!("{name} tile {},{}", k % across, k / across),
            vertices,
            indices,
            material,
            transform: glam::Mat4::IDENTITY,
        }
    }
}

/// The texels along one axis of `n` that carry vertices: every `step`-th and the last.
fn axis_texels(n: u32, step: u32) -> Vec<u32> {
    let mut at: Vec<u32> = (0..n).step_by(step as usize).collect();
    if at.last() != Some(&(n - 1)) {
        at.push(n - 1);
    }
    if at.len() == 1 {
        // A one-texel axis still spans a quad (of zero width).
        at.push(n - 1);
    }
    at
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::heightfield::Generator;

    #[test]
    fn tiles_cover_the_map_and_meet_edge_to_edge() {
        let hf = Generator::Fbm.generate(100, 60, 3);
        let options = GridOptions {
            extent: 10.0,
            height: 2.0,
            tile_quads: 16,
            step: 2,
        };
        let tiles = terrain_tiles(&hf, &options, "t", 0);
        // 50 + 1 vertex columns -> 50 quads -> 4 tiles; 30 + 1 rows -> 30 quads -> 2 tiles.
        assert_eq!(tiles.len(), 4 * 2);
        let quads: usize = tiles.iter().map(|t| t.indices.len() / 6).sum();
        assert_eq!(quads, 50 * 30);
        // Extent along x is 10 (the longer side), z 6, centred; heights within the map's.
        let (lo, hi) = tiles.iter().flat_map(|t| &t.vertices).fold(
            (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN)),
            |(lo, hi), v| (lo.min(v.position.into()), hi.max(v.position.into())),
        );
        assert!(
            (lo.x + 4.95).abs() < 1e-4 && (hi.x - 4.95).abs() < 1e-4,
            "{lo} {hi}"
        );
        assert!(
            (lo.z + 2.95).abs() < 1e-4 && (hi.z - 2.95).abs() < 1e-4,
            "{lo} {hi}"
        );
        assert!(lo.y >= 0.0 && hi.y <= 2.0);
        // Neighbouring tiles share their edge's vertices exactly (no cracks).
        let right_edge: Vec<[f32; 3]> = tiles[0]
            .vertices
            .chunks(17)
            .map(|row| row[16].position)
            .collect();
        let left_edge: Vec<[f32; 3]> = tiles[1]
            .vertices
            .chunks(tiles[1].vertices.len() / right_edge.len())
            .map(|row| row[0].position)
            .collect();
        assert_eq!(right_edge, left_edge);
    }

    #[test]
    fn a_slope_gets_its_normal_and_faces_up() {
        // Elevation rising along u: 0.5 over the map's 8 texels, height 4, extent 8 -> slope 0.25.
        let data = (0..64).map(|t| (t % 8) as f32 / 14.0).collect();
        let hf = Heightfield::new(8, 8, data).unwrap();
        let options = GridOptions {
            extent: 8.0,
            height: 4.0 * 14.0 / 8.0 * 0.5,
            tile_quads: 4,
            step: 1,
        };
        let tiles = terrain_tiles(&hf, &options, "slope", 0);
        let v = &tiles[0].vertices[2 * 5 + 2];
        let expected = Vec3::new(-0.25, 1.0, 0.0).normalize();
        assert!(
            Vec3::from(v.normal).abs_diff_eq(expected, 1e-5),
            "{:?}",
            v.normal
        );
        for t in &tiles {
            for tri in t.indices.chunks_exact(3) {
                let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(t.vertices[tri[k] as usize].position));
                assert!((b - a).cross(c - a).y > 0.0, "a triangle faces down");
            }
        }
    }

    #[test]
    fn a_single_texel_map_still_makes_a_tile() {
        let hf = Heightfield::new(1, 1, vec![0.5]).unwrap();
        let tiles = terrain_tiles(&hf, &GridOptions::default(), "dot", 0);
        assert_eq!(tiles.len(), 1);
        assert!(tiles[0]
            .vertices
            .iter()
            .all(|v| v.normal == [0.0, 1.0, 0.0]));
    }
}
