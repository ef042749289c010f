//! The glTF seed: the test plane under a relief material (`extras.relief` with a height texture,
//! method, shadows, LOD), its height map an embedded PNG, and a perspective camera moved by a
//! two-key animation, so one file reaches the extras reader, the accessor and image readers and
//! the camera-path reader. Written as `.gltf` (JSON, data URIs) and as `.glb` (binary chunks).

use serde_json::{json, Value};

use crate::common::base64::base64;
use crate::common::plane_gltf::plane_buffer;

/// A 4x4 grey PNG, the relief's height map.
fn height_png() -> Vec<u8> {
    let img = image::GrayImage::from_fn(4, 4, |x, y| image::Luma([(x * 60 + y * 5) as u8]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png)
        .expect("encodes");
    out.into_inner()
}

/// The document without its buffer's `uri`, and the buffer's bytes.
fn document() -> (Value, Vec<u8>) {
    let (mut bin, views, accessors) = plane_buffer(None);
    let (Value::Array(mut views), Value::Array(mut accessors)) = (views, accessors) else {
        unreachable!("plane_buffer returns arrays")
    };
    let times: [f32; 2] = [0.0, 1.0];
    let places: [[f32; 3]; 2] = [[0.0, 1.0, 3.0], [1.0, 1.0, 3.0]];
    let at = bin.len();
    bin.extend_from_slice(bytemuck::cast_slice(&times));
    bin.extend_from_slice(bytemuck::cast_slice(&places));
    views.push(json!({"buffer": 0, "byteOffset": at, "byteLength": 8}));
    views.push(json!({"buffer": 0, "byteOffset": at + 8, "byteLength": 24}));
    let (tv, pv) = (views.len() - 2, views.len() - 1);
    accessors.push(json!({"bufferView": tv, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [0.0], "max": [1.0]}));
    accessors.push(json!({"bufferView": pv, "componentType": 5126, "count": 2, "type": "VEC3"}));
    let (ta, pa) = (accessors.len() - 2, accessors.len() - 1);
    let doc = json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [{"mesh": 0}, {"camera": 0, "translation": [0.0, 1.0, 3.0]}],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100.0}}],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2}, "indices": 3, "material": 0}]}],
        "materials": [{
            "pbrMetallicRoughness": {"baseColorFactor": [0.8, 0.7, 0.6, 1.0]},
            "extras": {"relief": {
                "height": {"index": 0, "texCoord": 0, "channel": "r", "invert": false},
                "depth_scale": 0.05, "method": "qdm", "budget": 64,
                "shadows": "horizon", "shadow_steps": 5, "ao": "horizon-8",
                "lod": {"factor": 1, "bias": 0, "fade_start": 0, "fade_end": 0, "average_below": 16}
            }}
        }],
        "textures": [{"source": 0}],
        "images": [{"uri": format!("data:image/png;base64,{}", base64(&height_png()))}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors,
        "animations": [{
            "channels": [{"sampler": 0, "target": {"node": 1, "path": "translation"}}],
            "samplers": [{"input": ta, "output": pa, "interpolation": "LINEAR"}]
        }]
    });
    (doc, bin)
}

/// The `.gltf` form: one JSON document, its buffer a base64 data URI.
pub fn gltf_json() -> Value {
    let (mut doc, bin) = document();
    doc["buffers"][0]["uri"] = Value::String(format!(
        "data:application/octet-stream;base64,{}",
        base64(&bin)
    ));
    doc
}

/// The `.glb` form: header, JSON chunk, BIN chunk (each padded to 4 bytes).
pub fn glb() -> Vec<u8> {
    let (doc, mut bin) = document();
    let mut json = serde_json::to_vec(&doc).expect("serialises");
    json.resize(json.len().div_ceil(4) * 4, b' ');
    bin.resize(bin.len().div_ceil(4) * 4, 0);
    let total = 12 + 8 + json.len() + 8 + bin.len();
    let mut out = Vec::with_capacity(total);
    out.extend_from_slice(b"glTF");
    out.extend_from_slice(&2u32.to_le_bytes());
    out.extend_from_slice(&(total as u32).to_le_bytes());
    out.extend_from_slice(&(json.len() as u32).to_le_bytes());
    out.extend_from_slice(b"JSON");
    out.extend_from_slice(&json);
    out.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    out.extend_from_slice(b"BIN\0");
    out.extend_from_slice(&bin);
    out
}
