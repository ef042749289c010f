//! Distance maps on the domain faces of grey cells (Apaza and Andujar, sections 3.3.2 and 3.3.3), sampled on the CPU by
//! casting each texel's projection line into its cell: the reference for a GPU sampler, and where the overlap ratio
//! that picks the grid size is counted.
//!
//! A texel's face point `q` (its centre on the face, in cell-local coordinates) lies on one projection line, which
//! runs from `q` into the cell to the projection's centre, axis or plane (for a parallel projection, across the
//! cell). The texel stores the distance from `q` to the line's first crossing of the surface, the nearest surface
//! point that projects onto the texel as in the paper's depth-tested rendering, or the line's whole length where it
//! crosses none. The paper counts the fragments that the depth test hides; here that is every crossing of a line
//! after its first, over all crossings: the overlap ratio. Distances are in cell sides.

use super::case::{Face, FaceSet};
use super::grid::{CellGrid, CellIndex};
use super::mesh::{cross, dot, norm, sub, ClosedMesh};
use super::parallel::map_in_parallel;
use super::projection::{domain_faces, face_point, Projection};

/// Crossings along one line closer than this (cell sides) are one: a line through an edge or a vertex meets
/// every triangle around it at the same point.
const SAME_CROSSING: f64 = 1e-9;

/// One domain face's distance map.
#[derive(Debug, Clone)]
pub struct FaceMap {
    /// The grey cell the map belongs to.
    pub cell: CellIndex,
    /// Which of the cell's domain faces it covers.
    pub face: Face,
    /// Row-major `resolution`^2 distances in cell sides, from the texel's face point along its projection line
    /// to the first surface crossing (the line's whole length where it crosses none); texel `(a, b)` sits at face coordinates `((a + 0.5) / R, (b + 0.5) / R)`
    /// along the face's [`Face::span`] axes.
    pub distances: Vec<f32>,
    /// Per texel, whether its face point lies inside the mesh; empty when none does. Only an interior grey cell
    /// (case 6) has domain faces shared with grey cells, whose points may lie on either side; an external face
    /// borders a white cell, whose closed box misses the surface, so its points are all outside.
    pub inside_at_face: Vec<bool>,
    /// Per texel, the surface point its distance stops at: which of the mesh's triangles, where in it. Where the
    /// cells pass starts looking for the triangle a hit lies on ([`super::surface_triangles`]).
    pub surface: Vec<SurfacePoint>,
}

/// Where a texel's line first crosses the surface: a triangle of the [`ClosedMesh`] and barycentric weights of
/// its second and third corners; `triangle` is [`SurfacePoint::NONE`] for a line that crosses nothing.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfacePoint {
    /// Index into [`ClosedMesh::triangles`], or [`SurfacePoint::NONE`].
    pub triangle: u32,
    /// Weights of the triangle's second and third corners; the first's is `1 - b[0] - b[1]`.
    pub barycentric: [f32; 2],
}

impl SurfacePoint {
    /// The `triangle` of a line that crosses no triangle.
    pub const NONE: u32 = u32::MAX;

    /// Whether the line crossed the surface (`triangle` is not [`SurfacePoint::NONE`]).
    pub fn is_hit(&self) -> bool {
        self.triangle != SurfacePoint::NONE
    }
}

impl FaceMap {
    /// Whether the point at `distance` along texel `texel`'s line lies inside the mesh, given the surface's
    /// distance `surface` there: past the first crossing the line has changed sides.
    pub fn inside(&self, texel: usize, distance: f64, surface: f64) -> bool {
        let face_inside = self.inside_at_face.get(texel).copied().unwrap_or(false);
        face_inside != (distance > surface)
    }
}

/// Every grey cell's distance maps at one resolution.
#[derive(Debug, Clone)]
pub struct CellMaps {
    /// Texels along each side of every face map.
    pub resolution: u32,
    /// One map per domain face of every grey cell, grey cells in [`CellGrid::grey_cells`] order; the order
    /// is the map layers' order on the GPU ([`super::PackedComplex`]).
    pub faces: Vec<FaceMap>,
    /// How many grey cells carry the maps.
    pub grey_cells: usize,
    /// Crossings after the first along the texels' lines, over all crossings (0 when nothing crosses).
    pub overlap_ratio: f64,
}

impl CellMaps {
    /// Samples the maps of every grey cell of `grid` (classified from `mesh`) at `resolution`^2 texels a face, the
    /// faces shared among the machine's cores (no map depends on another).
    pub fn sample(mesh: &ClosedMesh, grid: &CellGrid, resolution: u32) -> CellMaps {
        assert!(resolution >= 1, "a distance map needs at least one texel");
        let cells: Vec<CellIndex> = grid.grey_cells().collect();
        let prepared = map_in_parallel(&cells, |&cell| GreyCellLines::new(mesh, grid, cell));
        let faces: Vec<(&GreyCellLines, Face)> = prepared
            .iter()
            .flat_map(|lines| {
                domain_faces(lines.internal)
                    .faces()
                    .map(move |f| (lines, f))
            })
            .collect();
        let sampled = map_in_parallel(&faces, |&(lines, face)| lines.sample_face(face, resolution));
        let crossings: u64 = sampled.iter().map(|s| s.crossings).sum();
        let hidden: u64 = sampled.iter().map(|s| s.hidden).sum();
        CellMaps {
            resolution,
            faces: sampled.into_iter().map(|s| s.map).collect(),
            grey_cells: cells.len(),
            overlap_ratio: if crossings == 0 {
                0.0
            } else {
                hidden as f64 / crossings as f64
            },
        }
    }

    /// Bytes of the maps as 16-bit distances (the paper's storage), one layer of `resolution`^2 a domain face.
    pub fn bytes(&self) -> u64 {
        self.faces.len() as u64 * u64::from(self.resolution).pow(2) * 2
    }
}

/// One domain face's map and its lines' crossings.
struct FaceSample {
    map: FaceMap,
    crossings: u64,
    hidden: u64,
}

/// What every projection line of one grey cell is crossed with: the cell's triangles in cell-local coordinates
/// and its projection, prepared once for all its domain faces.
struct GreyCellLines {
    cell: CellIndex,
    internal: FaceSet,
    projection: Projection,
    triangles: Vec<[[f64; 3]; 3]>,
    /// The mesh's index of each of `triangles`.
    triangle_ids: Vec<u32>,
    /// For an interior cell, whose lines all end at its centre, whether the centre is inside: with each line's
    /// crossings it says on which side each face point lies.
    centre_inside: Option<bool>,
}

impl GreyCellLines {
    fn new(mesh: &ClosedMesh, grid: &CellGrid, cell: CellIndex) -> GreyCellLines {
        let internal = grid.internal_faces(cell);
        GreyCellLines {
            cell,
            internal,
            projection: Projection::for_cell(internal),
            triangles: grid
                .triangles_in(cell)
                .iter()
                .map(|&t| mesh.triangle(t as usize).map(|p| grid.to_cell(cell, p)))
                .collect(),
            triangle_ids: grid.triangles_in(cell).to_vec(),
            centre_inside: internal
                .complement()
                .is_empty()
                .then(|| mesh.winding_number(grid.from_cell(cell, [0.5; 3])).abs() > 0.5),
        }
    }

    /// Samples the map of domain face `face`: each texel's line against the cell's triangles.
    fn sample_face(&self, face: Face, resolution: u32) -> FaceSample {
        let texels = (resolution as usize).pow(2);
        let mut distances = Vec::with_capacity(texels);
        let mut surface = Vec::with_capacity(texels);
        let mut inside_at_face = Vec::with_capacity(if self.centre_inside.is_some() {
            texels
        } else {
            0
        });
        let (mut crossings, mut hidden) = (0, 0);
        for b in 0..resolution {
            for a in 0..resolution {
                let uv = [a, b].map(|x| (f64::from(x) + 0.5) / f64::from(resolution));
                let line = Line::new(&self.projection, face, uv);
                let hits = line.crossings(&self.triangles);
                crossings += hits.len() as u64;
                hidden += hits.len().saturating_sub(1) as u64;
                distances.push(hits.first().map_or(line.length, |h| h.t) as f32);
                surface.push(hits.first().map_or(
                    SurfacePoint {
                        triangle: SurfacePoint::NONE,
                        barycentric: [0.0; 2],
                    },
                    |h| SurfacePoint {
                        triangle: self.triangle_ids[h.triangle],
                        barycentric: h.barycentric.map(|w| w as f32),
                    },
                ));
                if let Some(centre) = self.centre_inside {
                    inside_at_face.push(centre != (hits.len() % 2 == 1));
                }
            }
        }
        FaceSample {
            map: FaceMap {
                cell: self.cell,
                face,
                distances,
                inside_at_face,
                surface,
            },
            crossings,
            hidden,
        }
    }
}

/// The most memory the doubling lets one grid's maps take while they are sampled (f32 distances): past it the
/// next grid is not tried (a detailed mesh at 64^3 could otherwise ask for gigabytes).
pub const MAP_MEMORY_LIMIT: u64 = 1 << 30;

/// Why the grid's doubling stopped.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GridStop {
    /// The maps' overlap ratio fell to the threshold and their texels to the size asked for.
    Settled,
    /// The next grid would exceed the largest size allowed.
    MaxGrid,
    /// The next grid's maps would take `bytes`, more than the memory limit.
    Memory {
        /// Cells per axis of the grid that was not tried.
        next_n: u32,
        /// Bytes its maps would have taken while sampled ([`sampled_bytes`]).
        bytes: u64,
    },
}

/// Bytes the maps of `grid` take while sampled at `resolution`^2 (f32 distances and their surface points), known
/// before sampling them.
pub fn sampled_bytes(grid: &CellGrid, resolution: u32) -> u64 {
    let faces: u64 = grid
        .grey_cells()
        .map(|cell| u64::from(domain_faces(grid.internal_faces(cell)).len()))
        .sum();
    faces * u64::from(resolution).pow(2) * SAMPLED_TEXEL_BYTES
}

/// A sampled texel's distance and surface point.
const SAMPLED_TEXEL_BYTES: u64 =
    (std::mem::size_of::<f32>() + std::mem::size_of::<SurfacePoint>()) as u64;

/// The grid and maps the paper's size choice ends at: N doubles from 1 while the maps' overlap ratio is above
/// `threshold` or their texels are wider than `max_texel` (in the mesh's units; infinite for the paper's rule
/// alone), up to `max_n` and while the next grid's maps stay within `max_bytes`; and why it stopped.
pub fn choose_grid_within(
    mesh: &ClosedMesh,
    resolution: u32,
    threshold: f64,
    max_texel: f64,
    max_n: u32,
    max_bytes: u64,
) -> (CellGrid, CellMaps, GridStop) {
    let mut grid = CellGrid::classify(mesh, 1);
    loop {
        let maps = CellMaps::sample(mesh, &grid, resolution);
        if maps.overlap_ratio <= threshold && texel_size(&grid, resolution) <= max_texel {
            return (grid, maps, GridStop::Settled);
        }
        let next_n = grid.n() * 2;
        if next_n > max_n {
            return (grid, maps, GridStop::MaxGrid);
        }
        let next = CellGrid::classify(mesh, next_n);
        let bytes = sampled_bytes(&next, resolution);
        if bytes > max_bytes {
            return (grid, maps, GridStop::Memory { next_n, bytes });
        }
        grid = next;
    }
}

/// A fixed grid whose maps would not fit in [`MAP_MEMORY_LIMIT`] while sampled.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("a {n}^3 grid's maps at {resolution}^2 would take {} MiB while sampled (at most {} MiB)", bytes >> 20, MAP_MEMORY_LIMIT >> 20)]
pub struct GridTooLarge {
    /// Cells per axis asked for.
    pub n: u32,
    /// Texels per side of each face map asked for.
    pub resolution: u32,
    /// Bytes the maps would take while sampled ([`sampled_bytes`]).
    pub bytes: u64,
}

/// The grid of `n` cells a side over `mesh` and its maps, refused before any is sampled when they
/// would take more than [`MAP_MEMORY_LIMIT`].
pub fn fixed_grid(
    mesh: &ClosedMesh,
    n: u32,
    resolution: u32,
) -> Result<(CellGrid, CellMaps), GridTooLarge> {
    let grid = CellGrid::classify(mesh, n);
    let bytes = sampled_bytes(&grid, resolution);
    if bytes > MAP_MEMORY_LIMIT {
        return Err(GridTooLarge {
            n,
            resolution,
            bytes,
        });
    }
    let maps = CellMaps::sample(mesh, &grid, resolution);
    Ok((grid, maps))
}

/// The paper's choice: [`choose_grid_within`] by the overlap ratio alone, with [`MAP_MEMORY_LIMIT`], without
/// the reason.
pub fn choose_grid(
    mesh: &ClosedMesh,
    resolution: u32,
    threshold: f64,
    max_n: u32,
) -> (CellGrid, CellMaps) {
    let (grid, maps, _) = choose_grid_within(
        mesh,
        resolution,
        threshold,
        f64::INFINITY,
        max_n,
        MAP_MEMORY_LIMIT,
    );
    (grid, maps)
}

/// The side of one map texel of `grid` at `resolution`, in the mesh's units.
pub fn texel_size(grid: &CellGrid, resolution: u32) -> f64 {
    grid.cell_size() / f64::from(resolution)
}

/// One texel's projection line in cell-local coordinates: from `start` on the face along the unit `dir` into the
/// cell, `length` long.
struct Line {
    start: [f64; 3],
    dir: [f64; 3],
    length: f64,
}

impl Line {
    fn new(projection: &Projection, face: Face, uv: [f64; 2]) -> Line {
        let start = face_point(face, uv);
        // The projection moves points outward to the face; the line runs back against it.
        let outward = projection.direction(start);
        let size = norm(outward);
        let dir = outward.map(|c| -c / size);
        let length = projection.line_length(face, uv);
        Line { start, dir, length }
    }

    /// Where the line crosses the triangles, ascending, equal distances merged.
    fn crossings(&self, triangles: &[[[f64; 3]; 3]]) -> Vec<Crossing> {
        let mut hits: Vec<Crossing> = triangles
            .iter()
            .enumerate()
            .filter_map(|(k, &t)| {
                ray_triangle_at(self.start, self.dir, t).map(|(t, barycentric)| Crossing {
                    t,
                    triangle: k,
                    barycentric,
                })
            })
            .filter(|c| c.t <= self.length)
            .collect();
        hits.sort_by(|a, b| a.t.total_cmp(&b.t));
        hits.dedup_by(|b, a| b.t - a.t < SAME_CROSSING);
        hits
    }
}

/// A line's crossing of one of a cell's triangles: its distance, which triangle, and where in it.
struct Crossing {
    t: f64,
    triangle: usize,
    barycentric: [f64; 2],
}

/// Where the ray `origin + t dir` (t >= 0) meets the closed triangle, by Möller and Trumbore's test; `None` for a
/// ray in the triangle's plane.
pub(crate) fn ray_triangle(
    origin: [f64; 3],
    dir: [f64; 3],
    triangle: [[f64; 3]; 3],
) -> Option<f64> {
    ray_triangle_at(origin, dir, triangle).map(|(t, _)| t)
}

/// [`ray_triangle`] with the hit's barycentric weights of the second and third corners.
fn ray_triangle_at(
    origin: [f64; 3],
    dir: [f64; 3],
    [a, b, c]: [[f64; 3]; 3],
) -> Option<(f64, [f64; 2])> {
    let (e1, e2) = (sub(b, a), sub(c, a));
    let p = cross(dir, e2);
    let det = dot(e1, p);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = sub(origin, a);
    let u = dot(s, p) / det;
    let q = cross(s, e1);
    let v = dot(dir, q) / det;
    let t = dot(e2, q) / det;
    (u >= 0.0 && v >= 0.0 && u + v <= 1.0 && t >= 0.0).then_some((t, [u, v]))
}

#[cfg(test)]
mod tests {
    use super::super::mesh::shapes::{icosphere, inscribed_radius, torus};
    use super::super::projection::Image;
    use super::*;

    fn mesh(shape: (Vec<[f64; 3]>, Vec<[u32; 3]>), name: &str) -> ClosedMesh {
        ClosedMesh::new(name, &shape.0, &shape.1).expect("closed")
    }

    /// The mesh-space point of texel `(a, b)` of `map` at its stored distance.
    fn surface_point(grid: &CellGrid, map: &FaceMap, resolution: u32, a: u32, b: u32) -> [f64; 3] {
        let projection = Projection::for_cell(grid.internal_faces(map.cell));
        let image = Image {
            face: map.face,
            uv: [a, b].map(|x| (f64::from(x) + 0.5) / f64::from(resolution)),
            distance: f64::from(map.distances[(b * resolution + a) as usize]),
        };
        grid.from_cell(map.cell, projection.unproject(&image))
    }

    #[test]
    fn sphere_maps_rebuild_points_of_the_sphere() {
        let centre = [0.2, 0.1, -0.3];
        let sphere = mesh(icosphere(centre, 1.0, 3), "sphere");
        let inscribed = inscribed_radius(&sphere, centre);
        let resolution = 12;
        for n in [1, 3, 4] {
            let grid = CellGrid::classify(&sphere, n);
            let maps = CellMaps::sample(&sphere, &grid, resolution);
            let mut on_surface = 0;
            for map in &maps.faces {
                let internal = grid.internal_faces(map.cell);
                let external = internal.complement();
                let projection = Projection::for_cell(internal);
                for b in 0..resolution {
                    for a in 0..resolution {
                        let d = f64::from(map.distances[(b * resolution + a) as usize]);
                        let uv = [a, b].map(|x| (f64::from(x) + 0.5) / f64::from(resolution));
                        let full = Line::new(&projection, map.face, uv).length;
                        let p = surface_point(&grid, map, resolution, a, b);
                        let r = norm(sub(p, centre));
                        if d < full - 1e-6 {
                            // A crossing: on the polyhedron, which lies between its inscribed sphere and the sphere.
                            assert!(r > inscribed - 1e-6 && r < 1.0 + 1e-6, "n = {n}: r = {r}");
                            on_surface += 1;
                        } else if !external.is_empty() {
                            // No crossing: the whole line lies outside, as its face point on an external face does.
                            let winding = sphere.winding_number(p);
                            assert!(
                                winding.abs() < 0.5,
                                "n = {n}: a line's end inside ({winding})"
                            );
                        }
                    }
                }
            }
            assert!(on_surface > 0);
            // From the centre of a single cell the sphere is star-shaped: every line crosses it once.
            if n == 1 {
                assert_eq!(maps.grey_cells, 1);
                assert_eq!(maps.faces.len(), 6);
                assert_eq!(maps.overlap_ratio, 0.0);
            }
            assert_eq!(maps.bytes(), maps.faces.len() as u64 * 12 * 12 * 2);
        }
    }

    #[test]
    fn the_grid_doubles_until_the_torus_stops_overlapping() {
        let ring = mesh(torus([0.0; 3], 1.0, 0.4, 32, 16), "torus");
        // One cell sees the torus's outer and inner walls along the same lines.
        let whole = CellMaps::sample(&ring, &CellGrid::classify(&ring, 1), 8);
        assert!(whole.overlap_ratio > 0.2, "{}", whole.overlap_ratio);
        let (grid, maps) = choose_grid(&ring, 8, 0.05, 16);
        assert!(grid.n() > 1);
        assert!(
            maps.overlap_ratio <= 0.05,
            "n = {}: {}",
            grid.n(),
            maps.overlap_ratio
        );
        assert!(maps.overlap_ratio < whole.overlap_ratio);
        // The choice stops at the first N that qualifies: half of it did not.
        let coarser = CellMaps::sample(&ring, &CellGrid::classify(&ring, grid.n() / 2), 8);
        assert!(coarser.overlap_ratio > 0.05);
    }

    #[test]
    fn the_doubling_stops_before_maps_outgrow_the_memory_limit() {
        let ring = mesh(torus([0.0; 3], 1.0, 0.4, 32, 16), "torus");
        let (free, _, why) = choose_grid_within(&ring, 8, 0.05, f64::INFINITY, 16, u64::MAX);
        assert_eq!(why, GridStop::Settled);
        assert!(free.n() > 1);
        // Room for the first grid's maps only: it stops there and says what the next would take.
        let one = sampled_bytes(&CellGrid::classify(&ring, 1), 8);
        let (grid, maps, why) = choose_grid_within(&ring, 8, 0.05, f64::INFINITY, 16, one);
        assert_eq!(grid.n(), 1);
        assert_eq!(maps.faces.len() as u64 * 64 * 16, one);
        let GridStop::Memory { next_n, bytes } = why else {
            panic!("{why:?}");
        };
        assert_eq!(next_n, 2);
        assert_eq!(bytes, sampled_bytes(&CellGrid::classify(&ring, 2), 8));
        assert!(bytes > one);
        let (_, _, why) = choose_grid_within(&ring, 8, 0.05, f64::INFINITY, 1, u64::MAX);
        assert_eq!(why, GridStop::MaxGrid);
    }

    #[test]
    fn the_grid_also_doubles_until_its_texels_are_as_fine_as_asked() {
        let ball = mesh(icosphere([0.0; 3], 1.0, 2), "sphere");
        // A sphere overlaps nothing from its one cell: the paper's rule stops there.
        let (grid, _, why) = choose_grid_within(&ball, 8, 0.05, f64::INFINITY, 16, u64::MAX);
        assert_eq!((grid.n(), why), (1, GridStop::Settled));
        let coarse = texel_size(&grid, 8);
        let (grid, _, why) = choose_grid_within(&ball, 8, 0.05, coarse / 3.0, 16, u64::MAX);
        assert_eq!((grid.n(), why), (4, GridStop::Settled));
        assert!(texel_size(&grid, 8) <= coarse / 3.0);
    }

    #[test]
    fn ray_triangle_hits_inside_and_on_the_border_only() {
        let t = [[0.0, 0.0, 1.0], [1.0, 0.0, 1.0], [0.0, 1.0, 1.0]];
        let down = [0.0, 0.0, 1.0];
        assert_eq!(ray_triangle([0.2, 0.2, 0.0], down, t), Some(1.0));
        assert_eq!(
            ray_triangle([0.5, 0.5, 0.0], down, t),
            Some(1.0),
            "on the hypotenuse"
        );
        assert_eq!(ray_triangle([0.6, 0.6, 0.0], down, t), None);
        assert_eq!(
            ray_triangle([0.2, 0.2, 2.0], down, t),
            None,
            "behind the origin"
        );
        assert_eq!(
            ray_triangle([0.2, 0.2, 1.0], [1.0, 0.0, 0.0], t),
            None,
            "in the plane"
        );
    }
}
