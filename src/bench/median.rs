//! The medians the bench reports, in one place so that every table agrees on what a median is.

/// `values` sorted ascending (NaN last, by `f64::total_cmp`).
pub fn sorted(values: impl IntoIterator<Item = f64>) -> Vec<f64> {
    let mut sorted: Vec<f64> = values.into_iter().collect();
    sorted.sort_by(f64::total_cmp);
    sorted
}

/// The middle of `values` once sorted, the upper of the two middle ones for an even count, so that
/// the value is always one that was measured: the median of a few timed repeats. NaN when `values`
/// is empty: an empty list has no median, and NaN shows as such in a table where 0 would pass for
/// a measurement.
pub fn median(values: impl IntoIterator<Item = f64>) -> f64 {
    let sorted = sorted(values);
    sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The median of many frame times, `sorted` ascending: the middle one, or the mean of the two
/// middle ones for an even count (the textbook median, which [`crate::bench::GpuMs`] reports). NaN
/// when `sorted` is empty, as [`median`].
pub fn median_of_sorted_frames(sorted: &[f64]) -> f64 {
    let n = sorted.len();
    match n {
        0 => f64::NAN,
        _ if n % 2 == 1 => sorted[n / 2],
        _ => 0.5 * (sorted[n / 2 - 1] + sorted[n / 2]),
    }
}

#[cfg(test)]
mod tests {
    use super::median;

    #[test]
    fn upper_middle_and_nan_when_empty() {
        assert_eq!(median([3.0, 1.0, 2.0]), 2.0);
        assert_eq!(median([4.0, 1.0, 2.0, 3.0]), 3.0);
        assert!(median([]).is_nan());
    }

    #[test]
    fn frames_average_the_two_middles() {
        use super::median_of_sorted_frames;
        assert_eq!(median_of_sorted_frames(&[1.0, 2.0, 3.0]), 2.0);
        assert_eq!(median_of_sorted_frames(&[1.0, 2.0, 3.0, 4.0]), 2.5);
        assert!(median_of_sorted_frames(&[]).is_nan());
    }
}
