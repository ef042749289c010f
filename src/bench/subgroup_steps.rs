//! What a SIMD machine pays for a loop: the invocations of a subgroup run in lockstep, so the
//! subgroup iterates as often as its slowest ray needs. The mean of those per-subgroup maxima,
//! over the timed rays, tracks GPU time where the mean steps do not: a few long rays cost their
//! whole subgroup.

use serde::{Deserialize, Serialize};

use crate::render::TRACE_GROUP_SIDE;

/// Iteration counts of the timed rays.
#[derive(Debug, Clone, Copy, Default, Serialize, Deserialize, PartialEq)]
pub struct TimedSteps {
    /// Mean iterations per ray.
    pub mean: f64,
    /// Mean over subgroups of the slowest ray's iterations.
    pub subgroup_mean_max: f64,
    /// Lanes per subgroup the maxima were taken over (the device's `subgroupSize`, at most a
    /// workgroup).
    pub subgroup_size: u32,
}

/// Steps of the rays of a `cols x rows` trace grouped as the trace pass runs them: square
/// workgroups of `TRACE_GROUP_SIDE`, invocations numbered row by row inside a workgroup, and
/// consecutive invocations forming subgroups of `subgroup_size` lanes (lanes past the grid's edge
/// are idle). `steps` holds `(steps, capped)` per ray, row by row over the grid.
pub fn subgroup_steps(steps: &[[u32; 2]], grid: (u32, u32), subgroup_size: u32) -> TimedSteps {
    let (cols, rows) = grid;
    let side = TRACE_GROUP_SIDE;
    let lanes = subgroup_size.clamp(1, side * side);
    if steps.len() != cols as usize * rows as usize || steps.is_empty() {
        return TimedSteps::default();
    }
    let mut sum = 0u64;
    let mut maxima = 0u64;
    let mut groups = 0u64;
    for gy in (0..rows).step_by(side as usize) {
        for gx in (0..cols).step_by(side as usize) {
            let mut slowest = None;
            for local in 0..side * side {
                let (x, y) = (gx + local % side, gy + local / side);
                if x < cols && y < rows {
                    let s = steps[(y * cols + x) as usize][0];
                    sum += u64::from(s);
                    slowest = Some(slowest.map_or(s, |m: u32| m.max(s)));
                }
                if (local + 1) % lanes == 0 || local + 1 == side * side {
                    if let Some(m) = slowest.take() {
                        maxima += u64::from(m);
                        groups += 1;
                    }
                }
            }
        }
    }
    TimedSteps {
        mean: sum as f64 / steps.len() as f64,
        subgroup_mean_max: maxima as f64 / groups.max(1) as f64,
        subgroup_size: lanes,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn grid_of(cols: u32, rows: u32, f: impl Fn(u32, u32) -> u32) -> Vec<[u32; 2]> {
        (0..rows)
            .flat_map(|y| (0..cols).map(move |x| (x, y)))
            .map(|(x, y)| [f(x, y), 0])
            .collect()
    }

    #[test]
    fn one_slow_ray_costs_its_whole_subgroup() {
        // 16x8 rays: two workgroups; one ray of 100 steps among rays of 1.
        let steps = grid_of(16, 8, |x, y| if (x, y) == (3, 0) { 100 } else { 1 });
        // Subgroups of 8 are workgroup rows: 16 subgroups, one of them pays 100.
        let t = subgroup_steps(&steps, (16, 8), 8);
        assert_eq!(t.subgroup_size, 8);
        assert!((t.subgroup_mean_max - (15.0 + 100.0) / 16.0).abs() < 1e-12);
        assert!((t.mean - (127.0 + 100.0) / 128.0).abs() < 1e-12);
        // Subgroups of 32 are half workgroups: 4 subgroups.
        let t = subgroup_steps(&steps, (16, 8), 32);
        assert!((t.subgroup_mean_max - (3.0 + 100.0) / 4.0).abs() < 1e-12);
        // A subgroup wider than a workgroup runs one workgroup.
        let t = subgroup_steps(&steps, (16, 8), 128);
        assert_eq!(t.subgroup_size, 64);
        assert!((t.subgroup_mean_max - (1.0 + 100.0) / 2.0).abs() < 1e-12);
    }

    #[test]
    fn lanes_follow_the_workgroup_layout_not_the_grid_rows() {
        // Steps equal to the column: a subgroup of 8 is one workgroup row, columns 0..8 or 8..16,
        // so its slowest ray is column 7 or 15, never a grid-row-wide maximum.
        let steps = grid_of(16, 8, |x, _| x);
        let t = subgroup_steps(&steps, (16, 8), 8);
        assert!((t.subgroup_mean_max - 11.0).abs() < 1e-12);
    }

    #[test]
    fn idle_lanes_past_the_edge_do_not_count() {
        // 10x3 grid: the second workgroup column holds 2x3 rays; its subgroups of 8 lanes hold
        // 2 rays each (one per row), the rest idle.
        let steps = grid_of(10, 3, |x, _| if x >= 8 { 5 } else { 2 });
        let t = subgroup_steps(&steps, (10, 3), 8);
        assert!((t.subgroup_mean_max - (3.0 * 2.0 + 3.0 * 5.0) / 6.0).abs() < 1e-12);
        assert_eq!(subgroup_steps(&steps, (5, 3), 8), TimedSteps::default());
    }
}
