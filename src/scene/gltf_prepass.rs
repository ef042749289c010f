//! The file's bytes to a validated `gltf::Document`, by way of the raw JSON: the GLB container
//! is checked strictly (the gltf crate accepts misplaced, oversized or duplicate chunks), the
//! JSON is checked for what the gltf crate's validator misses or panics on, and patched where
//! that validator is stricter than glTF 2.0 itself.

use serde_json::{Map, Value};

use super::gltf_accessor::MAX_ZERO_COMPONENTS;

const GLB_JSON: u32 = 0x4E4F_534A;
const GLB_BIN: u32 = 0x004E_4942;

/// The document, its raw JSON (for extension fields the gltf crate does not expose) and the
/// GLB binary chunk, if any.
pub(super) struct Parsed {
    pub doc: gltf::Document,
    pub raw: Value,
    pub blob: Option<Vec<u8>>,
    /// Buffers from this index on are the zero fill of accessors without a bufferView.
    pub zero_buffers: usize,
}

pub(super) fn parse(bytes: &[u8]) -> Result<Parsed, String> {
    let (json, blob) = if bytes.starts_with(b"glTF") {
        let (json, bin) = split_glb(bytes)?;
        (json, bin.map(<[u8]>::to_vec))
    } else {
        (bytes, None)
    };
    let mut raw: Value = serde_json::from_slice(json).map_err(|e| format!("JSON: {e}"))?;
    let zero_buffers = raw
        .get("buffers")
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    check_and_patch(&mut raw)?;
    let root: gltf::json::Root =
        serde_json::from_value(raw.clone()).map_err(|e| format!("glTF JSON: {e}"))?;
    let doc = gltf::Document::from_json(root).map_err(|e| e.to_string())?;
    Ok(Parsed {
        doc,
        raw,
        blob,
        zero_buffers,
    })
}

fn u32_at(bytes: &[u8], at: usize) -> Option<u32> {
    bytes
        .get(at..at + 4)
        .map(|b| u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
}

/// The JSON chunk and the BIN chunk of a GLB file, after checking its header and chunk layout.
fn split_glb(bytes: &[u8]) -> Result<(&[u8], Option<&[u8]>), String> {
    let version = u32_at(bytes, 4).ok_or("GLB: truncated header")?;
    let length = u32_at(bytes, 8).ok_or("GLB: truncated header")? as usize;
    if version != 2 {
        return Err(format!("GLB: version {version}, only 2 is supported"));
    }
    // Bytes after the stated length are ignored (the validator only warns about them).
    let bytes = bytes.get(..length).ok_or_else(|| {
        format!(
            "GLB: header says {length} bytes, the file has {}",
            bytes.len()
        )
    })?;
    let (mut at, mut json, mut bin, mut chunk) = (12, None, None, 0);
    while at < bytes.len() {
        let (Some(len), Some(kind)) = (u32_at(bytes, at), u32_at(bytes, at + 4)) else {
            return Err(format!("GLB: truncated chunk header at byte {at}"));
        };
        let len = len as usize;
        let data = bytes
            .get(at + 8..at + 8 + len)
            .ok_or_else(|| format!("GLB: chunk at byte {at} runs past the end of the file"))?;
        if len % 4 != 0 {
            return Err(format!(
                "GLB: chunk at byte {at} has a length ({len}) that is not a multiple of 4"
            ));
        }
        match kind {
            GLB_JSON if at == 12 && len > 0 => json = Some(data),
            GLB_BIN if chunk == 1 && len > 0 => bin = Some(data),
            GLB_JSON | GLB_BIN => {
                return Err(format!(
                    "GLB: misplaced, empty or repeated {} chunk at byte {at}",
                    if kind == GLB_JSON { "JSON" } else { "BIN" }
                ))
            }
            _ => {} // Unknown chunk types are to be ignored.
        }
        at += 8 + len;
        chunk += 1;
    }
    Ok((json.ok_or("GLB: no JSON chunk")?, bin))
}

/// Rejects what the gltf crate's validator misses (or panics on) and fills in what it wrongly
/// requires.
fn check_and_patch(raw: &mut Value) -> Result<(), String> {
    check_extensions(raw, "")?;
    let root = raw
        .as_object_mut()
        .ok_or("JSON: the top level is not an object")?;
    check_asset(root)?;
    check_empty_arrays(root)?;
    check_positions(root)?;
    check_image_sources(root)?;
    for (i, skin) in array(root, "skins").iter().enumerate() {
        if skin
            .get("joints")
            .and_then(Value::as_array)
            .is_some_and(Vec::is_empty)
        {
            return Err(format!("skins[{i}].joints: empty array"));
        }
    }
    check_buffer_uris(root)?;
    for (i, cam) in array(root, "cameras").iter().enumerate() {
        if cam.get("perspective").is_some() && cam.get("orthographic").is_some() {
            return Err(format!(
                "cameras[{i}]: has both perspective and orthographic"
            ));
        }
    }
    for (i, node) in array(root, "nodes").iter().enumerate() {
        if node.get("mesh").is_none()
            && (node.get("skin").is_some() || node.get("weights").is_some())
        {
            return Err(format!("nodes[{i}]: skin or weights without a mesh"));
        }
        if node
            .get("children")
            .and_then(Value::as_array)
            .is_some_and(Vec::is_empty)
        {
            return Err(format!("nodes[{i}].children: empty array"));
        }
    }
    patch_scene_nodes(root)?;
    drop_extension_channels(root);
    zero_fill_accessors(root)
}

/// Arrays the spec requires to be non-empty when present.
fn check_empty_arrays(root: &Map<String, Value>) -> Result<(), String> {
    for key in [
        "accessors",
        "animations",
        "buffers",
        "bufferViews",
        "cameras",
        "images",
        "materials",
        "meshes",
        "nodes",
        "samplers",
        "scenes",
        "skins",
        "textures",
    ] {
        if root
            .get(key)
            .and_then(Value::as_array)
            .is_some_and(Vec::is_empty)
        {
            return Err(format!("{key}: empty array (omit it instead)"));
        }
    }
    Ok(())
}

/// Primitives' POSITION accessors exist.
fn check_positions(root: &Map<String, Value>) -> Result<(), String> {
    let accessors = root
        .get("accessors")
        .and_then(Value::as_array)
        .map_or(0, Vec::len);
    for (m, mesh) in array(root, "meshes").iter().enumerate() {
        for (p, prim) in mesh["primitives"]
            .as_array()
            .into_iter()
            .flatten()
            .enumerate()
        {
            // gltf-json indexes the accessor list with POSITION before checking the index.
            if let Some(pos) = prim.get("attributes").and_then(|a| a.get("POSITION")) {
                if pos.as_u64().is_none_or(|i| i as usize >= accessors) {
                    return Err(format!(
                        "meshes[{m}].primitives[{p}].attributes.POSITION: no accessor {pos}"
                    ));
                }
            }
        }
    }
    Ok(())
}

/// Images name one source and textures an image.
fn check_image_sources(root: &Map<String, Value>) -> Result<(), String> {
    for (i, image) in array(root, "images").iter().enumerate() {
        // The gltf crate unwraps these.
        let (uri, view, mime) = (
            image.get("uri"),
            image.get("bufferView"),
            image.get("mimeType"),
        );
        if uri.is_some() == view.is_some() || (view.is_some() && mime.is_none()) {
            return Err(format!(
                "images[{i}]: needs exactly one of uri and bufferView (with mimeType)"
            ));
        }
    }
    for (i, texture) in array(root, "textures").iter().enumerate() {
        if texture.get("source").is_none() {
            return Err(format!(
                "textures[{i}]: no source image (images through extensions such as KTX2 or WebP are not supported)"
            ));
        }
    }
    Ok(())
}

/// Embedded buffers are base64 binary data URIs.
fn check_buffer_uris(root: &Map<String, Value>) -> Result<(), String> {
    for (i, buffer) in array(root, "buffers").iter().enumerate() {
        if let Some(uri) = buffer.get("uri").and_then(Value::as_str) {
            let ok = [
                "data:application/octet-stream;base64,",
                "data:application/gltf-buffer;base64,",
            ];
            if uri.starts_with("data:") && !ok.iter().any(|p| uri.starts_with(p)) {
                return Err(format!(
                    "buffers[{i}].uri: not a base64 application/octet-stream data URI"
                ));
            }
        }
    }
    Ok(())
}

/// glTF 2.0 makes scene.nodes optional; gltf-json requires it, so scenes without get an empty
/// list (an empty list given is refused).
fn patch_scene_nodes(root: &mut Map<String, Value>) -> Result<(), String> {
    if let Some(scenes) = root.get_mut("scenes").and_then(Value::as_array_mut) {
        for (i, scene) in scenes.iter_mut().enumerate() {
            match scene.as_object_mut() {
                Some(s)
                    if s.get("nodes")
                        .and_then(Value::as_array)
                        .is_some_and(Vec::is_empty) =>
                {
                    return Err(format!("scenes[{i}].nodes: empty array"));
                }
                Some(s) => {
                    s.entry("nodes").or_insert_with(|| Value::Array(Vec::new()));
                }
                None => {}
            }
        }
    }
    Ok(())
}

/// A channel without target.node animates something an extension names; gltf-json requires
/// the node, and animations are not played here, so such channels are dropped.
fn drop_extension_channels(root: &mut Map<String, Value>) {
    if let Some(anims) = root.get_mut("animations").and_then(Value::as_array_mut) {
        for anim in anims {
            if let Some(channels) = anim.get_mut("channels").and_then(Value::as_array_mut) {
                channels.retain(|c| c.get("target").is_none_or(|t| t.get("node").is_some()));
            }
        }
    }
}

/// glTF allows an accessor with neither bufferView nor sparse (all zeros); gltf-json rejects it,
/// so it gets a bufferView over a new zero-filled buffer (a base64 data URI of 'A's).
fn zero_fill_accessors(root: &mut Map<String, Value>) -> Result<(), String> {
    let mut needs = Vec::new();
    for (i, acc) in array(root, "accessors").iter().enumerate() {
        // Not an object: gltf-json refuses it by name; there is nothing to fill in.
        if !acc.is_object() {
            continue;
        }
        if acc.get("bufferView").is_none() && acc.get("byteOffset").is_some() {
            return Err(format!("accessors[{i}]: byteOffset without bufferView"));
        }
        if acc.get("bufferView").is_none() && acc.get("sparse").is_none() {
            let count = acc["count"].as_u64().unwrap_or(0);
            let comps = match acc["type"].as_str() {
                Some("VEC2") => 2,
                Some("VEC3") => 3,
                Some("VEC4") | Some("MAT2") => 4,
                Some("MAT3") => 12,
                Some("MAT4") => 16,
                _ => 1,
            };
            // No byte of the file stands for these zeros, so their number is capped outright
            // (as the accessor reader caps them), else a 100-byte file could ask for gigabytes.
            if count.saturating_mul(comps) > MAX_ZERO_COMPONENTS as u64 {
                return Err(format!(
                    "accessors[{i}]: {count} zero-filled elements is more than the \
                     {MAX_ZERO_COMPONENTS} zero components read"
                ));
            }
            // Enough bytes for any component type; matrices allowing for column padding.
            let bytes = count * comps * 4;
            needs.push((i, bytes.max(4) as usize));
        }
    }
    for (i, bytes) in needs {
        let groups = bytes.div_ceil(3);
        let buffer = serde_json::json!({
            "byteLength": groups * 3,
            "uri": format!("data:application/octet-stream;base64,{}", "AAAA".repeat(groups)),
        });
        let buffers = root
            .entry("buffers")
            .or_insert_with(|| Value::Array(Vec::new()));
        let buffers = buffers.as_array_mut().ok_or("buffers: not an array")?;
        buffers.push(buffer);
        let view = serde_json::json!({"buffer": buffers.len() - 1, "byteLength": groups * 3});
        let views = root
            .entry("bufferViews")
            .or_insert_with(|| Value::Array(Vec::new()));
        let views = views.as_array_mut().ok_or("bufferViews: not an array")?;
        views.push(view);
        root["accessors"][i]["bufferView"] = Value::from(views.len() - 1);
    }
    Ok(())
}

fn array<'v>(root: &'v Map<String, Value>, key: &str) -> &'v [Value] {
    root.get(key)
        .and_then(Value::as_array)
        .map_or(&[], Vec::as_slice)
}

/// `asset.version` must be "2.x" and `asset.minVersion`, if any, no newer than it.
fn check_asset(root: &Map<String, Value>) -> Result<(), String> {
    let parse = |v: &Value| -> Option<(u32, u32)> {
        let (major, minor) = v.as_str()?.split_once('.')?;
        let digits = |s: &str| !s.is_empty() && s.bytes().all(|b| b.is_ascii_digit());
        (digits(major) && digits(minor))
            .then(|| Some((major.parse().ok()?, minor.parse().ok()?)))?
    };
    let asset = root.get("asset").ok_or("asset: missing")?;
    let version = parse(&asset["version"])
        .ok_or_else(|| format!("asset.version: {} is not MAJOR.MINOR", asset["version"]))?;
    if version.0 != 2 {
        return Err(format!(
            "asset.version: {}.{}; only glTF 2.x is supported",
            version.0, version.1
        ));
    }
    if let Some(min) = asset.get("minVersion") {
        let min =
            parse(min).ok_or_else(|| format!("asset.minVersion: {min} is not MAJOR.MINOR"))?;
        if min > version {
            return Err("asset.minVersion is newer than asset.version".into());
        }
    }
    Ok(())
}

/// Every `extensions` property, anywhere, must map names to objects.
fn check_extensions(v: &Value, path: &str) -> Result<(), String> {
    match v {
        Value::Object(o) => {
            for (k, child) in o {
                let here = format!("{path}/{k}");
                if k == "extensions" {
                    let ext = child
                        .as_object()
                        .ok_or_else(|| format!("{here}: not an object"))?;
                    if let Some((name, _)) = ext.iter().find(|(_, e)| !e.is_object()) {
                        return Err(format!("{here}/{name}: not an object"));
                    }
                }
                check_extensions(child, &here)?;
            }
        }
        Value::Array(a) => {
            // Skip number arrays (matrices, factors) without building their paths.
            for (i, child) in a
                .iter()
                .enumerate()
                .filter(|(_, c)| c.is_object() || c.is_array())
            {
                check_extensions(child, &format!("{path}/{i}"))?;
            }
        }
        _ => {}
    }
    Ok(())
}
