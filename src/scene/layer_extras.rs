//! Height-blended layers carried in a glTF material's `extras.relief.layers` (see
//! [`super::layered`] for what they mean):
//!
//! ```json
//! "extras": { "relief": { "depth_scale": 0.005, "method": "qdm",
//!     "layers": {
//!         "mode": "height", "splat": 5, "resolution": 2048,
//!         "layers": [
//!             { "name": "sand", "height": 0, "channel": "r", "albedo": 1, "normal": 2,
//!               "roughness": 3, "tiling": 8, "depth": 1.0 },
//!             { "name": "rock", "height": 4, "tiling": 4 } ] } } }
//! ```
//!
//! Textures are glTF texture indices, read with texture coordinate set 0 (the height uv);
//! `splat` (RGBA, channel k weighs layer k; or `"vertex-colors"`: the colours of the meshes using
//! the material, baked into a splat map at a quarter of `resolution` when the file is loaded) and
//! `height` are required, the other maps optional.
//! Defaults: `mode` "height" (`alpha`, `height`, `height-intersect`), `resolution` 1024 (the
//! blended field's side), `channel` "r", `tiling` 1, `depth` 1, `name` "layer K". A material with
//! `layers` takes its heights from them (`height` beside it is an error). Unknown keys are errors.

use serde_json::{Map, Value};

use super::layered::{LayerWeights, Layers, MaterialLayer};
use super::relief_extras::{object, only_keys, parsed};
use super::TextureRef;
use crate::heightfield::Channel;
use crate::terrain::BlendMode;

/// Side of the blended field when `resolution` is left out.
const DEFAULT_RESOLUTION: u32 = 1024;
/// Vertex-colour weights are baked at the blended field's side over this: weights are smooth.
const VERTEX_SPLAT_DIVISOR: u32 = 4;

/// The layers `extras.relief.layers` describes; `texture` resolves a glTF texture index.
pub(super) fn parse_layers(
    v: &Value,
    texture: &impl Fn(usize, u32) -> Option<TextureRef>,
    texture_count: usize,
) -> Result<Layers, String> {
    let field = "extras.relief.layers";
    let o = object(v, field)?;
    only_keys(o, field, &["mode", "splat", "resolution", "layers"])?;
    let mode: BlendMode = match o.get("mode") {
        None => BlendMode::Height,
        Some(v) => parsed(v, &format!("{field}.mode"))?,
    };
    let resolve = |v: Option<&Value>, what: &str| -> Result<Option<TextureRef>, String> {
        let Some(v) = v else { return Ok(None) };
        let index = v
            .as_u64()
            .ok_or_else(|| format!("{what}: {v} is not a texture index"))?;
        usize::try_from(index)
            .ok()
            .and_then(|i| texture(i, 0))
            .map(Some)
            .ok_or_else(|| {
                format!("{what}: texture {index} does not exist (the file has {texture_count})")
            })
    };
    let resolution = match o.get("resolution") {
        None => DEFAULT_RESOLUTION,
        Some(v) => v
            .as_u64()
            .and_then(|r| u32::try_from(r).ok())
            .ok_or_else(|| format!("{field}.resolution: {v} is not a texel count"))?,
    };
    let weights = match o.get("splat") {
        Some(Value::String(s)) if s == "vertex-colors" => LayerWeights::VertexColors {
            resolution: (resolution / VERTEX_SPLAT_DIVISOR).max(1),
        },
        splat => LayerWeights::Splat(resolve(splat, &format!("{field}.splat"))?.ok_or_else(
            || format!("{field}.splat: missing (the RGBA weights' texture index, or \"vertex-colors\")"),
        )?),
    };
    let list = match o.get("layers") {
        Some(Value::Array(list)) => list,
        Some(v) => return Err(format!("{field}.layers: expected an array, found {v}")),
        None => return Err(format!("{field}.layers: missing (1 to 4 layers)")),
    };
    let layers = list
        .iter()
        .enumerate()
        .map(|(k, l)| layer(l, k, &format!("{field}.layers[{k}]"), &resolve))
        .collect::<Result<Vec<_>, _>>()?;
    let parsed = Layers {
        layers,
        weights,
        mode,
        resolution,
    };
    parsed.check().map_err(|e| format!("{field}: {e}"))?;
    Ok(parsed)
}

type Resolve<'a> = dyn Fn(Option<&Value>, &str) -> Result<Option<TextureRef>, String> + 'a;

fn layer(v: &Value, k: usize, field: &str, resolve: &Resolve) -> Result<MaterialLayer, String> {
    let o: &Map<String, Value> = object(v, field)?;
    only_keys(
        o,
        field,
        &[
            "name",
            "height",
            "channel",
            "albedo",
            "normal",
            "roughness",
            "tiling",
            "depth",
        ],
    )?;
    let number = |key: &str, default: f32| -> Result<f32, String> {
        match o.get(key) {
            None => Ok(default),
            Some(v) => v
                .as_f64()
                .map(|x| x as f32)
                .ok_or_else(|| format!("{field}.{key}: {v} is not a number")),
        }
    };
    let name = match o.get("name") {
        None => format!("layer {k}"),
        Some(v) => v
            .as_str()
            .ok_or_else(|| format!("{field}.name: {v} is not a string"))?
            .to_owned(),
    };
    Ok(MaterialLayer {
        name,
        height: resolve(o.get("height"), &format!("{field}.height"))?
            .ok_or_else(|| format!("{field}.height: missing (the layer's height texture index)"))?,
        height_channel: match o.get("channel") {
            None => Channel::R,
            Some(v) => parsed(v, &format!("{field}.channel"))?,
        },
        albedo: resolve(o.get("albedo"), &format!("{field}.albedo"))?,
        normal: resolve(o.get("normal"), &format!("{field}.normal"))?,
        roughness: resolve(o.get("roughness"), &format!("{field}.roughness"))?,
        tiling: number("tiling", 1.0)?,
        depth: number("depth", 1.0)?,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{SamplerDesc, UvTransform};

    fn tex(index: usize, tex_coord: u32) -> Option<TextureRef> {
        (index < 6).then_some(TextureRef {
            image: index + 10,
            tex_coord,
            transform: UvTransform::default(),
            sampler: SamplerDesc::default(),
        })
    }

    fn parse(json: &str) -> Result<Layers, String> {
        parse_layers(&serde_json::from_str(json).unwrap(), &tex, 6)
    }

    #[test]
    fn full_layers() {
        let l = parse(
            r#"{"mode": "height-intersect", "splat": 5, "resolution": 512, "layers": [
                {"name": "sand", "height": 0, "channel": "a", "albedo": 1, "normal": 2,
                 "roughness": 3, "tiling": 8, "depth": 0.5},
                {"height": 4}]}"#,
        )
        .unwrap();
        assert_eq!(l.mode, BlendMode::HeightIntersect);
        assert_eq!((l.splat().unwrap().image, l.resolution), (15, 512));
        let sand = &l.layers[0];
        assert_eq!(sand.name, "sand");
        assert_eq!(sand.height_channel, Channel::A);
        assert_eq!(sand.albedo.unwrap().image, 11);
        assert_eq!((sand.tiling, sand.depth), (8.0, 0.5));
        let second = &l.layers[1];
        assert_eq!(second.name, "layer 1");
        assert_eq!(
            (second.tiling, second.depth, second.albedo),
            (1.0, 1.0, None)
        );
    }

    #[test]
    fn vertex_colour_weights_wait_for_baking() {
        let l =
            parse(r#"{"splat": "vertex-colors", "resolution": 256, "layers": [{"height": 0}]}"#)
                .unwrap();
        assert_eq!(l.weights, LayerWeights::VertexColors { resolution: 64 });
        assert!(l.splat().is_none());
    }

    #[test]
    fn bad_layers_are_refused_naming_the_field() {
        let cases = [
            (r#"{"layers": [{"height": 0}]}"#, "layers.splat: missing"),
            (
                r#"{"splat": 9, "layers": [{"height": 0}]}"#,
                "texture 9 does not exist",
            ),
            (r#"{"splat": 5, "layers": []}"#, "1 to 4 layers, got 0"),
            (
                r#"{"splat": 5, "layers": [{"albedo": 1}]}"#,
                "layers[0].height: missing",
            ),
            (
                r#"{"splat": 5, "layers": [{"height": 0, "tiling": -1}]}"#,
                "tiling must be",
            ),
            (
                r#"{"splat": 5, "layers": [{"height": 0, "depth": 2}]}"#,
                "depth must be",
            ),
            (
                r#"{"splat": 5, "mode": "max", "layers": [{"height": 0}]}"#,
                "unknown blend mode",
            ),
            (
                r#"{"splat": 5, "layers": [{"height": 0, "tint": 1}]}"#,
                "unknown key \"tint\"",
            ),
            (
                r#"{"splat": 5, "resolution": 0, "layers": [{"height": 0}]}"#,
                "resolution",
            ),
        ];
        for (json, needle) in cases {
            let err = parse(json).unwrap_err();
            assert!(err.contains(needle), "{json}: {err}");
            assert!(!err.contains('\n'));
        }
    }
}
