//! Whether a method as a whole moved: the median over its cells of their log ratios NEW/BASE,
//! with an interval. On a shared machine one cell's frames can all land in a moment of
//! contention, and a lone cell then reads twice as slow with a tight interval (its frames run
//! back to back); a real change moves a method's cells together. So a cell's verdict counts
//! only when its method moved the same way ([`super::CellComparison::verdict`]).

use super::stats::{median_interval, seed_of, RatioInterval};
use super::verdict::Verdict;
use super::CellComparison;

/// One method's shift over its cells.
#[derive(Debug, Clone, PartialEq)]
pub struct MethodShift {
    /// The method id.
    pub method: String,
    /// Cells with a ratio.
    pub cells: usize,
    /// The median ratio over the cells and its interval; `full_coverage` false when there are
    /// fewer than six cells, whose whole range it then is.
    pub interval: RatioInterval,
    /// What the interval says.
    pub verdict: Verdict,
}

/// A shift per method, in the order the methods first appear among `cells`.
pub fn method_shifts(cells: &[CellComparison], min_effect: f64) -> Vec<MethodShift> {
    super::methods_in_order(cells)
        .into_iter()
        .filter_map(|method| {
            let logs: Vec<f64> = cells
                .iter()
                .filter(|c| c.key.method == method)
                .filter_map(|c| c.interval)
                .map(|i| i.ratio.ln())
                .collect();
            let (median, low, high, full) = median_interval(&logs, seed_of(method))?;
            let interval = RatioInterval {
                ratio: median.exp(),
                low: low.exp(),
                high: high.exp(),
                full_coverage: full,
            };
            Some(MethodShift {
                method: method.to_owned(),
                cells: logs.len(),
                verdict: Verdict::of(Some(&interval), min_effect),
                interval,
            })
        })
        .collect()
}
