//! How far the cell complex's hits are from the mesh's: parallel rays across the mesh's bounds, marched through the
//! complex ([`CellComplex::march`]) and intersected exactly with every triangle ([`exact_hits`]). Errors are in
//! cell sides, the scale the paper's construction works at.

use std::time::Instant;

use super::distance_map::CellMaps;
use super::grid::CellGrid;
use super::mesh::{cross, norm, ClosedMesh};
use super::parallel::map_in_parallel;
use super::trace::{exact_hits, CellComplex, MarchSettings};

/// One ray's outcome: the exact first hit, the exact chord through the solid behind it, and the march's hit
/// with its samples (distances in units of the unit direction; `NaN` where there is none).
#[derive(Debug, Clone, Copy)]
pub struct RayOutcome {
    /// Distance to the exact first hit with the mesh's triangles (`NaN` if the ray misses the mesh).
    pub exact: f64,
    /// Distance from the first exact hit to the second, where the ray leaves the solid (0 when there is no such pair).
    pub chord: f64,
    /// Distance to the march's hit through the cell complex (`NaN` if the march finds none).
    pub marched: f64,
    /// Map samples the march took for this ray (0 when it found no hit).
    pub samples: u32,
}

/// What a batch of rays measured.
#[derive(Debug, Clone, Default, serde::Serialize)]
pub struct HitAgreement {
    /// Rays cast in the batch.
    pub rays: usize,
    /// Rays whose exact chord through the solid is at least two map texels long: they must hit.
    pub solid: usize,
    /// Of those, the ones the march hits, with their mean, 99th percentile and largest error (cell sides).
    pub both: usize,
    /// Mean of `|marched - exact|` over the `both` rays, in cell sides (0 when `both` is 0).
    pub mean_error: f64,
    /// 99th percentile of that error, in cell sides.
    pub p99_error: f64,
    /// Largest such error, in cell sides.
    pub max_error: f64,
    /// Solid rays the march misses.
    pub missed_solid: usize,
    /// Rays that graze the solid (chord under two texels) that the march misses: silhouette texels.
    pub grazing_missed: usize,
    /// The largest error of the grazing rays the march hits (cell sides).
    pub graze_max_error: f64,
    /// Rays that miss the mesh where the march hits (the maps' interpolation widens a silhouette a little), and
    /// the farthest such hit from the mesh (cell sides).
    pub false_hits: usize,
    /// For the `false_hits`, the largest distance from the marched hit to the mesh, in cell sides.
    pub false_hit_max_distance: f64,
    /// Samples the march took per ray, on average.
    pub mean_samples: f64,
    /// Rays marched per second on the CPU (one thread), not counting the exact intersections.
    pub rays_per_second: f64,
}

/// `side` x `side` parallel rays along `dir` (normalized) over a square that covers the mesh's bounding sphere,
/// starting a sphere's diameter before it: (origin, direction) each.
pub fn parallel_rays(mesh: &ClosedMesh, dir: [f64; 3], side: u32) -> Vec<([f64; 3], [f64; 3])> {
    let dir = dir.map(|c| c / norm(dir));
    let helper = if dir[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let u = cross(dir, helper);
    let u = u.map(|c| c / norm(u));
    let v = cross(dir, u);
    let (lo, hi) = mesh.bounds();
    let centre = [0, 1, 2].map(|k| 0.5 * (lo[k] + hi[k]));
    let radius = 0.5 * norm([0, 1, 2].map(|k| hi[k] - lo[k]));
    (0..side * side)
        .map(|i| {
            let [a, b] = [i % side, i / side]
                .map(|x| (2.0 * (f64::from(x) + 0.5) / f64::from(side) - 1.0) * radius);
            let origin = [0, 1, 2].map(|k| centre[k] + a * u[k] + b * v[k] - 2.0 * radius * dir[k]);
            (origin, dir)
        })
        .collect()
}

/// Marches `side` x `side` parallel rays along `dir` ([`parallel_rays`]) through the complex of `grid` and `maps`
/// (built from `mesh`) on the CPU and compares each with the exact hits.
pub fn measure_hits(
    mesh: &ClosedMesh,
    grid: &CellGrid,
    maps: &CellMaps,
    dir: [f64; 3],
    side: u32,
) -> (HitAgreement, Vec<RayOutcome>) {
    let complex = CellComplex::new(grid, maps);
    let rays = parallel_rays(mesh, dir, side);
    let started = Instant::now();
    let marched: Vec<_> = rays
        .iter()
        .map(|&(origin, dir)| {
            complex
                .march(origin, dir, MarchSettings::default())
                .map(|h| (h.t, h.samples))
        })
        .collect();
    let seconds = started.elapsed().as_secs_f64();
    compare_hits(mesh, grid, maps.resolution, &rays, &marched, seconds)
}

/// Compares marched hits (t and samples, `None` for a miss) of `rays` through the complex of `grid` with maps
/// of `resolution`^2 with the exact hits; `march_seconds` is what the march took, for the rays per second.
pub fn compare_hits(
    mesh: &ClosedMesh,
    grid: &CellGrid,
    resolution: u32,
    rays: &[([f64; 3], [f64; 3])],
    marched: &[Option<(f64, u32)>],
    march_seconds: f64,
) -> (HitAgreement, Vec<RayOutcome>) {
    let size = grid.cell_size();
    let mut out = HitAgreement {
        rays: rays.len(),
        ..HitAgreement::default()
    };
    let mut errors = Vec::new();
    let mut outcomes = Vec::with_capacity(rays.len());
    let mut samples = 0u64;
    let exact = map_in_parallel(rays, |&(origin, dir)| exact_hits(mesh, origin, dir));
    for ((&(origin, dir), &hit), &(first, second)) in rays.iter().zip(marched).zip(&exact) {
        let chord = match (first, second) {
            (Some(f), Some(s)) => s - f,
            _ => 0.0,
        };
        samples += u64::from(hit.map_or(0, |h| h.1));
        outcomes.push(RayOutcome {
            exact: first.unwrap_or(f64::NAN),
            chord,
            marched: hit.map_or(f64::NAN, |h| h.0),
            samples: hit.map_or(0, |h| h.1),
        });
        let solid = first.is_some() && chord >= 2.0 * size / f64::from(resolution);
        if solid {
            out.solid += 1;
        }
        match (first, hit) {
            (Some(t), Some((ht, _))) if solid => errors.push((ht - t).abs() / size),
            (Some(_), None) if solid => out.missed_solid += 1,
            (Some(t), Some((ht, _))) => {
                out.graze_max_error = out.graze_max_error.max((ht - t).abs() / size)
            }
            (Some(_), None) => out.grazing_missed += 1,
            (None, Some((ht, _))) => {
                out.false_hits += 1;
                let p = [0, 1, 2].map(|k| origin[k] + ht * dir[k]);
                out.false_hit_max_distance =
                    out.false_hit_max_distance.max(mesh.distance(p) / size);
            }
            (None, None) => {}
        }
    }
    out.both = errors.len();
    if !errors.is_empty() {
        out.mean_error = errors.iter().sum::<f64>() / errors.len() as f64;
        out.max_error = errors.iter().copied().fold(0.0, f64::max);
        errors.sort_by(f64::total_cmp);
        out.p99_error = errors[((errors.len() - 1) as f64 * 0.99).round() as usize];
    }
    out.mean_samples = samples as f64 / rays.len().max(1) as f64;
    out.rays_per_second = rays.len() as f64 / march_seconds.max(1e-9);
    (out, outcomes)
}
