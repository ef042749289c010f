//! The time ratio NEW/BASE of one cell with a confidence interval, from the two runs' frame
//! samples.
//!
//! The estimate is the ratio of the two medians (a frame that a busy machine stalls moves a mean,
//! not a median). Its interval is the hull of two intervals:
//! - a percentile bootstrap: both sample sets resampled with replacement [`RESAMPLES`] times, the
//!   ratio of medians of each pair, the central [`CONFIDENCE`] of them. It reflects both sides'
//!   spread jointly, but with a handful of frames a resampled median takes only a few values and
//!   the percentiles come out too narrow;
//! - a distribution-free one: on each side the order statistics that hold the median with at
//!   least [`CONFIDENCE`] (from the binomial distribution, as the sign test does), their ratios
//!   crossed. Its coverage holds for any distribution; with fewer than six frames no pair of order
//!   statistics reaches it, and the side falls back to its whole range, which the result marks.
//!
//! Random draws come from a SplitMix64 stream seeded by the cell, so a comparison prints the same
//! numbers every time it is run on the same files.

use crate::bench::median::{median_of_sorted_frames, sorted};
use crate::heightfield::rng::SplitMix64;

/// Bootstrap resamples per cell.
pub const RESAMPLES: usize = 2000;
/// The interval's nominal coverage.
pub const CONFIDENCE: f64 = 0.95;

/// A ratio NEW/BASE with its interval.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RatioInterval {
    /// Median of NEW over median of BASE.
    pub ratio: f64,
    /// Lower end of the interval.
    pub low: f64,
    /// Upper end of the interval.
    pub high: f64,
    /// Whether each side had enough frames for the distribution-free interval to reach
    /// [`CONFIDENCE`]; when false the interval is the samples' whole range and covers less.
    pub full_coverage: bool,
}

/// The ratio of medians of `new` over `base` and its interval; `None` when a side has no
/// samples or a median that is not a positive number (nothing to divide by).
pub fn ratio_interval(base: &[f64], new: &[f64], seed: u64) -> Option<RatioInterval> {
    let (b, n) = (sorted(base.iter().copied()), sorted(new.iter().copied()));
    let (mb, mn) = (median_of_sorted_frames(&b), median_of_sorted_frames(&n));
    if !(mb > 0.0 && mn.is_finite() && mb.is_finite()) || b.is_empty() || n.is_empty() {
        return None;
    }
    let (b_low, b_high, b_full) = median_bounds(&b);
    let (n_low, n_high, n_full) = median_bounds(&n);
    let (boot_low, boot_high) = bootstrap(&b, &n, seed);
    let low = (n_low / b_high.max(f64::MIN_POSITIVE)).min(boot_low);
    let high = if b_low > 0.0 {
        (n_high / b_low).max(boot_high)
    } else {
        f64::INFINITY
    };
    Some(RatioInterval {
        ratio: mn / mb,
        low,
        high,
        full_coverage: b_full && n_full,
    })
}

/// The median of `values` with its interval, for the spread of many cells' log ratios: the hull
/// of the bootstrap percentile interval of the median and the order statistics that hold it (as
/// [`ratio_interval`] does for each side's frames). `None` for no values.
pub fn median_interval(values: &[f64], seed: u64) -> Option<(f64, f64, f64, bool)> {
    let v = sorted(values.iter().copied());
    if v.is_empty() || !v.iter().all(|x| x.is_finite()) {
        return None;
    }
    let (low, high, full) = median_bounds(&v);
    let mut rng = SplitMix64::new(seed);
    let mut draw = Vec::with_capacity(v.len());
    let mut medians: Vec<f64> = (0..RESAMPLES)
        .map(|_| {
            draw.clear();
            draw.extend((0..v.len()).map(|_| v[rng.below(v.len() as u32) as usize]));
            draw.sort_by(f64::total_cmp);
            median_of_sorted_frames(&draw)
        })
        .collect();
    medians.sort_by(f64::total_cmp);
    let (boot_low, boot_high) = central(&medians);
    Some((
        median_of_sorted_frames(&v),
        low.min(boot_low),
        high.max(boot_high),
        full,
    ))
}

/// The central [`CONFIDENCE`] of `sorted` values.
fn central(sorted: &[f64]) -> (f64, f64) {
    let last = sorted.len() - 1;
    let at = |q: f64| sorted[((q * last as f64).round() as usize).min(last)];
    let tail = (1.0 - CONFIDENCE) / 2.0;
    (at(tail), at(1.0 - tail))
}

/// The order statistics `x_(k) <= median <= x_(n+1-k)` for the largest `k` whose coverage
/// `1 - 2 P(Binomial(n, 1/2) < k)` is at least [`CONFIDENCE`]; the whole range, and `false`,
/// when even `k = 1` falls short.
fn median_bounds(sorted: &[f64]) -> (f64, f64, bool) {
    let n = sorted.len();
    let tail = (1.0 - CONFIDENCE) / 2.0;
    let mut below = binomial_half_pmf(n, 0); // P(B <= cut)
    if below > tail {
        return (sorted[0], sorted[n - 1], false);
    }
    let mut cut = 0; // values cut from each end
    while cut < (n - 1) / 2 {
        let next = below + binomial_half_pmf(n, cut + 1);
        if next > tail {
            break;
        }
        (cut, below) = (cut + 1, next);
    }
    (sorted[cut], sorted[n - 1 - cut], true)
}

/// `P(B = k)` for `B ~ Binomial(n, 1/2)`, in floating point (exact enough for n in the hundreds).
fn binomial_half_pmf(n: usize, k: usize) -> f64 {
    let mut log = -(n as f64) * std::f64::consts::LN_2;
    for i in 0..k {
        log += ((n - i) as f64).ln() - ((i + 1) as f64).ln();
    }
    log.exp()
}

/// The central [`CONFIDENCE`] of the bootstrap ratios of medians.
fn bootstrap(base: &[f64], new: &[f64], seed: u64) -> (f64, f64) {
    let mut rng = SplitMix64::new(seed);
    let mut draw = |from: &[f64], into: &mut Vec<f64>| {
        into.clear();
        into.extend((0..from.len()).map(|_| from[rng.below(from.len() as u32) as usize]));
        into.sort_by(f64::total_cmp);
        median_of_sorted_frames(into)
    };
    let (mut bs, mut ns) = (Vec::new(), Vec::new());
    let mut ratios: Vec<f64> = (0..RESAMPLES)
        .map(|_| {
            let b = draw(base, &mut bs);
            draw(new, &mut ns) / b
        })
        .collect();
    ratios.sort_by(f64::total_cmp);
    central(&ratios)
}

/// A stable seed for a cell from its label (FNV-1a), so each cell draws its own stream and the
/// same cell draws the same one in every run of `compare`.
pub fn seed_of(label: &str) -> u64 {
    label.bytes().fold(0xcbf2_9ce4_8422_2325, |h, b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bench::compare::Verdict;

    /// Frame times around `ms` with a deterministic spread of about +-10%.
    fn frames(ms: f64, count: usize, seed: u64) -> Vec<f64> {
        let mut rng = SplitMix64::new(seed);
        (0..count)
            .map(|_| ms * (0.9 + 0.2 * f64::from(rng.next_f32())))
            .collect()
    }

    #[test]
    fn identical_samples_give_a_ratio_of_one_inside_the_interval() {
        let a = frames(2.0, 10, 1);
        let r = ratio_interval(&a, &a, 7).unwrap();
        assert_eq!(r.ratio, 1.0);
        assert!(r.low < 1.0 && r.high > 1.0, "{r:?}");
        assert!(r.full_coverage);
        assert_eq!(Verdict::of(Some(&r), 0.05), Verdict::WithinNoise);
    }

    #[test]
    fn samples_scaled_by_one_and_a_half_give_that_ratio() {
        let a = frames(2.0, 10, 1);
        let b: Vec<f64> = a.iter().map(|x| 1.5 * x).collect();
        let r = ratio_interval(&a, &b, 7).unwrap();
        assert!((r.ratio - 1.5).abs() < 1e-12, "{r:?}");
        assert!(r.low < 1.5 && r.high > 1.5 && r.low > 1.2, "{r:?}");
        assert_eq!(Verdict::of(Some(&r), 0.05), Verdict::Slower);
    }

    #[test]
    fn the_interval_holds_the_true_ratio_in_most_repeats() {
        // Independent draws of the same +-10% noise, the new side 1.3 times slower: the true
        // ratio of medians is 1.3, and a 95% interval must hold it nearly always.
        let mut held = 0;
        for k in 0..200 {
            let base = frames(1.0, 10, 2 * k);
            let new = frames(1.3, 10, 2 * k + 1);
            let r = ratio_interval(&base, &new, k).unwrap();
            held += usize::from(r.low <= 1.3 && 1.3 <= r.high);
        }
        assert!(held >= 190, "held the true ratio {held} times in 200");
    }

    #[test]
    fn three_frames_give_the_whole_range_and_say_so() {
        let base = [1.0, 1.1, 0.9];
        let new = [1.0, 1.05, 0.95];
        let r = ratio_interval(&base, &new, 3).unwrap();
        assert!(!r.full_coverage);
        assert!((r.low - 0.95 / 1.1).abs() < 1e-12, "{r:?}");
        assert!((r.high - 1.05 / 0.9).abs() < 1e-12, "{r:?}");
    }

    #[test]
    fn order_statistics_match_the_sign_test_tables() {
        // n = 6: only the extremes (coverage 96.9%); n = 10: the 2nd and 9th (97.9%);
        // n = 20: the 6th and 15th (95.9%).
        let values = |n: usize| (1..=n).map(|i| i as f64).collect::<Vec<_>>();
        assert_eq!(median_bounds(&values(6)), (1.0, 6.0, true));
        assert_eq!(median_bounds(&values(10)), (2.0, 9.0, true));
        assert_eq!(median_bounds(&values(20)), (6.0, 15.0, true));
        assert_eq!(median_bounds(&values(5)), (1.0, 5.0, false));
        assert_eq!(median_bounds(&values(1)), (1.0, 1.0, false));
    }

    #[test]
    fn the_median_of_many_cells_holds_its_centre_and_ignores_a_few_wild_ones() {
        // Twenty cells near 0 in log ratio and three lone jumps of a factor 2.
        let mut values: Vec<f64> = frames(1.0, 20, 8).iter().map(|x| x.ln()).collect();
        values.extend([2f64.ln(), 2f64.ln(), 0.5f64.ln()]);
        let (median, low, high, full) = median_interval(&values, 1).unwrap();
        assert!(
            full && low < median && median < high,
            "{low} {median} {high}"
        );
        assert!(low > -0.1 && high < 0.1, "{low} {high}");
        assert!(median_interval(&[], 1).is_none());
    }

    #[test]
    fn nothing_to_divide_gives_none_and_the_same_seed_the_same_interval() {
        assert!(ratio_interval(&[], &[1.0], 1).is_none());
        assert!(ratio_interval(&[0.0], &[1.0], 1).is_none());
        let (a, b) = (frames(1.0, 8, 4), frames(1.1, 8, 5));
        assert_eq!(ratio_interval(&a, &b, 9), ratio_interval(&a, &b, 9));
        assert_ne!(seed_of("pom 30"), seed_of("pom 31"));
    }
}
