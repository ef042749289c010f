//! The square plane glTF tests draw: y = 0, facing +y, x and z in -1..1, uv 0..1 along them.

use serde_json::{json, Value};

/// Its buffer (positions, normals, uvs, u16 indices, then `colors` per vertex when given) and the
/// `bufferViews` and `accessors` over it: accessor 0 POSITION, 1 NORMAL, 2 TEXCOORD_0, 3 the
/// indices, 4 COLOR_0 (with colours).
pub fn plane_buffer(colors: Option<[[f32; 4]; 4]>) -> (Vec<u8>, Value, Value) {
    let positions: [[f32; 3]; 4] = [[-1., 0., -1.], [1., 0., -1.], [1., 0., 1.], [-1., 0., 1.]];
    let normals = [[0f32, 1., 0.]; 4];
    let uvs: [[f32; 2]; 4] = [[0., 0.], [1., 0.], [1., 1.], [0., 1.]];
    let indices: [u16; 6] = [0, 2, 1, 0, 3, 2];
    let mut bin: Vec<u8> = Vec::new();
    bin.extend_from_slice(bytemuck::cast_slice(&positions));
    bin.extend_from_slice(bytemuck::cast_slice(&normals));
    bin.extend_from_slice(bytemuck::cast_slice(&uvs));
    bin.extend_from_slice(bytemuck::cast_slice(&indices));
    // Pads the indices (128..140) to 4-byte alignment.
    bin.extend_from_slice(&[0; 4]);
    let mut views = vec![
        json!({"buffer": 0, "byteOffset": 0, "byteLength": 48}),
        json!({"buffer": 0, "byteOffset": 48, "byteLength": 48}),
        json!({"buffer": 0, "byteOffset": 96, "byteLength": 32}),
        json!({"buffer": 0, "byteOffset": 128, "byteLength": 12}),
    ];
    let mut accessors = vec![
        json!({"bufferView": 0, "componentType": 5126, "count": 4, "type": "VEC3", "min": [-1.0, 0.0, -1.0], "max": [1.0, 0.0, 1.0]}),
        json!({"bufferView": 1, "componentType": 5126, "count": 4, "type": "VEC3"}),
        json!({"bufferView": 2, "componentType": 5126, "count": 4, "type": "VEC2"}),
        json!({"bufferView": 3, "componentType": 5123, "count": 6, "type": "SCALAR"}),
    ];
    if let Some(colors) = colors {
        views.push(json!({"buffer": 0, "byteOffset": bin.len(), "byteLength": 64}));
        accessors.push(json!({"bufferView": 4, "componentType": 5126, "count": 4, "type": "VEC4"}));
        bin.extend_from_slice(bytemuck::cast_slice(&colors));
    }
    (bin, Value::Array(views), Value::Array(accessors))
}
