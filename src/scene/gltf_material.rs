//! glTF materials to [`Material`]s: factors, textures with their samplers and
//! KHR_texture_transform, and relief from the material's extras.

use gltf::texture::{MagFilter, MinFilter, WrappingMode};
use serde_json::Value;

use super::relief_extras::parse_relief;
use super::{AlphaMode, Filter, Material, SamplerDesc, TextureRef, UvTransform, Wrap};

/// Every material of the document, in glTF order. `raw` is the document's JSON: the gltf
/// crate does not expose KHR_texture_transform on normal and occlusion textures.
pub(super) fn convert_materials(
    doc: &gltf::Document,
    raw: &Value,
) -> Result<Vec<Material>, String> {
    doc.materials()
        .map(|m| {
            let index = m.index().unwrap_or(0);
            let name = m
                .name()
                .map_or_else(|| format!("material {index}"), str::to_owned);
            convert(doc, &m, &raw["materials"][index])
                .map_err(|e| format!("material {name:?}: {e}"))
        })
        .collect()
}

fn convert(doc: &gltf::Document, m: &gltf::Material, raw: &Value) -> Result<Material, String> {
    let pbr = m.pbr_metallic_roughness();
    let pbr_raw = &raw["pbrMetallicRoughness"];
    let info = |info: Option<gltf::texture::Info>, raw: &Value, slot: &str| match info {
        None => Ok(None),
        Some(i) => texture_ref(&i.texture(), i.tex_coord(), raw)
            .map(Some)
            .map_err(|e| format!("{slot}: {e}")),
    };
    let base_color_texture = info(
        pbr.base_color_texture(),
        &pbr_raw["baseColorTexture"],
        "baseColorTexture",
    )?;
    let metallic_roughness_texture = info(
        pbr.metallic_roughness_texture(),
        &pbr_raw["metallicRoughnessTexture"],
        "metallicRoughnessTexture",
    )?;
    let emissive_texture = info(
        m.emissive_texture(),
        &raw["emissiveTexture"],
        "emissiveTexture",
    )?;
    let normal = m.normal_texture();
    let normal_texture = match &normal {
        None => None,
        Some(n) => Some(
            texture_ref(&n.texture(), n.tex_coord(), &raw["normalTexture"])
                .map_err(|e| format!("normalTexture: {e}"))?,
        ),
    };
    let occlusion = m.occlusion_texture();
    let occlusion_texture = match &occlusion {
        None => None,
        Some(o) => Some(
            texture_ref(&o.texture(), o.tex_coord(), &raw["occlusionTexture"])
                .map_err(|e| format!("occlusionTexture: {e}"))?,
        ),
    };
    let strength = m.emissive_strength().unwrap_or(1.0);
    let alpha_mode = match m.alpha_mode() {
        gltf::material::AlphaMode::Opaque => AlphaMode::Opaque,
        gltf::material::AlphaMode::Mask => AlphaMode::Mask {
            cutoff: m.alpha_cutoff().unwrap_or(0.5),
        },
        gltf::material::AlphaMode::Blend => AlphaMode::Blend,
    };
    let extras = m.extras().as_ref().map(|r| r.get());
    let parsed = parse_relief(
        extras,
        |index, tex_coord| {
            let t = doc.textures().nth(index)?;
            texture_ref(&t, tex_coord, &Value::Null).ok()
        },
        doc.textures().len(),
    )?;
    let (relief, layers) = match parsed {
        Some((relief, layers)) => (Some(relief), layers),
        None => (None, None),
    };
    let mat = Material {
        name: m.name().map_or_else(
            || format!("material {}", m.index().unwrap_or(0)),
            str::to_owned,
        ),
        base_color: pbr.base_color_factor(),
        base_color_texture,
        roughness: pbr.roughness_factor(),
        metallic: pbr.metallic_factor(),
        metallic_roughness_texture,
        normal_texture,
        normal_scale: normal.as_ref().map_or(1.0, |n| n.scale()),
        occlusion_texture,
        occlusion_strength: occlusion.as_ref().map_or(1.0, |o| o.strength()),
        emissive: m.emissive_factor().map(|c| c * strength),
        emissive_texture,
        alpha_mode,
        double_sided: m.double_sided(),
        relief,
        layers,
    };
    check_factors(&mat)?;
    Ok(mat)
}

/// Factors outside glTF's ranges are validator errors and would light the surface wrongly.
fn check_factors(m: &Material) -> Result<(), String> {
    let unit = |v: f32| (0.0..=1.0).contains(&v);
    let checks = [
        (
            "pbrMetallicRoughness.baseColorFactor",
            m.base_color.iter().all(|&v| unit(v)),
        ),
        ("pbrMetallicRoughness.roughnessFactor", unit(m.roughness)),
        ("pbrMetallicRoughness.metallicFactor", unit(m.metallic)),
        ("occlusionTexture.strength", unit(m.occlusion_strength)),
        ("normalTexture.scale", m.normal_scale.is_finite()),
        (
            "emissiveFactor",
            m.emissive.iter().all(|&v| v.is_finite() && v >= 0.0),
        ),
        (
            "alphaCutoff",
            match m.alpha_mode {
                AlphaMode::Mask { cutoff } => cutoff.is_finite() && cutoff >= 0.0,
                _ => true,
            },
        ),
    ];
    match checks.iter().find(|(_, ok)| !ok) {
        Some((field, _)) => Err(format!("{field}: value out of range")),
        None => Ok(()),
    }
}

/// A texture as a material slot uses it. `raw` is the slot's textureInfo JSON, read for
/// KHR_texture_transform (`Value::Null` when there is none).
pub(super) fn texture_ref(
    texture: &gltf::Texture,
    tex_coord: u32,
    raw: &Value,
) -> Result<TextureRef, String> {
    let (transform, override_coord) = uv_transform(&raw["extensions"]["KHR_texture_transform"])?;
    let tex_coord = override_coord.unwrap_or(tex_coord);
    if tex_coord > 1 {
        return Err(format!(
            "texCoord {tex_coord}: only sets 0 and 1 are supported"
        ));
    }
    Ok(TextureRef {
        image: texture.source().index(),
        tex_coord,
        transform,
        sampler: sampler_desc(&texture.sampler()),
    })
}

/// KHR_texture_transform's offset, rotation, scale and texCoord override, type-checked.
fn uv_transform(ext: &Value) -> Result<(UvTransform, Option<u32>), String> {
    let field = "extensions.KHR_texture_transform";
    if ext.is_null() {
        return Ok((UvTransform::default(), None));
    }
    if !ext.is_object() {
        return Err(format!("{field}: expected an object"));
    }
    let pair = |key: &str, default: [f32; 2]| -> Result<[f32; 2], String> {
        match &ext[key] {
            Value::Null => Ok(default),
            Value::Array(a) if a.len() == 2 => {
                let x = a[0].as_f64().map(|v| v as f32).filter(|v| v.is_finite());
                let y = a[1].as_f64().map(|v| v as f32).filter(|v| v.is_finite());
                x.zip(y)
                    .map(|(x, y)| [x, y])
                    .ok_or_else(|| format!("{field}.{key}: expected two finite numbers"))
            }
            _ => Err(format!("{field}.{key}: expected two finite numbers")),
        }
    };
    let rotation = match &ext["rotation"] {
        Value::Null => 0.0,
        v => v
            .as_f64()
            .map(|r| r as f32)
            .filter(|r| r.is_finite())
            .ok_or_else(|| format!("{field}.rotation: expected a finite number"))?,
    };
    let tex_coord = match &ext["texCoord"] {
        Value::Null => None,
        v => Some(
            v.as_u64()
                .and_then(|t| u32::try_from(t).ok())
                .ok_or_else(|| format!("{field}.texCoord: expected an unsigned integer"))?,
        ),
    };
    let transform = UvTransform {
        offset: pair("offset", [0.0; 2])?,
        rotation,
        scale: pair("scale", [1.0; 2])?,
    };
    Ok((transform, tex_coord))
}

pub(super) fn sampler_desc(s: &gltf::texture::Sampler) -> SamplerDesc {
    let d = SamplerDesc::default();
    let wrap = |w: WrappingMode| match w {
        WrappingMode::ClampToEdge => Wrap::ClampToEdge,
        WrappingMode::MirroredRepeat => Wrap::MirroredRepeat,
        WrappingMode::Repeat => Wrap::Repeat,
    };
    let (min, mipmaps) = match s.min_filter() {
        None => (d.min, d.mipmaps),
        Some(MinFilter::Nearest) => (Filter::Nearest, None),
        Some(MinFilter::Linear) => (Filter::Linear, None),
        Some(MinFilter::NearestMipmapNearest) => (Filter::Nearest, Some(Filter::Nearest)),
        Some(MinFilter::LinearMipmapNearest) => (Filter::Linear, Some(Filter::Nearest)),
        Some(MinFilter::NearestMipmapLinear) => (Filter::Nearest, Some(Filter::Linear)),
        Some(MinFilter::LinearMipmapLinear) => (Filter::Linear, Some(Filter::Linear)),
    };
    SamplerDesc {
        mag: match s.mag_filter() {
            None => d.mag,
            Some(MagFilter::Nearest) => Filter::Nearest,
            Some(MagFilter::Linear) => Filter::Linear,
        },
        min,
        mipmaps,
        wrap_u: wrap(s.wrap_s()),
        wrap_v: wrap(s.wrap_t()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn transform_rows_follow_translation_rotation_scale() {
        let (t, coord) = uv_transform(&json!({"offset": [0.5, 0.25], "rotation": std::f64::consts::FRAC_PI_2, "scale": [2.0, 3.0], "texCoord": 1})).unwrap();
        assert_eq!(coord, Some(1));
        let [r0, r1] = t.rows();
        let apply = |u: f32, v: f32| [r0[0] * u + r0[1] * v + r0[2], r1[0] * u + r1[1] * v + r1[2]];
        // Scale (1, 0) to (2, 0); rotating by +90 degrees in the extension's sense maps +u to
        // -v (its matrix is [c s; -s c]); then the offset.
        let [u, v] = apply(1.0, 0.0);
        assert!(
            (u - 0.5).abs() < 1e-6 && (v - (0.25 - 2.0)).abs() < 1e-6,
            "{u} {v}"
        );
        let [u, v] = apply(0.0, 1.0);
        assert!((u - 3.5).abs() < 1e-6 && (v - 0.25).abs() < 1e-6, "{u} {v}");
    }

    #[test]
    fn transform_defaults_and_bad_types() {
        assert_eq!(
            uv_transform(&Value::Null).unwrap(),
            (UvTransform::default(), None)
        );
        assert_eq!(
            uv_transform(&json!({})).unwrap(),
            (UvTransform::default(), None)
        );
        assert!(uv_transform(&json!({"offset": [1]}))
            .unwrap_err()
            .contains(".offset"));
        assert!(uv_transform(&json!({"rotation": "x"}))
            .unwrap_err()
            .contains(".rotation"));
        assert!(uv_transform(&json!({"texCoord": -1}))
            .unwrap_err()
            .contains(".texCoord"));
    }
}
