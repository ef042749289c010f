//! The N x N x N grid over a mesh's bounding cube and its cells' colours (Apaza and Andujar, section 3.3.1): grey cells
//! meet the surface, white cells lie outside it, black cells inside.
//!
//! Grey cells come from an exact separating-axis test of each triangle against the closed cells its bounds
//! overlap, so a cell that only touches the surface is grey too. The other cells are split into 6-connected
//! components; two face neighbours that both miss the surface lie on the same side of it (their shared face
//! misses it too), so one winding-number test per component colours it. That also finds white cavities that a
//! flood fill from the grid's border would call black.

use std::collections::HashMap;

use super::case::{Face, FaceSet};
use super::mesh::{cross, dot, sub, ClosedMesh};

/// A cell's place relative to the mesh.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Colour {
    /// Wholly outside the mesh: its closed box meets no triangle.
    White,
    /// Meets the surface: at least one triangle crosses its closed box; only these carry distance maps.
    Grey,
    /// Wholly inside the mesh.
    Black,
}

/// Cell indices `[i, j, k]` along x, y, z.
pub type CellIndex = [u32; 3];

/// The coloured grid over a mesh's bounding cube.
#[derive(Debug, Clone)]
pub struct CellGrid {
    n: u32,
    origin: [f64; 3],
    cell_size: f64,
    colours: Vec<Colour>,
    /// Per grey cell (by index), the triangles that meet it: what its distance maps sample.
    triangles: HashMap<usize, Vec<u32>>,
}

impl CellGrid {
    /// Colours the `n`^3 cells (`n >= 1`) of the cube around `mesh`'s bounds: the cube has the bounds' longest
    /// side and their centre.
    pub fn classify(mesh: &ClosedMesh, n: u32) -> CellGrid {
        assert!(n >= 1, "a grid needs at least one cell");
        let (lo, hi) = mesh.bounds();
        let side = (0..3).map(|k| hi[k] - lo[k]).fold(0.0, f64::max);
        // A flat or point-like mesh still gets a cube of some size.
        let side = if side > 0.0 { side } else { 1.0 };
        let origin = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]) - 0.5 * side);
        let mut grid = CellGrid {
            n,
            origin,
            cell_size: side / f64::from(n),
            colours: vec![Colour::White; (n as usize).pow(3)],
            triangles: HashMap::new(),
        };
        grid.mark_grey(mesh);
        grid.colour_components(mesh);
        grid
    }

    /// Cells per axis.
    pub fn n(&self) -> u32 {
        self.n
    }

    /// The least corner of the grid's cube.
    pub fn origin(&self) -> [f64; 3] {
        self.origin
    }

    /// The side of one cell.
    pub fn cell_size(&self) -> f64 {
        self.cell_size
    }

    fn index(&self, [i, j, k]: CellIndex) -> usize {
        let n = self.n as usize;
        (k as usize * n + j as usize) * n + i as usize
    }

    /// The colour of `cell`, whose indices must each be below [`CellGrid::n`].
    pub fn colour(&self, cell: CellIndex) -> Colour {
        self.colours[self.index(cell)]
    }

    /// The closed box of a cell: (least corner, greatest corner).
    pub fn cell_box(&self, cell: CellIndex) -> ([f64; 3], [f64; 3]) {
        let lo = [0, 1, 2].map(|a| self.origin[a] + f64::from(cell[a]) * self.cell_size);
        (lo, lo.map(|c| c + self.cell_size))
    }

    /// Every cell, x fastest.
    pub fn cells(&self) -> impl Iterator<Item = CellIndex> + '_ {
        let n = self.n;
        (0..n).flat_map(move |k| (0..n).flat_map(move |j| (0..n).map(move |i| [i, j, k])))
    }

    /// The grey cells, in [`CellGrid::cells`] order (x fastest).
    pub fn grey_cells(&self) -> impl Iterator<Item = CellIndex> + '_ {
        self.cells().filter(|&c| self.colour(c) == Colour::Grey)
    }

    /// The mesh triangles that meet a grey cell (none for other cells).
    pub fn triangles_in(&self, cell: CellIndex) -> &[u32] {
        self.triangles
            .get(&self.index(cell))
            .map_or(&[], Vec::as_slice)
    }

    /// A mesh-space point in `cell`'s local coordinates (the cell spans `[0, 1]^3`).
    pub fn to_cell(&self, cell: CellIndex, p: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|a| (p[a] - self.origin[a]) / self.cell_size - f64::from(cell[a]))
    }

    /// The mesh-space point at `local` coordinates in `cell` ([`Self::to_cell`]'s inverse).
    pub fn from_cell(&self, cell: CellIndex, local: [f64; 3]) -> [f64; 3] {
        [0, 1, 2].map(|a| self.origin[a] + (f64::from(cell[a]) + local[a]) * self.cell_size)
    }

    /// How many cells have each colour: (white, grey, black).
    pub fn counts(&self) -> (usize, usize, usize) {
        let count = |colour| self.colours.iter().filter(|&&c| c == colour).count();
        (
            count(Colour::White),
            count(Colour::Grey),
            count(Colour::Black),
        )
    }

    /// The neighbour across `face`, or `None` past the grid's border.
    pub fn neighbour(&self, cell: CellIndex, face: Face) -> Option<CellIndex> {
        let mut next = cell;
        let coordinate = &mut next[face.axis];
        if face.positive {
            *coordinate += 1;
            (*coordinate < self.n).then_some(next)
        } else {
            coordinate.checked_sub(1).map(|c| {
                next[face.axis] = c;
                next
            })
        }
    }

    /// A grey cell's internal faces: those whose neighbour is not white (past the border counts as white).
    pub fn internal_faces(&self, cell: CellIndex) -> FaceSet {
        Face::ALL
            .into_iter()
            .filter(|&f| {
                self.neighbour(cell, f)
                    .is_some_and(|m| self.colour(m) != Colour::White)
            })
            .fold(FaceSet::EMPTY, FaceSet::with)
    }

    fn mark_grey(&mut self, mesh: &ClosedMesh) {
        let last = f64::from(self.n - 1);
        for t in 0..mesh.triangles().len() {
            let corners = mesh.triangle(t);
            let range = |axis: usize| {
                let cell_of = |x: f64| {
                    ((x - self.origin[axis]) / self.cell_size)
                        .floor()
                        .clamp(0.0, last) as u32
                };
                let (lo, hi) = corners
                    .iter()
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
                        (lo.min(p[axis]), hi.max(p[axis]))
                    });
                // One cell more below: a triangle on a grid plane touches the cells on both sides.
                (cell_of(lo).saturating_sub(1), cell_of(hi))
            };
            let (x, y, z) = (range(0), range(1), range(2));
            for k in z.0..=z.1 {
                for j in y.0..=y.1 {
                    for i in x.0..=x.1 {
                        let cell = [i, j, k];
                        let (lo, hi) = self.cell_box(cell);
                        if triangle_meets_box(corners, lo, hi) {
                            let index = self.index(cell);
                            self.colours[index] = Colour::Grey;
                            self.triangles.entry(index).or_default().push(t as u32);
                        }
                    }
                }
            }
        }
    }

    fn colour_components(&mut self, mesh: &ClosedMesh) {
        let mut seen = vec![false; self.colours.len()];
        let cells: Vec<CellIndex> = self.cells().collect();
        for start in cells {
            let index = self.index(start);
            if seen[index] || self.colours[index] == Colour::Grey {
                continue;
            }
            let (lo, _) = self.cell_box(start);
            let centre = lo.map(|c| c + 0.5 * self.cell_size);
            let colour = if mesh.winding_number(centre).abs() > 0.5 {
                Colour::Black
            } else {
                Colour::White
            };
            seen[index] = true;
            let mut stack = vec![start];
            while let Some(cell) = stack.pop() {
                let index = self.index(cell);
                self.colours[index] = colour;
                for face in Face::ALL {
                    if let Some(next) = self.neighbour(cell, face) {
                        let m = self.index(next);
                        if !seen[m] && self.colours[m] != Colour::Grey {
                            seen[m] = true;
                            stack.push(next);
                        }
                    }
                }
            }
        }
    }
}

/// Whether the closed triangle meets the closed box `[lo, hi]`: no separating axis among the box's three normals,
/// the triangle's normal and the nine cross products of their edges (Akenine-Möller's test, in f64).
pub fn triangle_meets_box(triangle: [[f64; 3]; 3], lo: [f64; 3], hi: [f64; 3]) -> bool {
    let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let half = [0, 1, 2].map(|k| 0.5 * (hi[k] - lo[k]));
    let v = triangle.map(|p| sub(p, centre));
    let edges = [sub(v[1], v[0]), sub(v[2], v[1]), sub(v[0], v[2])];
    let separates = |axis: [f64; 3]| {
        let radius = half[0] * axis[0].abs() + half[1] * axis[1].abs() + half[2] * axis[2].abs();
        let projected = v.map(|p| dot(p, axis));
        let (min, max) = projected
            .iter()
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), &x| {
                (lo.min(x), hi.max(x))
            });
        min > radius || max < -radius
    };
    let unit = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];
    if unit.iter().any(|&a| separates(a)) {
        return false;
    }
    if separates(cross(edges[0], edges[1])) {
        return false;
    }
    !unit
        .iter()
        .any(|&a| edges.iter().any(|&e| separates(cross(a, e))))
}

#[cfg(test)]
mod tests {
    use super::super::mesh::norm;
    use super::super::mesh::shapes::{icosphere, inscribed_radius, torus};
    use super::*;

    fn mesh(shape: (Vec<[f64; 3]>, Vec<[u32; 3]>), name: &str) -> ClosedMesh {
        ClosedMesh::new(name, &shape.0, &shape.1).expect("closed")
    }

    /// The nearest and farthest distances from `p` to the points of a box.
    fn distance_range(p: [f64; 3], (lo, hi): ([f64; 3], [f64; 3])) -> (f64, f64) {
        let near = [0, 1, 2].map(|k| p[k].clamp(lo[k], hi[k]) - p[k]);
        let far = [0, 1, 2].map(|k| (lo[k] - p[k]).abs().max((hi[k] - p[k]).abs()));
        (norm(near), norm(far))
    }

    /// No white cell shares a face with a black one: the surface between them would make one of them grey.
    fn assert_grey_separates(grid: &CellGrid) {
        for cell in grid.cells() {
            if grid.colour(cell) == Colour::White {
                for face in Face::ALL {
                    if let Some(m) = grid.neighbour(cell, face) {
                        assert_ne!(grid.colour(m), Colour::Black, "{cell:?} across {face}");
                    }
                }
            }
        }
    }

    #[test]
    fn sphere_cells_match_the_geometry() {
        let centre = [0.3, -0.2, 0.1];
        let sphere = mesh(icosphere(centre, 1.0, 3), "sphere");
        // The polyhedron lies between its inscribed sphere and the unit sphere.
        let inscribed = inscribed_radius(&sphere, centre);
        assert!(inscribed > 0.98 && inscribed < 1.0);
        for n in [1, 2, 5, 16] {
            let grid = CellGrid::classify(&sphere, n);
            for cell in grid.cells() {
                let (near, far) = distance_range(centre, grid.cell_box(cell));
                let expected = if far < inscribed {
                    Some(Colour::Black)
                } else if near > 1.0 {
                    Some(Colour::White)
                } else if near < inscribed && far > 1.0 {
                    Some(Colour::Grey)
                } else {
                    None
                };
                if let Some(colour) = expected {
                    assert_eq!(grid.colour(cell), colour, "n = {n}, {cell:?}");
                }
            }
            assert_grey_separates(&grid);
        }
        let (white, grey, black) = CellGrid::classify(&sphere, 16).counts();
        assert!(grey > 0 && black > 0 && white > 0);
        assert_eq!(white + grey + black, 16 * 16 * 16);
    }

    #[test]
    fn the_torus_hole_is_white_and_a_cavity_is_found() {
        let ring = mesh(torus([0.0; 3], 1.0, 0.35, 48, 24), "torus");
        let grid = CellGrid::classify(&ring, 12);
        // The middle cells of the grid lie in the hole.
        for cell in [[5, 5, 5], [6, 6, 6], [5, 6, 5]] {
            assert_eq!(grid.colour(cell), Colour::White, "{cell:?}");
        }
        assert_grey_separates(&grid);
        // A shell: the outer sphere wound outward, the inner one inward. The cavity is not reachable from the
        // grid's border, yet it is outside the solid.
        let (mut p, mut t) = icosphere([0.0; 3], 1.0, 2);
        let (inner_p, inner_t) = icosphere([0.0; 3], 0.5, 2);
        let offset = p.len() as u32;
        p.extend(inner_p);
        t.extend(
            inner_t
                .iter()
                .map(|&[a, b, c]| [a + offset, c + offset, b + offset]),
        );
        let shell = CellGrid::classify(&mesh((p, t), "shell"), 16);
        assert_eq!(shell.colour([7, 7, 7]), Colour::White, "the cavity");
        assert_eq!(shell.colour([0, 0, 0]), Colour::White, "outside");
        assert_grey_separates(&shell);
        assert!(shell.counts().2 > 0, "the shell has black cells");
    }

    #[test]
    fn internal_faces_follow_the_neighbours() {
        let sphere = mesh(icosphere([0.0; 3], 1.0, 3), "sphere");
        let grid = CellGrid::classify(&sphere, 8);
        for cell in grid.grey_cells() {
            let internal = grid.internal_faces(cell);
            for face in Face::ALL {
                let white = grid
                    .neighbour(cell, face)
                    .is_none_or(|m| grid.colour(m) == Colour::White);
                assert_eq!(internal.contains(face), !white, "{cell:?} {face}");
            }
        }
        // A cell at the grid's corner has its outward faces external.
        let corner_cells = CellGrid::classify(&sphere, 2);
        assert_eq!(
            corner_cells.counts().1,
            8,
            "every cell of a 2^3 grid meets the sphere"
        );
        assert!(!corner_cells
            .internal_faces([0, 0, 0])
            .contains(Face::new(0, false)));
    }

    #[test]
    fn triangle_box_test_is_closed_and_exact() {
        let (lo, hi) = ([0.0; 3], [1.0; 3]);
        // Touching the box at a face, an edge or a corner counts.
        assert!(triangle_meets_box(
            [[1.0, 0.2, 0.2], [2.0, 0.5, 0.5], [1.0, 0.8, 0.3]],
            lo,
            hi
        ));
        assert!(triangle_meets_box(
            [[1.0, 1.0, 0.5], [2.0, 2.0, 0.5], [2.0, 1.0, 0.5]],
            lo,
            hi
        ));
        assert!(triangle_meets_box(
            [[1.0, 1.0, 1.0], [2.0, 1.0, 1.0], [1.0, 2.0, 1.0]],
            lo,
            hi
        ));
        // Beside the box, although its bounds overlap it: only an edge cross product separates.
        assert!(!triangle_meets_box(
            [[2.7, -0.5, 0.5], [-0.5, 2.7, 0.5], [2.7, 2.7, 0.5]],
            lo,
            hi
        ));
        // Through the box with no corner inside.
        assert!(triangle_meets_box(
            [[-1.0, -1.0, 0.5], [3.0, -1.0, 0.5], [-1.0, 3.0, 0.5]],
            lo,
            hi
        ));
    }
}
