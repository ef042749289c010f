//! What a cell's interval says: faster, slower, or within noise. A difference counts only when
//! the whole interval lies beyond a band of practical indifference around 1, so a tiny shift
//! that many frames make "significant" on a noisy device does not raise an alarm (the rule
//! criterion uses with its noise threshold).

use std::fmt;

use super::stats::RatioInterval;

/// The band: ratios within `[1 / (1 + min_effect), 1 + min_effect]` are no practical change.
pub const DEFAULT_MIN_EFFECT: f64 = 0.05;

/// A cell's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// The whole interval is below the band.
    Faster,
    /// The whole interval is above the band.
    Slower,
    /// The interval reaches into the band (or no ratio could be formed).
    WithinNoise,
}

impl Verdict {
    /// The verdict of `interval` for a band of `min_effect` (0.05: 5%).
    pub fn of(interval: Option<&RatioInterval>, min_effect: f64) -> Verdict {
        let Some(r) = interval else {
            return Verdict::WithinNoise;
        };
        let up = 1.0 + min_effect;
        if r.low > up {
            Verdict::Slower
        } else if r.high < 1.0 / up {
            Verdict::Faster
        } else {
            Verdict::WithinNoise
        }
    }
}

impl fmt::Display for Verdict {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Verdict::Faster => "faster",
            Verdict::Slower => "slower",
            Verdict::WithinNoise => "within noise",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn interval(low: f64, high: f64) -> RatioInterval {
        RatioInterval {
            ratio: (low + high) / 2.0,
            low,
            high,
            full_coverage: true,
        }
    }

    #[test]
    fn only_intervals_wholly_beyond_the_band_count() {
        let v = |low, high| Verdict::of(Some(&interval(low, high)), 0.05);
        assert_eq!(v(1.2, 1.8), Verdict::Slower);
        assert_eq!(v(0.5, 0.9), Verdict::Faster);
        assert_eq!(v(0.9, 1.1), Verdict::WithinNoise);
        // Beyond 1 but not beyond the band: significant, not practical.
        assert_eq!(v(1.01, 1.04), Verdict::WithinNoise);
        assert_eq!(v(1.04, 1.3), Verdict::WithinNoise);
        assert_eq!(
            Verdict::of(Some(&interval(1.01, 1.04)), 0.0),
            Verdict::Slower
        );
        assert_eq!(Verdict::of(None, 0.05), Verdict::WithinNoise);
    }
}
