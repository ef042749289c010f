//! The median the bench tables report.

/// The middle of `values` once sorted, the upper of the two middle ones for an even count, so that
/// the value is always one that was measured. NaN when `values` is empty: an empty list has no
/// median, and NaN shows as such in a table where 0 would pass for a measurement.
///
/// [`crate::bench::GpuMs`] averages the two middle frame times instead; its median is a statistic
/// of many frames, these are of a few timed repeats.
pub fn median(values: impl IntoIterator<Item = f64>) -> f64 {
    let mut sorted: Vec<f64> = values.into_iter().collect();
    sorted.sort_by(f64::total_cmp);
    sorted.get(sorted.len() / 2).copied().unwrap_or(f64::NAN)
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
}
