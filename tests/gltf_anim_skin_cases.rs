//! Animations, skins and joint/weight attributes in small glTF files written on the fly: a
//! valid rig loads, and each broken rule is rejected with a message naming what broke it.

mod common;

use std::path::PathBuf;

use relief::scene::{load_gltf, SceneOptions};
use serde_json::{json, Value};

use common::base64::base64;

/// The data of a two-joint rig: keyframe times, translation and rotation keys, per-vertex
/// joints and weights of a triangle, and two inverse bind matrices.
struct Rig {
    times: [f32; 2],
    rotations: [[f32; 4]; 2],
    joints: [[u8; 4]; 3],
    weights: [[f32; 4]; 3],
    ibm: [[f32; 16]; 2],
}

impl Default for Rig {
    fn default() -> Rig {
        let identity = [
            1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0,
        ];
        Rig {
            times: [0.0, 1.0],
            rotations: [[0.0, 0.0, 0.0, 1.0], [0.0, 0.6, 0.0, 0.8]],
            joints: [[0, 0, 0, 0], [0, 1, 0, 0], [1, 0, 0, 0]],
            weights: [
                [1.0, 0.0, 0.0, 0.0],
                [0.25, 0.75, 0.0, 0.0],
                [1.0, 0.0, 0.0, 0.0],
            ],
            ibm: [identity; 2],
        }
    }
}

fn f32_bytes<'a>(values: impl IntoIterator<Item = &'a f32>) -> Vec<u8> {
    values.into_iter().flat_map(|v| v.to_le_bytes()).collect()
}

/// Nodes 0 (root joint) > 1 (joint), node 2 draws the triangle with skin 0; animation 0
/// moves and turns node 1.
fn rig_doc(rig: &Rig) -> Value {
    let parts: Vec<Vec<u8>> = vec![
        f32_bytes(&[0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0]),
        f32_bytes(&rig.times),
        f32_bytes(&[0.0, 0.0, 0.0, 1.0, 2.0, 3.0]),
        f32_bytes(rig.rotations.iter().flatten()),
        rig.joints.iter().flatten().copied().collect(),
        f32_bytes(rig.weights.iter().flatten()),
        f32_bytes(rig.ibm.iter().flatten()),
    ];
    let mut bytes = Vec::new();
    let mut views = Vec::new();
    for p in &parts {
        views.push(json!({"buffer": 0, "byteOffset": bytes.len(), "byteLength": p.len()}));
        bytes.extend(p);
    }
    let (lo, hi) = (
        rig.times[0].min(rig.times[1]),
        rig.times[0].max(rig.times[1]),
    );
    json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{}", base64(&bytes))}],
        "bufferViews": views,
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": [0.0, 0.0, 0.0], "max": [1.0, 1.0, 0.0]},
            {"bufferView": 1, "componentType": 5126, "count": 2, "type": "SCALAR", "min": [lo], "max": [hi]},
            {"bufferView": 2, "componentType": 5126, "count": 2, "type": "VEC3"},
            {"bufferView": 3, "componentType": 5126, "count": 2, "type": "VEC4"},
            {"bufferView": 4, "componentType": 5121, "count": 3, "type": "VEC4"},
            {"bufferView": 5, "componentType": 5126, "count": 3, "type": "VEC4"},
            {"bufferView": 6, "componentType": 5126, "count": 2, "type": "MAT4"}
        ],
        "meshes": [{"primitives": [{"attributes": {"POSITION": 0, "JOINTS_0": 4, "WEIGHTS_0": 5}}]}],
        "skins": [{"joints": [0, 1], "inverseBindMatrices": 6, "skeleton": 0}],
        "nodes": [{"children": [1]}, {"translation": [0.0, 1.0, 0.0]}, {"mesh": 0, "skin": 0}],
        "scenes": [{"nodes": [0, 2]}],
        "animations": [{
            "samplers": [{"input": 1, "output": 2}, {"input": 1, "output": 3, "interpolation": "LINEAR"}],
            "channels": [
                {"sampler": 0, "target": {"node": 1, "path": "translation"}},
                {"sampler": 1, "target": {"node": 1, "path": "rotation"}}
            ]
        }]
    })
}

fn write(name: &str, doc: &Value) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-anim-skin-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_vec_pretty(doc).unwrap()).unwrap();
    path
}

/// The error for `doc`, after checking it names the file and contains every part of `want`.
fn rejected(name: &str, doc: &Value, want: &[&str]) {
    let path = write(name, doc);
    let err = load_gltf(&path, &SceneOptions::default())
        .expect_err("the file should be rejected")
        .to_string();
    assert!(err.starts_with(&format!("scene {path:?}: ")), "{err}");
    for w in want {
        assert!(err.contains(w), "{name}: {err:?} lacks {w:?}");
    }
}

#[test]
fn valid_rig_loads() {
    let s = load_gltf(
        &write("valid", &rig_doc(&Rig::default())),
        &SceneOptions::default(),
    )
    .unwrap();
    assert_eq!(s.meshes.len(), 1);
}

#[test]
fn keyframe_times_must_increase() {
    let rig = Rig {
        times: [1.0, 1.0],
        ..Rig::default()
    };
    rejected(
        "times",
        &rig_doc(&rig),
        &[
            "animation 0 sampler 0: input accessor 1",
            "strictly increase",
        ],
    );
    let rig = Rig {
        times: [-1.0, 1.0],
        ..Rig::default()
    };
    rejected("negative", &rig_doc(&rig), &["keyframe time 0 is negative"]);
}

#[test]
fn rotations_must_be_unit_quaternions() {
    let rig = Rig {
        rotations: [[0.0, 0.0, 0.0, 1.0], [0.0, 0.5, 0.0, 0.5]],
        ..Rig::default()
    };
    rejected(
        "quat",
        &rig_doc(&rig),
        &["animation 0 channel 1", "output accessor 3", "unit length"],
    );
}

#[test]
fn channel_targets_are_checked() {
    let mut doc = rig_doc(&Rig::default());
    doc["animations"][0]["channels"][1]["target"]["path"] = json!("translation");
    doc["animations"][0]["channels"][1]["sampler"] = json!(0);
    rejected(
        "duplicate",
        &doc,
        &["animation 0: channels 0 and 1 both target node 1 translation"],
    );

    let mut doc = rig_doc(&Rig::default());
    doc["nodes"][1] = json!({"matrix": [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]});
    rejected("matrix", &doc, &["animation 0 channel 0", "has a matrix"]);

    let mut doc = rig_doc(&Rig::default());
    doc["animations"][0]["channels"][1]["target"]["path"] = json!("weights");
    rejected("morphs", &doc, &["node 1", "no morph targets"]);

    let mut doc = rig_doc(&Rig::default());
    doc["accessors"][2]["count"] = json!(1);
    rejected(
        "count",
        &doc,
        &["output accessor 2 has 1 elements", "exactly 2"],
    );

    let mut doc = rig_doc(&Rig::default());
    doc["animations"][0]["samplers"][0]["output"] = json!(3);
    rejected(
        "format",
        &doc,
        &["output accessor 3 is Vec4 F32", "Vec3 F32"],
    );
}

#[test]
fn joints_and_weights_are_checked() {
    let mut rig = Rig::default();
    rig.joints[1] = [0, 2, 0, 0];
    rejected(
        "joint-oob",
        &rig_doc(&rig),
        &["mesh 0 primitive 0", "joint 2 but its skin has 2 joints"],
    );

    let mut rig = Rig::default();
    rig.joints[1] = [1, 1, 0, 0];
    rejected("joint-twice", &rig_doc(&rig), &["joint 1 twice"]);

    let mut rig = Rig::default();
    rig.weights[2] = [0.5, 0.0, 0.0, 0.0];
    rejected("sum", &rig_doc(&rig), &["vertex 2's weights sum to 0.5"]);

    let mut rig = Rig::default();
    rig.weights[0] = [1.5, -0.5, 0.0, 0.0];
    rejected("negative-weight", &rig_doc(&rig), &["negative weight -0.5"]);

    let mut doc = rig_doc(&Rig::default());
    doc["meshes"][0]["primitives"][0]["attributes"]["JOINTS_1"] = json!(4);
    rejected("pairs", &doc, &["2 JOINTS_n attributes but 1 WEIGHTS_n"]);
}

#[test]
fn skins_are_checked() {
    let mut doc = rig_doc(&Rig::default());
    doc["accessors"][6]["count"] = json!(1);
    rejected(
        "ibm-count",
        &doc,
        &[
            "skin 0: inverseBindMatrices accessor 6",
            "1 matrices for 2 joints",
        ],
    );

    let mut rig = Rig::default();
    rig.ibm[1][7] = 2.0;
    rejected(
        "ibm-affine",
        &rig_doc(&rig),
        &["matrix 1", "component 7", "affine"],
    );

    let mut doc = rig_doc(&Rig::default());
    doc["skins"][0]["skeleton"] = json!(1);
    rejected("skeleton", &doc, &["skeleton node 1 is not a common root"]);

    let mut doc = rig_doc(&Rig::default());
    doc["nodes"][0] = json!({});
    doc["scenes"][0]["nodes"] = json!([0, 1, 2]);
    doc["skins"][0].as_object_mut().unwrap().remove("skeleton");
    rejected(
        "common-root",
        &doc,
        &["skin 0: joints 0 and 1 have no common root"],
    );

    let mut doc = rig_doc(&Rig::default());
    doc["scenes"][0]["nodes"] = json!([2]);
    rejected(
        "joints-in-scene",
        &doc,
        &["scene 0: node 2", "joint node 0 is not in the scene"],
    );

    let mut doc = rig_doc(&Rig::default());
    doc["meshes"][0]["primitives"][0]["attributes"] = json!({"POSITION": 0});
    rejected(
        "skin-without-joints",
        &doc,
        &["node 2: has skin 0", "no JOINTS_0"],
    );
}
