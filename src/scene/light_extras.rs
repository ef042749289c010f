//! A light's size and shadow-map settings, carried in its glTF `extras` (KHR_lights_punctual has
//! none):
//!
//! ```json
//! "extras": { "relief": { "angular_radius_deg": 0.27 } }   // directional: the sun's disk
//! "extras": { "relief": { "radius": 0.05 } }               // point and spot: a sphere, world units
//! "extras": { "relief": { "shadow_map_size": 2048, "shadow_cascades": 3 } }
//! ```
//!
//! The size defaults to 0, a hard light; the shadow-map settings to the renderer's. The size key
//! that does not fit the light's kind, `shadow_cascades` on a light that is not directional,
//! unknown keys, negative or non-finite values, angular radii above 90 degrees and map sizes or
//! cascade counts out of range are errors naming the field.

use serde_json::Value;

use super::LightKind;

/// The largest angular radius accepted: a hemisphere of directions.
pub const MAX_ANGULAR_RADIUS_DEG: f32 = 90.0;

/// Shadow-map sizes accepted, texels per side.
pub const SHADOW_MAP_SIZES: std::ops::RangeInclusive<u32> = 16..=8192;

/// Cascade counts accepted.
pub const SHADOW_CASCADES: std::ops::RangeInclusive<u32> = 1..=4;

/// What a light's extras say.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub(super) struct LightExtras {
    /// Radians of angular radius (directional) or world units (point, spot); 0 when not given.
    pub radius: f32,
    /// `shadow_map_size`, when given.
    pub shadow_map_size: Option<u32>,
    /// `shadow_cascades`, when given.
    pub shadow_cascades: Option<u32>,
}

/// A whole number in `range` at `key`, or an error naming it.
fn count_in(
    relief: &serde_json::Map<String, Value>,
    key: &str,
    range: std::ops::RangeInclusive<u32>,
) -> Result<Option<u32>, String> {
    let Some(v) = relief.get(key) else {
        return Ok(None);
    };
    v.as_u64()
        .and_then(|n| u32::try_from(n).ok())
        .filter(|n| range.contains(n))
        .map(Some)
        .ok_or_else(|| {
            format!(
                "extras.relief.{key}: {v} is not a whole number in {}..={}",
                range.start(),
                range.end()
            )
        })
}

/// The light's extras for a light of `kind`.
pub(super) fn parse_light_extras(
    extras: Option<&str>,
    kind: LightKind,
) -> Result<LightExtras, String> {
    let Some(text) = extras else {
        return Ok(LightExtras::default());
    };
    let root: Value = serde_json::from_str(text).map_err(|e| format!("extras: {e}"))?;
    let Some(relief) = root.as_object().and_then(|o| o.get("relief")) else {
        return Ok(LightExtras::default());
    };
    let relief = relief
        .as_object()
        .ok_or_else(|| format!("extras.relief: expected an object, found {relief}"))?;
    let size_key = match kind {
        LightKind::Directional => "angular_radius_deg",
        LightKind::Point | LightKind::Spot { .. } => "radius",
    };
    let mut expected = vec![size_key, "shadow_map_size"];
    if kind == LightKind::Directional {
        expected.push("shadow_cascades");
    }
    if let Some(key) = relief.keys().find(|k| !expected.contains(&k.as_str())) {
        return Err(format!(
            "extras.relief: unknown key {key:?} for this light (expected {})",
            expected
                .iter()
                .map(|k| format!("{k:?}"))
                .collect::<Vec<_>>()
                .join(", ")
        ));
    }
    let shadow_map_size = count_in(relief, "shadow_map_size", SHADOW_MAP_SIZES)?;
    let shadow_cascades = count_in(relief, "shadow_cascades", SHADOW_CASCADES)?;
    let radius = match relief.get(size_key) {
        None => 0.0,
        Some(v) => {
            let value = v
                .as_f64()
                .map(|x| x as f32)
                .filter(|x| x.is_finite() && *x >= 0.0)
                .ok_or_else(|| {
                    format!("extras.relief.{size_key}: {v} is not a finite number >= 0")
                })?;
            match kind {
                LightKind::Directional if value > MAX_ANGULAR_RADIUS_DEG => {
                    return Err(format!(
                    "extras.relief.angular_radius_deg: {value} is above {MAX_ANGULAR_RADIUS_DEG}"
                ))
                }
                LightKind::Directional => value.to_radians(),
                _ => value,
            }
        }
    };
    Ok(LightExtras {
        radius,
        shadow_map_size,
        shadow_cascades,
    })
}

/// The light's radius from its extras (see [`parse_light_extras`]).
#[cfg(test)]
fn parse_light_radius(extras: Option<&str>, kind: LightKind) -> Result<f32, String> {
    parse_light_extras(extras, kind).map(|e| e.radius)
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
    fn shadow_map_settings() {
        let e = parse_light_extras(
            Some(r#"{"relief": {"shadow_map_size": 512, "shadow_cascades": 3}}"#),
            LightKind::Directional,
        )
        .unwrap();
        assert_eq!((e.shadow_map_size, e.shadow_cascades), (Some(512), Some(3)));
        let spot = parse_light_extras(Some(r#"{"relief": {"shadow_map_size": 256}}"#), SPOT);
        assert_eq!(spot.unwrap().shadow_map_size, Some(256));
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
            (
                r#"{"relief": {"shadow_cascades": 2}}"#,
                LightKind::Point,
                "unknown key \"shadow_cascades\"",
            ),
            (
                r#"{"relief": {"shadow_map_size": 8}}"#,
                LightKind::Directional,
                "extras.relief.shadow_map_size: 8 is not a whole number in 16..=8192",
            ),
            (
                r#"{"relief": {"shadow_cascades": 5}}"#,
                LightKind::Directional,
                "extras.relief.shadow_cascades: 5",
            ),
        ];
        for (json, kind, expected) in cases {
            let e = parse_light_radius(Some(json), kind).unwrap_err();
            assert!(e.contains(expected), "{json}: {e}");
        }
    }
}
