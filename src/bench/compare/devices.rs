//! Two files from different devices: per method, the devices ranked by time over the cells both
//! measured, with each one's error beside (a device's rounding can change where rays land).

use super::CellComparison;

/// One method on both devices.
#[derive(Debug, Clone, PartialEq)]
pub struct DeviceRow {
    /// The method id.
    pub method: String,
    /// Cells both devices timed.
    pub cells: usize,
    /// Geometric mean of the cells' median frames, ms: BASE's device then NEW's.
    pub ms: [f64; 2],
    /// Mean of the cells' mean hit errors, texels: BASE's device then NEW's.
    pub error: [f64; 2],
}

impl DeviceRow {
    /// NEW's time over BASE's.
    pub fn ratio(&self) -> f64 {
        self.ms[1] / self.ms[0]
    }

    /// Which side is faster: 0 BASE, 1 NEW.
    pub fn fastest(&self) -> usize {
        usize::from(self.ms[1] < self.ms[0])
    }
}

/// A row per method, in the order the methods first appear; cells without a positive time on
/// both sides are left out (a geometric mean needs them).
pub fn rank_devices(cells: &[CellComparison]) -> Vec<DeviceRow> {
    super::methods_in_order(cells)
        .into_iter()
        .filter_map(|method| {
            let mine: Vec<&CellComparison> = cells
                .iter()
                .filter(|c| c.key.method == method && c.base_ms > 0.0 && c.new_ms > 0.0)
                .collect();
            if mine.is_empty() {
                return None;
            }
            let n = mine.len() as f64;
            let geo = |f: fn(&CellComparison) -> f64| {
                (mine.iter().map(|c| f(c).ln()).sum::<f64>() / n).exp()
            };
            let mean = |side: usize| mine.iter().map(|c| c.error[side]).sum::<f64>() / n;
            Some(DeviceRow {
                method: method.to_owned(),
                cells: mine.len(),
                ms: [geo(|c| c.base_ms), geo(|c| c.new_ms)],
                error: [mean(0), mean(1)],
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::compare::compare;
    use crate::bench::results_fixture::{device, results, run};

    #[test]
    fn each_method_ranks_the_device_that_ran_it_faster() {
        let base = results(
            device("laptop"),
            vec![
                run("pom", 10.0, &[2.0], 0.1),
                run("pom", 30.0, &[8.0], 0.1),
                run("qdm", 30.0, &[1.0], 0.02),
            ],
        );
        let new = results(
            device("workstation"),
            vec![
                run("pom", 10.0, &[1.0], 0.1),
                run("pom", 30.0, &[4.0], 0.1),
                run("qdm", 30.0, &[3.0], 0.04),
            ],
        );
        let rows = rank_devices(&compare(&base, &new, 0.05).cells);
        assert_eq!(rows.len(), 2);
        assert_eq!((rows[0].method.as_str(), rows[0].cells), ("pom", 2));
        assert!((rows[0].ms[0] - 4.0).abs() < 1e-12 && (rows[0].ms[1] - 2.0).abs() < 1e-12);
        assert_eq!(rows[0].fastest(), 1);
        assert_eq!(rows[1].fastest(), 0);
        assert!((rows[1].ratio() - 3.0).abs() < 1e-12);
        assert_eq!(rows[1].error, [0.02, 0.04]);
    }
}
