//! `relief render --frame-range A..B`: a slice of a frame sequence, so that a render farm can hand
//! each worker its own frames. Frames are numbered from 1 like the files (`STEM_0001.png` is
//! frame 1) and both ends are inclusive, as farm managers count them: `1..30` and `31..60` split
//! a sequence of 60 frames in two.

use std::ops::Range;
use std::str::FromStr;

/// Frames `first` to `last` of a sequence, 1-based, both included.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct FrameRange {
    pub first: u32,
    pub last: u32,
}

impl FromStr for FrameRange {
    type Err = String;

    fn from_str(text: &str) -> Result<FrameRange, String> {
        let expected = "expected A..B, 1-based and inclusive, e.g. 1..30";
        let (a, b) = text
            .split_once("..")
            .ok_or_else(|| format!("{text:?}: {expected}"))?;
        let number = |s: &str| {
            s.trim()
                .parse::<u32>()
                .map_err(|_| format!("{text:?}: {s:?} is not a frame number ({expected})"))
        };
        let (first, last) = (number(a)?, number(b)?);
        if first == 0 {
            return Err(format!("{text:?}: frames are numbered from 1 ({expected})"));
        }
        if first > last {
            return Err(format!(
                "{text:?}: the first frame {first} comes after the last {last}"
            ));
        }
        Ok(FrameRange { first, last })
    }
}

impl FrameRange {
    /// The 0-based frame indices of this range in a sequence of `frames`, or why it does not fit.
    pub fn within(self, frames: u32) -> anyhow::Result<Range<u32>> {
        if self.last > frames {
            anyhow::bail!(
                "--frame-range {}..{} ends past the sequence, which has {frames} frame(s)",
                self.first,
                self.last
            );
        }
        Ok(self.first - 1..self.last)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_range_is_one_based_and_inclusive() {
        let r: FrameRange = "3..5".parse().expect("a valid range");
        assert_eq!(r, FrameRange { first: 3, last: 5 });
        assert_eq!(r.within(5).expect("fits"), 2..5);
        assert_eq!(
            "7..7".parse::<FrameRange>().unwrap().within(9).unwrap(),
            6..7
        );
    }

    #[test]
    fn bad_ranges_say_what_is_wrong() {
        for (text, needle) in [
            ("5", "expected A..B"),
            ("a..3", "not a frame number"),
            ("1..", "not a frame number"),
            ("-1..3", "not a frame number"),
            ("0..3", "numbered from 1"),
            ("4..2", "comes after"),
        ] {
            let err = text.parse::<FrameRange>().expect_err(text);
            assert!(err.contains(needle), "{text}: {err}");
        }
        let past = FrameRange { first: 2, last: 11 }.within(10);
        let err = past.expect_err("11 > 10").to_string();
        assert!(err.contains("10 frame(s)"), "{err}");
    }
}
