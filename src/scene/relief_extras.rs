//! Relief settings carried in a glTF material's `extras`:
//!
//! ```json
//! "extras": { "relief": {
//!     "height": { "index": 3, "texCoord": 0, "channel": "a", "invert": false },
//!     "depth_scale": 0.05, "method": "qdm", "budget": 64,
//!     "shadows": "horizon", "shadow_steps": 5, "horizon_reach": 1.0, "ao": "horizon-8",
//!     "lod": { "factor": 1, "bias": 0, "fade_start": 0, "fade_end": 0, "average_below": 16 },
//!     "silhouettes": "flat", "write_depth": true } }
//! ```
//!
//! `depth_scale` is required (finite, > 0). Defaults: `method` "pom", `budget` none (the
//! method's own), `shadows` "hard" (`none`, `hard`, `pom-soft`, `horizon`, `cone`) with
//! `shadow_steps` (samples or the cone walk's cap, 1..=4096; the mode's default) and
//! `horizon_reach` (the horizon mode's light vector scale, > 0; 1), `ao` "none"
//! (`horizon-4|8|16`, optionally `-rotated`, or `exact-horizon`), `height.texCoord` 0,
//! `height.channel` "r", `height.invert` false, `lod` off (`true` takes the defaults shown above;
//! `false` is off; an object sets any of those fields: `factor` >= 0 scales the pixel's mip level
//! into the traversal's stop level, `bias` is added to it, past `fade_start` world units from the
//! eye the relief fades to normal mapping until `fade_end` (0: no fade), and stop levels below
//! `average_below` end on the averaged pyramid, 0 never), `silhouettes` "flat" (or "curved":
//! the relief follows the mesh's curvature and its outline is cut where rays leave the shell;
//! method "relief" only), `write_depth` true (false: the frame's depth holds the polygon's
//! depth, not the displaced hit's). Without
//! `height` the material takes the frame's height map, unless it has `layers` (height-blended
//! layers, documented in `layer_extras`). Extras without `relief` are ignored;
//! unknown keys inside `relief` are errors, so a misspelt setting is not silently dropped.

use std::fmt::Display;
use std::str::FromStr;

use serde_json::{Map, Value};

use super::layer_extras::parse_layers;
use super::{
    AoMode, HeightSource, Layers, Lod, Relief, ShadowMode, ShadowSettings, Silhouettes, TextureRef,
};
use crate::heightfield::Channel;
use crate::method::Method;

/// The relief a material's extras ask for with its layers (`extras.relief.layers`, see
/// `layer_extras`), or `None` when they do not mention relief.
/// `texture(index, tex_coord)` resolves a glTF texture index (`None`: no such texture);
/// `texture_count` is only for the message. Errors name the offending field.
pub(super) fn parse_relief(
    extras: Option<&str>,
    texture: impl Fn(usize, u32) -> Option<TextureRef>,
    texture_count: usize,
) -> Result<Option<(Relief, Option<Layers>)>, String> {
    let Some(text) = extras else { return Ok(None) };
    let root: Value = serde_json::from_str(text).map_err(|e| format!("extras: {e}"))?;
    let Some(relief) = root.as_object().and_then(|o| o.get("relief")) else {
        return Ok(None);
    };
    let relief = object(relief, "extras.relief")?;
    only_keys(
        relief,
        "extras.relief",
        &[
            "height",
            "depth_scale",
            "method",
            "budget",
            "shadows",
            "shadow_steps",
            "horizon_reach",
            "ao",
            "lod",
            "layers",
            "silhouettes",
            "write_depth",
        ],
    )?;
    let depth_scale = depth_scale(relief)?;
    let method = match relief.get("method") {
        None => Method::POM,
        Some(v) => parsed(v, "extras.relief.method")?,
    };
    let budget = budget(relief)?;
    let layers = relief
        .get("layers")
        .map(|v| parse_layers(v, &texture, texture_count))
        .transpose()?;
    let height = match (relief.get("height"), &layers) {
        (Some(_), Some(_)) => {
            return Err("extras.relief: give height or layers, not both".into());
        }
        (None, Some(_)) => HeightSource::Layers,
        (None, None) => HeightSource::Frame,
        (Some(h), None) => height_source(h, texture, texture_count)?,
    };
    let shadows = shadows(relief)?;
    let ao = match relief.get("ao") {
        None => AoMode::default(),
        Some(v) => parsed(v, "extras.relief.ao")?,
    };
    let lod = match relief.get("lod") {
        None => None,
        Some(v) => Lod::from_json(v, "extras.relief.lod")?,
    };
    let silhouettes = match relief.get("silhouettes") {
        None => Silhouettes::Flat,
        Some(v) => parsed(v, "extras.relief.silhouettes")?,
    };
    let write_depth = match relief.get("write_depth") {
        None => true,
        Some(v) => v
            .as_bool()
            .ok_or_else(|| format!("extras.relief.write_depth: {v} is not true or false"))?,
    };
    let relief = Relief {
        write_depth,
        depth_scale,
        method,
        budget,
        height,
        shadows,
        ao,
        lod,
        silhouettes,
    };
    Ok(Some((relief, layers)))
}

/// `extras.relief.depth_scale`, required.
fn depth_scale(relief: &Map<String, Value>) -> Result<f32, String> {
    Ok(match relief.get("depth_scale") {
        None => return Err("extras.relief.depth_scale: missing (a number > 0)".into()),
        Some(v) => v
            .as_f64()
            .map(|d| d as f32)
            .filter(|d| d.is_finite() && *d > 0.0)
            .ok_or_else(|| format!("extras.relief.depth_scale: {v} is not a finite number > 0"))?,
    })
}

/// `extras.relief.budget`, `None` for the method's default.
fn budget(relief: &Map<String, Value>) -> Result<Option<u32>, String> {
    Ok(match relief.get("budget") {
        None => None,
        Some(v) => Some(
            v.as_u64()
                .filter(|&b| b >= 1)
                .and_then(|b| u32::try_from(b).ok())
                .ok_or_else(|| {
                    format!("extras.relief.budget: {v} is not an integer in 1..=2^32-1")
                })?,
        ),
    })
}

/// `extras.relief.shadows` with its `shadow_steps` and `horizon_reach`.
fn shadows(relief: &Map<String, Value>) -> Result<ShadowSettings, String> {
    let mut shadows = ShadowSettings::new(match relief.get("shadows") {
        None => ShadowMode::default(),
        Some(v) => parsed(v, "extras.relief.shadows")?,
    });
    if let Some(v) = relief.get("shadow_steps") {
        let steps = v
            .as_u64()
            .filter(|s| (1..=4096).contains(s))
            .ok_or_else(|| {
                format!("extras.relief.shadow_steps: {v} is not an integer in 1..=4096")
            })?;
        shadows.steps = Some(steps as u32);
    }
    if let Some(v) = relief.get("horizon_reach") {
        shadows.horizon_reach = v
            .as_f64()
            .map(|r| r as f32)
            .filter(|r| r.is_finite() && *r > 0.0)
            .ok_or_else(|| {
                format!("extras.relief.horizon_reach: {v} is not a finite number > 0")
            })?;
    }
    Ok(shadows)
}

fn height_source(
    h: &Value,
    texture: impl Fn(usize, u32) -> Option<TextureRef>,
    texture_count: usize,
) -> Result<HeightSource, String> {
    let h = object(h, "extras.relief.height")?;
    only_keys(
        h,
        "extras.relief.height",
        &["index", "texCoord", "channel", "invert"],
    )?;
    let index = match h.get("index") {
        None => return Err("extras.relief.height.index: missing (a glTF texture index)".into()),
        Some(v) => v
            .as_u64()
            .ok_or_else(|| format!("extras.relief.height.index: {v} is not a texture index"))?,
    };
    let tex_coord = match h.get("texCoord") {
        None => 0,
        Some(v) => v
            .as_u64()
            .filter(|&t| t <= 1)
            .ok_or_else(|| format!("extras.relief.height.texCoord: {v} is not 0 or 1"))?
            as u32,
    };
    let texture = usize::try_from(index)
        .ok()
        .and_then(|i| texture(i, tex_coord))
        .ok_or_else(|| {
            format!("extras.relief.height.index: texture {index} does not exist (the file has {texture_count})")
        })?;
    let channel = match h.get("channel") {
        None => Channel::R,
        Some(v) => parsed(v, "extras.relief.height.channel")?,
    };
    let invert = match h.get("invert") {
        None => false,
        Some(v) => v
            .as_bool()
            .ok_or_else(|| format!("extras.relief.height.invert: {v} is not true or false"))?,
    };
    Ok(HeightSource::Texture {
        texture,
        channel,
        invert,
    })
}

pub(super) fn object<'v>(v: &'v Value, field: &str) -> Result<&'v Map<String, Value>, String> {
    v.as_object()
        .ok_or_else(|| format!("{field}: expected an object, found {v}"))
}

/// A string field read through `T`'s `FromStr`, whose message names what it accepts.
pub(super) fn parsed<T: FromStr>(v: &Value, field: &str) -> Result<T, String>
where
    T::Err: Display,
{
    v.as_str()
        .ok_or_else(|| format!("{field}: expected a string, found {v}"))?
        .parse()
        .map_err(|e| format!("{field}: {e}"))
}

pub(super) fn only_keys(o: &Map<String, Value>, field: &str, known: &[&str]) -> Result<(), String> {
    match o.keys().find(|k| !known.contains(&k.as_str())) {
        Some(k) => Err(format!(
            "{field}: unknown key {k:?}; known keys: {}",
            known.join(", ")
        )),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SamplerDesc, UvTransform};

    fn tex(index: usize, tex_coord: u32) -> Option<TextureRef> {
        (index < 4).then_some(TextureRef {
            image: index + 10,
            tex_coord,
            transform: UvTransform::default(),
            sampler: SamplerDesc::default(),
        })
    }

    fn parse(json: &str) -> Result<Option<Relief>, String> {
        parse_relief(Some(json), tex, 4).map(|r| r.map(|(relief, _)| relief))
    }

    #[test]
    fn full_settings() {
        let r = parse(
            r#"{"relief": {"height": {"index": 3, "texCoord": 1, "channel": "a", "invert": true},
                "depth_scale": 0.05, "method": "qdm", "budget": 64, "shadows": "pom-soft",
                "ao": "horizon-16-rotated"}, "other": 1}"#,
        )
        .unwrap()
        .unwrap();
        assert_eq!(r.depth_scale, 0.05);
        assert_eq!(r.method, "qdm".parse().unwrap());
        assert_eq!(r.budget, Some(64));
        assert_eq!(r.shadows.mode, ShadowMode::PomSoft);
        assert_eq!(
            r.ao,
            AoMode::Horizon {
                directions: 16,
                rotated: true
            }
        );
        let HeightSource::Texture {
            texture,
            channel,
            invert,
        } = r.height
        else {
            panic!("expected a texture height source")
        };
        assert_eq!((texture.image, texture.tex_coord), (13, 1));
        assert_eq!(channel, Channel::A);
        assert!(invert);
    }

    #[test]
    fn defaults() {
        let r = parse(r#"{"relief": {"depth_scale": 0.1}}"#)
            .unwrap()
            .unwrap();
        assert_eq!(r.method, Method::POM);
        assert_eq!(r.budget, None);
        assert_eq!(r.height, HeightSource::Frame);
        assert_eq!((r.shadows, r.ao), (ShadowSettings::default(), AoMode::None));
        assert_eq!(r.lod, None);
        assert_eq!(r.silhouettes, Silhouettes::Flat);
        assert!(r.write_depth);
        let r = parse(r#"{"relief": {"depth_scale": 1, "write_depth": false}}"#);
        assert!(!r.unwrap().unwrap().write_depth);
        let r = parse(r#"{"relief": {"depth_scale": 1, "height": {"index": 0}}}"#)
            .unwrap()
            .unwrap();
        let HeightSource::Texture {
            texture,
            channel,
            invert,
        } = r.height
        else {
            panic!("expected a texture height source")
        };
        assert_eq!(
            (texture.image, texture.tex_coord, channel, invert),
            (10, 0, Channel::R, false)
        );
    }

    #[test]
    fn silhouettes_are_flat_curved_or_shells() {
        let curved = parse(r#"{"relief": {"depth_scale": 1, "silhouettes": "curved"}}"#);
        assert_eq!(curved.unwrap().unwrap().silhouettes, Silhouettes::Curved);
        let shells = parse(r#"{"relief": {"depth_scale": 1, "silhouettes": "shells"}}"#);
        assert_eq!(shells.unwrap().unwrap().silhouettes, Silhouettes::Shells);
        let err = parse(r#"{"relief": {"depth_scale": 1, "silhouettes": "cage"}}"#).unwrap_err();
        assert!(
            err.contains("extras.relief.silhouettes") && err.contains("flat, curved or shells"),
            "{err}"
        );
    }

    #[test]
    fn lod_settings() {
        let lod = |json: &str| parse(json).unwrap().unwrap().lod;
        assert_eq!(
            lod(r#"{"relief": {"depth_scale": 1, "lod": true}}"#),
            Some(Lod::default())
        );
        assert_eq!(lod(r#"{"relief": {"depth_scale": 1, "lod": false}}"#), None);
        let set = lod(r#"{"relief": {"depth_scale": 1, "lod": {"factor": 2, "fade_end": 9}}}"#);
        let want = Lod {
            factor: 2.0,
            fade_end: 9.0,
            ..Lod::default()
        };
        assert_eq!(set, Some(want));
    }

    #[test]
    fn unrelated_extras_are_ignored() {
        assert_eq!(parse_relief(None, tex, 4), Ok(None));
        assert_eq!(parse(r#"{"author": "me"}"#), Ok(None));
        assert_eq!(parse(r#"[1, 2]"#), Ok(None));
        assert_eq!(parse(r#""just a string""#), Ok(None));
    }

    #[test]
    fn bad_values_name_their_field() {
        let cases = [
            (r#"{"relief": 3}"#, "extras.relief: expected an object"),
            (r#"{"relief": {}}"#, "extras.relief.depth_scale: missing"),
            (
                r#"{"relief": {"depth_scale": 0}}"#,
                "extras.relief.depth_scale: 0",
            ),
            (
                r#"{"relief": {"depth_scale": -1.5}}"#,
                "extras.relief.depth_scale: -1.5",
            ),
            (
                r#"{"relief": {"depth_scale": "big"}}"#,
                "extras.relief.depth_scale: \"big\"",
            ),
            (
                r#"{"relief": {"depth_scale": 1e300}}"#,
                "extras.relief.depth_scale",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "method": "foo"}}"#,
                "extras.relief.method: unknown method \"foo\"; known methods: ",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "method": 2}}"#,
                "extras.relief.method: expected a string",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "write_depth": "yes"}}"#,
                "extras.relief.write_depth: \"yes\" is not true or false",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "budget": 0}}"#,
                "extras.relief.budget",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "budget": 1.5}}"#,
                "extras.relief.budget",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "height": 3}}"#,
                "extras.relief.height: expected an object",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "height": {}}}"#,
                "extras.relief.height.index: missing",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "height": {"index": 4}}}"#,
                "extras.relief.height.index: texture 4 does not exist (the file has 4)",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "height": {"index": -1}}}"#,
                "extras.relief.height.index: -1",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "height": {"index": 0, "texCoord": 2}}}"#,
                "extras.relief.height.texCoord",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "height": {"index": 0, "channel": "x"}}}"#,
                "extras.relief.height.channel: unknown height channel",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "height": {"index": 0, "invert": 1}}}"#,
                "extras.relief.height.invert",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "shadows": "soft"}}"#,
                "extras.relief.shadows: unknown shadow mode \"soft\"",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "shadow_steps": 0}}"#,
                "extras.relief.shadow_steps: 0",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "horizon_reach": -2}}"#,
                "extras.relief.horizon_reach: -2",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "ao": "horizon-3"}}"#,
                "extras.relief.ao: unknown AO mode \"horizon-3\"",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "lod": {"fade": 2}}}"#,
                "extras.relief.lod: unknown key \"fade\"",
            ),
            (
                r#"{"relief": {"depth_scale": 1, "depthscale": 2}}"#,
                "extras.relief: unknown key \"depthscale\"",
            ),
        ];
        for (json, want) in cases {
            let err = parse(json).expect_err(json);
            assert!(
                err.starts_with(want),
                "{json}: got {err:?}, want {want:?}..."
            );
        }
    }
}
