//! JSON has no NaN: serde_json writes a NaN `f64` as `null`. Fields that may hold NaN (a failed
//! case's error) read `null` back as NaN with [`f64_or_nan`], so a file that relief wrote is
//! always one it can read.

use serde::{Deserialize, Deserializer};

/// A number, or NaN for `null`.
pub(crate) fn f64_or_nan<'de, D: Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    Ok(Option::<f64>::deserialize(d)?.unwrap_or(f64::NAN))
}

#[cfg(test)]
mod tests {
    use serde::Deserialize;

    #[derive(Deserialize)]
    struct Cell {
        #[serde(deserialize_with = "super::f64_or_nan")]
        error: f64,
    }

    #[test]
    fn null_reads_as_nan_and_numbers_as_themselves() {
        let nan: Cell = serde_json::from_str(r#"{"error": null}"#).unwrap();
        assert!(nan.error.is_nan());
        let one: Cell = serde_json::from_str(r#"{"error": 1.5}"#).unwrap();
        assert_eq!(one.error, 1.5);
        assert!(serde_json::from_str::<Cell>(r#"{"error": "x"}"#).is_err());
    }
}
