//! Rays through a cell complex (Apaza and Andujar, section 3.4), on the CPU: the reference the renderer's shader is
//! checked against, and what `relief cells` measures against exact ray/triangle intersection with the mesh.
//!
//! The paper marches each ray through the grey cells sample by sample, projects every sample onto its cell's
//! domain faces and compares its distance with the stored one, then refines the first crossing by bisection. It
//! leaves open what a sample in a white or black cell means and where a ray stops. relief decides (the decision lives
//! here and in docs/conventions.md):
//! - a sample is *inside* when it lies in a black cell, or in a grey cell past the surface along its projection
//!   line (the map's distance, bilinear between texel centres, against the sample's own; an interior cell's
//!   face points may start inside, which the map records per texel); white cells and everything outside the
//!   grid are outside;
//! - rays walk the grid cell by cell (Amanatides and Woo's traversal); white cells are crossed in one step, a
//!   grey cell is sampled at most `1 / samples_per_texel` map texels apart, and entering a black cell counts
//!   as a crossing (its box cannot touch the surface, so the crossing lies before it);
//! - the first inside sample is refined by bisection against the last outside one, whichever cells they lie in;
//! - a ray that leaves the grid without an inside sample misses.

use std::collections::HashMap;

use super::distance_map::{ray_triangle, CellMaps, FaceMap};
use super::grid::{CellGrid, CellIndex, Colour};
use super::mesh::ClosedMesh;
use super::projection::Projection;

/// How finely the march samples a grey cell, and how far it refines a crossing.
#[derive(Debug, Clone, Copy)]
pub struct MarchSettings {
    /// Samples per map texel of travel inside grey cells.
    pub samples_per_texel: f64,
    /// Bisection steps after the first inside sample.
    pub refinements: u32,
}

impl Default for MarchSettings {
    /// Two samples a texel (a feature thinner than half a texel can be stepped over) and 24 halvings (below f32
    /// rounding of a cell-sized interval).
    fn default() -> MarchSettings {
        MarchSettings {
            samples_per_texel: 2.0,
            refinements: 24,
        }
    }
}

/// Where a ray meets the complex's surface.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CellHit {
    /// Distance along the ray (in units of its direction's length).
    pub t: f64,
    /// Samples taken before the bisection, over every grey cell crossed.
    pub samples: u32,
}

/// A grey cell's projection and its domain faces' maps, by face index.
struct GreyCell {
    projection: Projection,
    maps: [Option<usize>; 6],
}

/// A grid and its distance maps, ready for rays.
pub struct CellComplex<'a> {
    grid: &'a CellGrid,
    maps: &'a CellMaps,
    grey: HashMap<CellIndex, GreyCell>,
}

impl<'a> CellComplex<'a> {
    /// Indexes `maps` (sampled on `grid`) by cell and face.
    pub fn new(grid: &'a CellGrid, maps: &'a CellMaps) -> CellComplex<'a> {
        let mut grey: HashMap<CellIndex, GreyCell> = HashMap::new();
        for (slot, map) in maps.faces.iter().enumerate() {
            let cell = grey.entry(map.cell).or_insert_with(|| GreyCell {
                projection: Projection::for_cell(grid.internal_faces(map.cell)),
                maps: [None; 6],
            });
            cell.maps[map.face.index()] = Some(slot);
        }
        CellComplex { grid, maps, grey }
    }

    /// The first crossing of the ray `origin + t dir` (t >= 0) with the complex's surface, as the march finds it.
    pub fn march(
        &self,
        origin: [f64; 3],
        dir: [f64; 3],
        settings: MarchSettings,
    ) -> Option<CellHit> {
        let n = self.grid.n() as i64;
        let size = self.grid.cell_size();
        let lo = self.grid.origin();
        let (t_enter, t_leave) = slab_interval(origin, dir, lo, lo.map(|c| c + size * n as f64))?;
        let at = |t: f64| [0, 1, 2].map(|k| origin[k] + t * dir[k]);
        let step_t = size
            / (f64::from(self.maps.resolution) * settings.samples_per_texel)
            / dir.iter().map(|c| c * c).sum::<f64>().sqrt();
        // The traversal: the cell the ray starts in, and per axis the t of its next boundary and the t between two.
        let start = at(t_enter);
        let mut cell =
            [0, 1, 2].map(|k| (((start[k] - lo[k]) / size).floor() as i64).clamp(0, n - 1));
        let mut next = [0.0; 3];
        let mut delta = [f64::INFINITY; 3];
        let mut step = [0i64; 3];
        for k in 0..3 {
            if dir[k] != 0.0 {
                step[k] = if dir[k] > 0.0 { 1 } else { -1 };
                let boundary = lo[k] + size * (cell[k] + i64::from(dir[k] > 0.0)) as f64;
                next[k] = (boundary - origin[k]) / dir[k];
                delta[k] = size / dir[k].abs();
            } else {
                next[k] = f64::INFINITY;
            }
        }
        let mut outside_t = t_enter;
        let mut entered = t_enter;
        let mut samples = 0;
        loop {
            let index = cell.map(|c| c as u32);
            let axis = (0..3)
                .min_by(|&a, &b| next[a].total_cmp(&next[b]))
                .unwrap_or(0);
            let left = next[axis].min(t_leave);
            match self.grid.colour(index) {
                Colour::White => outside_t = left,
                Colour::Black => {
                    let t = self.bisect(at, outside_t, entered, settings.refinements);
                    return Some(CellHit { t, samples });
                }
                Colour::Grey => {
                    let count = ((left - entered) / step_t).ceil().max(1.0) as u32;
                    for i in 1..=count {
                        let t = entered + (left - entered) * f64::from(i) / f64::from(count);
                        samples += 1;
                        if self.inside_cell(index, at(t)) {
                            let t = self.bisect(at, outside_t, t, settings.refinements);
                            return Some(CellHit { t, samples });
                        }
                        outside_t = t;
                    }
                }
            }
            if left >= t_leave {
                return None;
            }
            entered = left;
            cell[axis] += step[axis];
            if !(0..n).contains(&cell[axis]) {
                return None;
            }
            next[axis] += delta[axis];
        }
    }

    /// Whether mesh-space point `p` lies inside the complex's solid (see the module docs).
    pub fn inside(&self, p: [f64; 3]) -> bool {
        let n = i64::from(self.grid.n());
        let lo = self.grid.origin();
        let size = self.grid.cell_size();
        let mut cell = [0u32; 3];
        for k in 0..3 {
            let c = ((p[k] - lo[k]) / size).floor() as i64;
            // A point on the grid's far side belongs to the last cell.
            let c = if c == n && p[k] <= lo[k] + size * n as f64 {
                n - 1
            } else {
                c
            };
            if !(0..n).contains(&c) {
                return false;
            }
            cell[k] = c as u32;
        }
        self.inside_cell(cell, p)
    }

    /// Whether mesh-space point `p`, taken to lie in `cell` (on its boundary at most), is inside.
    fn inside_cell(&self, cell: CellIndex, p: [f64; 3]) -> bool {
        match self.grid.colour(cell) {
            Colour::White => false,
            Colour::Black => true,
            Colour::Grey => {
                let Some(grey) = self.grey.get(&cell) else {
                    return false;
                };
                let local = self.grid.to_cell(cell, p).map(|c| c.clamp(0.0, 1.0));
                // On the projection's own centre or axis a point has no image (a set of measure zero): it counts
                // as outside, and the march's next sample decides.
                let Some(image) = grey.projection.project(local) else {
                    return false;
                };
                let Some(slot) = grey.maps[image.face.index()] else {
                    return false;
                };
                let map = &self.maps.faces[slot];
                let (surface, texel) = bilinear(map, self.maps.resolution, image.uv);
                map.inside(texel, image.distance, surface)
            }
        }
    }

    /// Bisection between an outside `t_out` and an inside `t_in`: the last outside t.
    fn bisect(&self, at: impl Fn(f64) -> [f64; 3], t_out: f64, t_in: f64, steps: u32) -> f64 {
        let (mut out, mut inn) = (t_out, t_in);
        for _ in 0..steps {
            let mid = 0.5 * (out + inn);
            if self.inside(at(mid)) {
                inn = mid;
            } else {
                out = mid;
            }
        }
        0.5 * (out + inn)
    }
}

/// The map's distance at face coordinates `uv`, bilinear between texel centres (clamped at the face's edges),
/// and the nearest texel.
fn bilinear(map: &FaceMap, resolution: u32, uv: [f64; 2]) -> (f64, usize) {
    let r = f64::from(resolution);
    let last = resolution as i64 - 1;
    let x = (uv[0] * r - 0.5).clamp(0.0, last as f64);
    let y = (uv[1] * r - 0.5).clamp(0.0, last as f64);
    let (x0, y0) = (x.floor() as i64, y.floor() as i64);
    let (x1, y1) = ((x0 + 1).min(last), (y0 + 1).min(last));
    let (fx, fy) = (x - x0 as f64, y - y0 as f64);
    let d = |a: i64, b: i64| f64::from(map.distances[(b * (last + 1) + a) as usize]);
    let top = d(x0, y0) + fx * (d(x1, y0) - d(x0, y0));
    let bottom = d(x0, y1) + fx * (d(x1, y1) - d(x0, y1));
    let nearest = (y.round() as i64 * (last + 1) + x.round() as i64) as usize;
    (top + fy * (bottom - top), nearest)
}

/// The t interval where the ray `origin + t dir` (t >= 0) lies in the box `[lo, hi]`, if any.
fn slab_interval(
    origin: [f64; 3],
    dir: [f64; 3],
    lo: [f64; 3],
    hi: [f64; 3],
) -> Option<(f64, f64)> {
    let (mut enter, mut leave) = (0.0f64, f64::INFINITY);
    for k in 0..3 {
        if dir[k] == 0.0 {
            if origin[k] < lo[k] || origin[k] > hi[k] {
                return None;
            }
            continue;
        }
        let (a, b) = ((lo[k] - origin[k]) / dir[k], (hi[k] - origin[k]) / dir[k]);
        enter = enter.max(a.min(b));
        leave = leave.min(a.max(b));
    }
    (enter <= leave).then_some((enter, leave))
}

/// The exact first hit of the ray `origin + t dir` (t >= 0) with the mesh's triangles, and the exact next one
/// after it (where the ray leaves the solid again, for a ray that enters), by testing every triangle.
pub fn exact_hits(
    mesh: &ClosedMesh,
    origin: [f64; 3],
    dir: [f64; 3],
) -> (Option<f64>, Option<f64>) {
    let mut hits: Vec<f64> = (0..mesh.triangles().len())
        .filter_map(|t| ray_triangle(origin, dir, mesh.triangle(t)))
        .collect();
    hits.sort_by(f64::total_cmp);
    // A ray through an edge or a vertex meets every triangle there at one t.
    hits.dedup_by(|b, a| *b - *a < 1e-12 * (1.0 + a.abs()));
    (hits.first().copied(), hits.get(1).copied())
}

#[cfg(test)]
#[path = "trace_tests.rs"]
mod tests;
