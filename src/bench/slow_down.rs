//! `relief bench --slow-down METHOD=FACTOR`: a method made slower on purpose, for testing that
//! `relief bench compare` catches a regression. The timed pass dispatches that method's trace
//! FACTOR times per timed frame, so its GPU time grows by about FACTOR on any device, while its
//! hits (the last dispatch's) and error stay the same.

use std::fmt;
use std::str::FromStr;

use crate::method::Method;

/// The most dispatches per frame: enough to show any slow-down, few enough to keep a run short.
pub const MAX_SLOW_DOWN: u32 = 16;

/// One method's trace dispatched `factor` times per timed frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct SlowDown {
    /// The method slowed.
    pub method: Method,
    /// Dispatches per timed frame, 2..=[`MAX_SLOW_DOWN`].
    pub factor: u32,
}

impl FromStr for SlowDown {
    type Err = String;

    /// Parses `METHOD=FACTOR`, e.g. `pom=2`.
    fn from_str(s: &str) -> Result<SlowDown, String> {
        let (method, factor) = s
            .split_once('=')
            .ok_or_else(|| format!("expected METHOD=FACTOR (e.g. pom=2), got {s:?}"))?;
        let method: Method = method.parse().map_err(|e| format!("{e}"))?;
        let factor = factor
            .parse::<u32>()
            .ok()
            .filter(|f| (2..=MAX_SLOW_DOWN).contains(f))
            .ok_or_else(|| {
                format!("the factor must be a whole number in 2..={MAX_SLOW_DOWN}, got {factor:?}")
            })?;
        Ok(SlowDown { method, factor })
    }
}

/// `METHOD=FACTOR`, as it is parsed.
impl fmt::Display for SlowDown {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}={}", self.method, self.factor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_method_and_factor_and_names_what_is_wrong() {
        let s: SlowDown = "pom=3".parse().unwrap();
        assert_eq!((s.method, s.factor), (Method::POM, 3));
        assert_eq!(s.to_string(), "pom=3");
        assert!("pom"
            .parse::<SlowDown>()
            .unwrap_err()
            .contains("METHOD=FACTOR"));
        assert!("nope=2".parse::<SlowDown>().unwrap_err().contains("nope"));
        for bad in ["pom=1", "pom=0", "pom=17", "pom=1.5", "pom=x"] {
            assert!(
                bad.parse::<SlowDown>().unwrap_err().contains("2..=16"),
                "{bad}"
            );
        }
    }
}
