//! `relief bench compare`: two results files cell by cell. Each cell the two share gets the time
//! ratio NEW/BASE with a confidence interval from the frame samples ([`ratio_interval`]), the
//! change of its error, and a verdict ([`Verdict`]) that counts only when the cell's method moved
//! the same way as a whole ([`method_shifts`]); cells only one file has are listed, not dropped.
//! Files from different devices get a ranking of the devices per method instead of verdicts
//! ([`rank_devices`]), since a ratio across devices is a comparison, not a regression.
//!
//! Only the sweep's runs (`results.json`'s `runs`) are compared; the other sections are reported
//! by `relief bench` itself.

mod devices;
mod key;
mod method_shift;
mod plot;
mod stats;
mod table;
mod verdict;

pub use devices::{rank_devices, DeviceRow};
pub use key::{match_cells, CellKey, Matched};
pub use method_shift::{method_shifts, MethodShift};
pub use plot::ratio_plot;
pub use stats::{median_interval, ratio_interval, seed_of, RatioInterval, CONFIDENCE, RESAMPLES};
pub use table::{markdown_report, terminal_report};
pub use verdict::{Verdict, DEFAULT_MIN_EFFECT};

use super::provenance::{BenchDevice, ReliefBuild};
use super::results::{BenchResults, Run};

/// What one side of a comparison was.
#[derive(Debug, Clone)]
pub struct Side {
    /// The device it was measured on.
    pub device: BenchDevice,
    /// The relief that measured it.
    pub relief: ReliefBuild,
    /// When, RFC 3339 UTC.
    pub date: String,
    /// The command line.
    pub command: String,
}

impl From<&BenchResults> for Side {
    fn from(r: &BenchResults) -> Self {
        Side {
            device: r.device.clone(),
            relief: r.relief.clone(),
            date: r.date.clone(),
            command: r.command.clone(),
        }
    }
}

/// One cell both files have.
#[derive(Debug, Clone)]
pub struct CellComparison {
    /// Which cell.
    pub key: CellKey,
    /// BASE's median frame, ms.
    pub base_ms: f64,
    /// NEW's median frame, ms.
    pub new_ms: f64,
    /// Frame samples on each side, BASE then NEW.
    pub frames: [usize; 2],
    /// NEW/BASE with its interval; `None` when a side has no usable time.
    pub interval: Option<RatioInterval>,
    /// What the cell's own interval says, for the comparison's band.
    pub own: Verdict,
    /// The verdict: `own` when the cell's method moved the same way, else within noise (a cell
    /// that moved alone).
    pub verdict: Verdict,
    /// Mean hit error in texels, BASE then NEW.
    pub error: [f64; 2],
}

impl CellComparison {
    fn of(base: &Run, new: &Run, min_effect: f64) -> CellComparison {
        let key = CellKey::of(base);
        let interval = ratio_interval(
            &base.gpu_ms.samples,
            &new.gpu_ms.samples,
            seed_of(&key.to_string()),
        );
        let own = Verdict::of(interval.as_ref(), min_effect);
        CellComparison {
            own,
            verdict: own,
            key,
            base_ms: base.gpu_ms.median,
            new_ms: new.gpu_ms.median,
            frames: [base.gpu_ms.samples.len(), new.gpu_ms.samples.len()],
            interval,
            error: [base.error_texels.mean, new.error_texels.mean],
        }
    }

    /// Whether the cell's own interval is beyond the band but its method did not move with it.
    pub fn alone(&self) -> bool {
        self.own != Verdict::WithinNoise && self.verdict == Verdict::WithinNoise
    }

    /// NEW's mean error minus BASE's, in texels.
    pub fn error_change(&self) -> f64 {
        self.error[1] - self.error[0]
    }
}

/// The methods of `cells`, in the order they first appear.
fn methods_in_order(cells: &[CellComparison]) -> Vec<&str> {
    let mut methods: Vec<&str> = Vec::new();
    for c in cells {
        if !methods.contains(&c.key.method.as_str()) {
            methods.push(&c.key.method);
        }
    }
    methods
}

/// An option that differs between the two runs, as JSON text on each side.
#[derive(Debug, Clone, PartialEq)]
pub struct OptionChange {
    /// The option's name in `results.json`'s `options`.
    pub name: String,
    /// BASE's value, or `-` when it has none.
    pub base: String,
    /// NEW's value, or `-`.
    pub new: String,
}

/// Two files compared.
#[derive(Debug, Clone)]
pub struct Comparison {
    /// The first file.
    pub base: Side,
    /// The second file.
    pub new: Side,
    /// Whether both were measured on one device (else the verdicts give way to a ranking).
    pub same_device: bool,
    /// The band of practical indifference (0.05: ratios within 5% are no change).
    pub min_effect: f64,
    /// Cells both have, in BASE's order.
    pub cells: Vec<CellComparison>,
    /// Each method's shift over its cells.
    pub methods: Vec<MethodShift>,
    /// Cells only BASE has.
    pub only_base: Vec<CellKey>,
    /// Cells only NEW has.
    pub only_new: Vec<CellKey>,
    /// The sweep options that differ.
    pub option_changes: Vec<OptionChange>,
}

impl Comparison {
    /// How many cells are faster, slower and within noise.
    pub fn counts(&self) -> [usize; 3] {
        let count = |v: Verdict| self.cells.iter().filter(|c| c.verdict == v).count();
        [
            count(Verdict::Faster),
            count(Verdict::Slower),
            count(Verdict::WithinNoise),
        ]
    }

    /// Cells beyond the band whose method did not move with them.
    pub fn alone(&self) -> usize {
        self.cells.iter().filter(|c| c.alone()).count()
    }

    /// The cells slower beyond noise whose whole interval lies above `ratio`: what
    /// `--fail-above` fails on.
    pub fn slower_above(&self, ratio: f64) -> Vec<&CellComparison> {
        self.cells
            .iter()
            .filter(|c| c.verdict == Verdict::Slower)
            .filter(|c| c.interval.is_some_and(|i| i.low > ratio))
            .collect()
    }
}

/// Compares `new` with `base`, ratios within `min_effect` of 1 counting as no change.
pub fn compare(base: &BenchResults, new: &BenchResults, min_effect: f64) -> Comparison {
    let matched = match_cells(&base.runs, &new.runs);
    let mut cells: Vec<CellComparison> = matched
        .pairs
        .iter()
        .map(|(b, n)| CellComparison::of(b, n, min_effect))
        .collect();
    let methods = method_shifts(&cells, min_effect);
    for cell in &mut cells {
        let method = methods.iter().find(|m| m.method == cell.key.method);
        if method.is_none_or(|m| m.verdict != cell.own) {
            cell.verdict = Verdict::WithinNoise;
        }
    }
    Comparison {
        base: base.into(),
        new: new.into(),
        same_device: base.device.same_as(&new.device),
        min_effect,
        cells,
        methods,
        only_base: matched.only_base.iter().map(|r| CellKey::of(r)).collect(),
        only_new: matched.only_new.iter().map(|r| CellKey::of(r)).collect(),
        option_changes: option_changes(base, new),
    }
}

/// The options whose values differ, field by field of their JSON, so that an option added to
/// the schema shows here without a line of its own.
fn option_changes(base: &BenchResults, new: &BenchResults) -> Vec<OptionChange> {
    let as_map = |r: &BenchResults| match serde_json::to_value(&r.options) {
        Ok(serde_json::Value::Object(map)) => map,
        _ => serde_json::Map::new(),
    };
    let (b, n) = (as_map(base), as_map(new));
    let mut names: Vec<&String> = b.keys().chain(n.keys()).collect();
    names.sort();
    names.dedup();
    let text = |v: Option<&serde_json::Value>| v.map_or("-".to_owned(), |v| v.to_string());
    names
        .into_iter()
        .filter(|name| b.get(*name) != n.get(*name))
        .map(|name| OptionChange {
            name: name.clone(),
            base: text(b.get(name)),
            new: text(n.get(name)),
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::results_fixture::{device, results, run};

    fn frames(ms: f64, seed: u64) -> Vec<f64> {
        let mut rng = crate::heightfield::rng::SplitMix64::new(seed);
        (0..10)
            .map(|_| ms * (0.95 + 0.1 * f64::from(rng.next_f32())))
            .collect()
    }

    #[test]
    fn a_method_made_slower_is_flagged_and_the_rest_are_not() {
        let base = results(
            device("gpu"),
            vec![
                run("pom", 30.0, &frames(1.0, 1), 0.1),
                run("qdm", 30.0, &frames(2.0, 2), 0.01),
            ],
        );
        let new = results(
            device("gpu"),
            vec![
                run("pom", 30.0, &frames(1.0, 3), 0.1),
                run("qdm", 30.0, &frames(3.0, 4), 0.02),
            ],
        );
        let c = compare(&base, &new, DEFAULT_MIN_EFFECT);
        assert!(c.same_device);
        assert_eq!(c.cells[0].verdict, Verdict::WithinNoise);
        assert_eq!(c.cells[1].verdict, Verdict::Slower);
        let r = c.cells[1].interval.unwrap();
        assert!((r.ratio - 1.5).abs() < 0.1, "{r:?}");
        assert!((c.cells[1].error_change() - 0.01).abs() < 1e-12);
        assert_eq!(c.counts(), [0, 1, 1]);
        assert_eq!(c.slower_above(1.2).len(), 1);
        assert!(c.slower_above(1.6).is_empty());
    }

    #[test]
    fn a_cell_that_moved_alone_is_not_counted() {
        let angles = [5.0, 10.0, 20.0, 30.0, 45.0, 60.0, 75.0, 90.0];
        let base_runs = angles
            .iter()
            .zip(1..)
            .map(|(&a, k)| run("pom", a, &frames(1.0, k), 0.1))
            .collect();
        let new_runs = angles
            .iter()
            .zip(100..)
            .map(|(&a, k)| {
                let ms = if a == 30.0 { 2.0 } else { 1.0 };
                run("pom", a, &frames(ms, k), 0.1)
            })
            .collect();
        let c = compare(
            &results(device("gpu"), base_runs),
            &results(device("gpu"), new_runs),
            DEFAULT_MIN_EFFECT,
        );
        let lone = c.cells.iter().find(|x| x.key.angle_deg == 30.0).unwrap();
        assert_eq!(
            (lone.own, lone.verdict),
            (Verdict::Slower, Verdict::WithinNoise)
        );
        assert!(lone.alone());
        assert_eq!(c.counts(), [0, 0, 8]);
        assert_eq!(c.alone(), 1);
        assert_eq!(c.methods[0].verdict, Verdict::WithinNoise);
        assert!(c.slower_above(1.0).is_empty());
    }

    #[test]
    fn cells_on_one_side_and_changed_options_are_listed() {
        let base = results(device("gpu"), vec![run("pom", 30.0, &[1.0], 0.1)]);
        let mut new = results(device("other gpu"), vec![run("qdm", 30.0, &[1.0], 0.1)]);
        new.options.frames = 7;
        let c = compare(&base, &new, DEFAULT_MIN_EFFECT);
        assert!(!c.same_device);
        assert!(c.cells.is_empty());
        assert_eq!((c.only_base.len(), c.only_new.len()), (1, 1));
        assert_eq!(c.only_new[0].method, "qdm");
        let frames = c
            .option_changes
            .iter()
            .find(|o| o.name == "frames")
            .unwrap();
        assert_eq!((frames.base.as_str(), frames.new.as_str()), ("3", "7"));
        assert_eq!(c.option_changes.len(), 1);
    }
}
