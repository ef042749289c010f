//! Level of detail of a relief material (Drobot section 1.4's mixed automatic LOD, Ki and Oh
//! section 2.5's averaged pyramid): plain data parsed from `extras.relief.lod` and set by
//! `relief render --lod`; the renderer turns it into a pipeline variant and specialization
//! constants (shaders/include/lod.glsl).
//!
//! Invariant: every field is finite, `factor >= 0`, `fade_start >= 0`, and `fade_end` is either 0
//! (no fade) or above `fade_start`, so `Lod` can be `Eq` and hashed into pipeline keys.

use serde_json::{Map, Value};

/// How a relief material trades detail for time with distance and view angle.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lod {
    /// Multiplies the per-pixel mip level of the height map to give the traversal's stop level
    /// (Drobot's artist factor); 0 keeps full detail everywhere.
    pub factor: f32,
    /// Added to the scaled mip level, in levels.
    pub bias: f32,
    /// World distance from the eye at which the relief starts fading to plain normal mapping.
    pub fade_start: f32,
    /// Distance at which the fade is complete and nothing is traced; 0: no fade.
    pub fade_end: f32,
    /// Stop levels below this one end on Ki and Oh's averaged (mean) pyramid instead of the max
    /// pyramid's planes; 0 never uses it (and the mean pyramid is not built).
    pub average_below: u32,
}

// Finite fields only (checked where a `Lod` is made), so equality is reflexive.
impl Eq for Lod {}

impl Default for Lod {
    fn default() -> Lod {
        Lod {
            factor: 1.0,
            bias: 0.0,
            fade_start: 0.0,
            fade_end: 0.0,
            average_below: 16,
        }
    }
}

impl std::hash::Hash for Lod {
    fn hash<H: std::hash::Hasher>(&self, state: &mut H) {
        for x in [self.factor, self.bias, self.fade_start, self.fade_end] {
            x.to_bits().hash(state);
        }
        self.average_below.hash(state);
    }
}

impl Lod {
    /// The fields `extras.relief.lod` accepts.
    pub const KEYS: [&'static str; 5] =
        ["factor", "bias", "fade_start", "fade_end", "average_below"];

    /// Whether some stop level can use the averaged pyramid, so it must be built.
    pub fn uses_mean_pyramid(&self) -> bool {
        self.average_below > 0 && self.factor > 0.0
    }

    /// Checks the invariant; the message names the field (`field` is its parent's path).
    pub fn validate(&self, field: &str) -> Result<(), String> {
        let finite = |x: f32| x.is_finite();
        if !(finite(self.factor) && self.factor >= 0.0) {
            return Err(format!("{field}.factor: {} is not >= 0", self.factor));
        }
        if !finite(self.bias) {
            return Err(format!("{field}.bias: {} is not finite", self.bias));
        }
        if !(finite(self.fade_start) && self.fade_start >= 0.0) {
            return Err(format!(
                "{field}.fade_start: {} is not >= 0",
                self.fade_start
            ));
        }
        let no_fade = self.fade_end == 0.0;
        if !(finite(self.fade_end) && (no_fade || self.fade_end > self.fade_start)) {
            return Err(format!(
                "{field}.fade_end: {} is neither 0 (no fade) nor above fade_start ({})",
                self.fade_end, self.fade_start
            ));
        }
        Ok(())
    }

    /// `extras.relief.lod`: `true` (the defaults), `false` (off) or an object of `KEYS`.
    pub fn from_json(v: &Value, field: &str) -> Result<Option<Lod>, String> {
        let o = match v {
            Value::Bool(on) => return Ok(on.then(Lod::default)),
            Value::Object(o) => o,
            _ => {
                return Err(format!(
                    "{field}: expected true, false or an object, found {v}"
                ))
            }
        };
        if let Some(k) = o.keys().find(|k| !Lod::KEYS.contains(&k.as_str())) {
            return Err(format!(
                "{field}: unknown key {k:?}; known keys: {}",
                Lod::KEYS.join(", ")
            ));
        }
        let mut lod = Lod::default();
        let number = |key: &str, dst: &mut f32| -> Result<(), String> {
            if let Some(x) = o.get(key) {
                *dst = x
                    .as_f64()
                    .map(|x| x as f32)
                    .ok_or_else(|| format!("{field}.{key}: {x} is not a number"))?;
            }
            Ok(())
        };
        number("factor", &mut lod.factor)?;
        number("bias", &mut lod.bias)?;
        number("fade_start", &mut lod.fade_start)?;
        number("fade_end", &mut lod.fade_end)?;
        lod.average_below = average_below(o, field)?.unwrap_or(lod.average_below);
        lod.validate(field)?;
        Ok(Some(lod))
    }
}

fn average_below(o: &Map<String, Value>, field: &str) -> Result<Option<u32>, String> {
    o.get("average_below")
        .map(|v| {
            v.as_u64()
                .filter(|&l| l <= 32)
                .map(|l| l as u32)
                .ok_or_else(|| format!("{field}.average_below: {v} is not a level in 0..=32"))
        })
        .transpose()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(json: &str) -> Result<Option<Lod>, String> {
        let v: Value = serde_json::from_str(json).expect("test json");
        Lod::from_json(&v, "extras.relief.lod")
    }

    #[test]
    fn booleans_and_objects() {
        assert_eq!(parse("false"), Ok(None));
        assert_eq!(parse("true"), Ok(Some(Lod::default())));
        let lod = parse(
            r#"{"factor": 0.5, "bias": -1, "fade_start": 10, "fade_end": 20, "average_below": 4}"#,
        )
        .unwrap()
        .unwrap();
        assert_eq!(
            lod,
            Lod {
                factor: 0.5,
                bias: -1.0,
                fade_start: 10.0,
                fade_end: 20.0,
                average_below: 4
            }
        );
        assert!(lod.uses_mean_pyramid());
        let off = parse(r#"{"average_below": 0}"#).unwrap().unwrap();
        assert!(!off.uses_mean_pyramid());
    }

    #[test]
    fn bad_values_name_their_field() {
        let cases = [
            ("3", "extras.relief.lod: expected true, false or an object"),
            (
                r#"{"factr": 1}"#,
                "extras.relief.lod: unknown key \"factr\"",
            ),
            (r#"{"factor": -1}"#, "extras.relief.lod.factor: -1"),
            (r#"{"factor": "x"}"#, "extras.relief.lod.factor: \"x\""),
            (r#"{"fade_start": -2}"#, "extras.relief.lod.fade_start"),
            (
                r#"{"fade_start": 5, "fade_end": 4}"#,
                "extras.relief.lod.fade_end: 4",
            ),
            (
                r#"{"average_below": -1}"#,
                "extras.relief.lod.average_below",
            ),
            (
                r#"{"average_below": 99}"#,
                "extras.relief.lod.average_below",
            ),
        ];
        for (json, want) in cases {
            let err = parse(json).expect_err(json);
            assert!(err.starts_with(want), "{json}: got {err:?}, want {want:?}");
        }
    }
}
