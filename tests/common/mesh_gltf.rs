//! Small glTF meshes written by tests: positions and triangles in one embedded buffer.

use std::path::{Path, PathBuf};

use serde_json::json;

use super::base64::base64;

/// A glTF file of one mesh with these positions and triangles.
pub fn write_mesh(
    dir: &Path,
    name: &str,
    positions: &[[f32; 3]],
    triangles: &[[u16; 3]],
) -> PathBuf {
    let mut bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    let index_offset = bytes.len();
    bytes.extend(triangles.iter().flatten().flat_map(|i| i.to_le_bytes()));
    while bytes.len() % 4 != 0 {
        bytes.push(0);
    }
    let lo: Vec<f32> = (0..3)
        .map(|k| positions.iter().map(|p| p[k]).fold(f32::INFINITY, f32::min))
        .collect();
    let hi: Vec<f32> = (0..3)
        .map(|k| {
            positions
                .iter()
                .map(|p| p[k])
                .fold(f32::NEG_INFINITY, f32::max)
        })
        .collect();
    let doc = json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{}", base64(&bytes))}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": index_offset},
            {"buffer": 0, "byteOffset": index_offset, "byteLength": triangles.len() * 6}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": positions.len(), "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5123, "count": triangles.len() * 3, "type": "SCALAR"}
        ],
        "meshes": [{"name": name, "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0, "translation": [2.0, 0.0, 0.0]}],
        "scenes": [{"nodes": [0]}]
    });
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_vec_pretty(&doc).unwrap()).unwrap();
    path
}

pub const TETRAHEDRON: [[f32; 3]; 4] = [
    [0.0, 0.0, 0.0],
    [1.0, 0.0, 0.0],
    [0.0, 1.0, 0.0],
    [0.0, 0.0, 1.0],
];
pub const TETRAHEDRON_FACES: [[u16; 3]; 4] = [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]];
