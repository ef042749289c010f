//! A light's size, carried in its glTF `extras` (KHR_lights_punctual has none):
//!
//! ```json
//! "extras": { "relief": { "angular_radius_deg": 0.27 } }   // directional: the sun's disk
//! "extras": { "relief": { "radius": 0.05 } }               // point and spot: a sphere, world units
//! ```
//!
//! Both default to 0, a hard light. The key that does not fit the light's kind, unknown keys,
//! negative or non-finite values, and angular radii above 90 degrees are errors naming the field.

use serde_json::Value;

use super::LightKind;

/// The largest angular radius accepted: a hemisphere of directions.
pub const MAX_ANGULAR_RADIUS_DEG: f32 = 90.0;

/// The light's radius from its extras: radians of angular radius for a directional light, world
/// units for point and spot lights; 0 when the extras do not mention one.
pub(super) fn parse_light_radius(extras: Option<&str>, kind: LightKind) -> Result<f32, String> {
    let Some(text) = extras else { return Ok(0.0) };
    let root: Value = serde_json::from_str(text).map_err(|e| format!("extras: {e}"))?;
    let Some(relief) = root.as_object().and_then(|o| o.get("relief")) else {
        return Ok(0.0);
    };
    let relief = relief
        .as_object()
        .ok_or_else(|| format!("extras.relief: expected an object, found {relief}"))?;
    let expected = match kind {
        LightKind::Directional => "angular_radius_deg",
        LightKind::Point | LightKind::Spot { .. } => "radius",
    };
    if let Some(key) = relief.keys().find(|k| k.as_str() != expected) {
        return Err(format!(
            "extras.relief: unknown key {key:?} for this light (expected only {expected:?})"
        ));
    }
    let Some(v) = relief.get(expected) else {
        return Ok(0.0);
    };
    let value = v
        .as_f64()
        .map(|x| x as f32)
        .filter(|x| x.is_finite() && *x >= 0.0)
        .ok_or_else(|| format!("extras.relief.{expected}: {v} is not a finite number >= 0"))?;
    match kind {
        LightKind::Directional if value > MAX_ANGULAR_RADIUS_DEG => Err(format!(
            "extras.relief.angular_radius_deg: {value} is above {MAX_ANGULAR_RADIUS_DEG}"
        )),
        LightKind::Directional => Ok(value.to_radians()),
        _ => Ok(value),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const SPOT: LightKind = LightKind::Spot {
        inner_cone: 0.1,
        outer_cone: 0.5,
    };

    #[test]
    fn radii_by_kind() {
        let sun = parse_light_radius(
            Some(r#"{"relief": {"angular_radius_deg": 0.27}}"#),
            LightKind::Directional,
        );
        assert!((sun.unwrap() - 0.27f32.to_radians()).abs() < 1e-9);
        let bulb = parse_light_radius(Some(r#"{"relief": {"radius": 0.5}}"#), SPOT);
        assert_eq!(bulb, Ok(0.5));
        assert_eq!(parse_light_radius(None, LightKind::Point), Ok(0.0));
        assert_eq!(
            parse_light_radius(Some(r#"{"other": 1}"#), LightKind::Point),
            Ok(0.0)
        );
    }

    #[test]
    fn bad_values_name_their_field() {
        let cases = [
            (
                r#"{"relief": {"radius": 1}}"#,
                LightKind::Directional,
                "unknown key \"radius\"",
            ),
            (
                r#"{"relief": {"angular_radius_deg": 1}}"#,
                LightKind::Point,
                "unknown key \"angular_radius_deg\"",
            ),
            (
                r#"{"relief": {"angular_radius_deg": 91}}"#,
                LightKind::Directional,
                "above 90",
            ),
            (
                r#"{"relief": {"radius": -1}}"#,
                LightKind::Point,
                "extras.relief.radius: -1",
            ),
            (r#"{"relief": 2}"#, LightKind::Point, "expected an object"),
        ];
        for (json, kind, expected) in cases {
            let e = parse_light_radius(Some(json), kind).unwrap_err();
            assert!(e.contains(expected), "{json}: {e}");
        }
    }
}
