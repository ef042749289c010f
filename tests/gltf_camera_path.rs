//! The camera's glTF animation, loaded from small files written on the fly: a camera under an
//! animated parent follows it (LINEAR, STEP with normalized-short rotations, CUBICSPLINE), the
//! first animation that moves the camera's chain is the one used, and a camera nothing moves
//! has no path.

mod common;

use std::path::PathBuf;

use glam::Vec3;
use relief::scene::{load_gltf, SceneOptions};
use serde_json::{json, Value};

use common::base64::base64;

/// A glTF file under construction: each accessor gets its own 4-byte aligned bufferView.
#[derive(Default)]
struct Doc {
    bytes: Vec<u8>,
    views: Vec<Value>,
    accessors: Vec<Value>,
}

impl Doc {
    fn push(&mut self, data: Vec<u8>, mut accessor: Value) -> usize {
        accessor["bufferView"] = json!(self.views.len());
        self.views
            .push(json!({"buffer": 0, "byteOffset": self.bytes.len(), "byteLength": data.len()}));
        self.bytes.extend(&data);
        self.bytes.resize(self.bytes.len().next_multiple_of(4), 0);
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    /// Keyframe times (inputs need min and max).
    fn times(&mut self, t: &[f32]) -> usize {
        let data = t.iter().flat_map(|v| v.to_le_bytes()).collect();
        let (lo, hi) = (t[0], t[t.len() - 1]);
        self.push(
            data,
            json!({"componentType": 5126, "count": t.len(), "type": "SCALAR", "min": [lo], "max": [hi]}),
        )
    }

    fn vec3s(&mut self, v: &[[f32; 3]]) -> usize {
        let data = v.iter().flatten().flat_map(|x| x.to_le_bytes()).collect();
        self.push(
            data,
            json!({"componentType": 5126, "count": v.len(), "type": "VEC3"}),
        )
    }

    /// Rotations as normalized signed shorts (glTF allows them for rotation outputs).
    fn short_quats(&mut self, q: &[[f32; 4]]) -> usize {
        let data = q
            .iter()
            .flatten()
            .flat_map(|x| ((x * 32767.0).round() as i16).to_le_bytes())
            .collect();
        self.push(
            data,
            json!({"componentType": 5122, "normalized": true, "count": q.len(), "type": "VEC4"}),
        )
    }

    fn finish(self, nodes: Value, animations: Value) -> Value {
        let uri = format!(
            "data:application/octet-stream;base64,{}",
            base64(&self.bytes)
        );
        json!({
            "asset": {"version": "2.0"},
            "buffers": [{"byteLength": self.bytes.len(), "uri": uri}],
            "bufferViews": self.views,
            "accessors": self.accessors,
            "cameras": [
                {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "zfar": 100.0}},
                {"type": "perspective", "perspective": {"yfov": 0.5, "znear": 0.1}}
            ],
            "nodes": nodes,
            "scenes": [{"nodes": [0, 3]}],
            "animations": animations
        })
    }
}

/// Node 0 (at y = 1) > node 1 (animated parent) > node 2 (camera 0, 3 units along +z); node 3
/// is a second root holding camera 1. Animation 0 moves only node 3; animation 1 moves node 1:
/// translation LINEAR (0,0,0) -> (2,0,0) -> (2,0,4) at 0, 1, 2 s, and rotation STEP from none
/// to 90 degrees about +y at 1.5 s.
fn rig() -> Value {
    let mut d = Doc::default();
    let t3 = d.times(&[0.0, 1.0, 2.0]);
    let moves = d.vec3s(&[[0.0; 3], [2.0, 0.0, 0.0], [2.0, 0.0, 4.0]]);
    let t2 = d.times(&[0.0, 1.5]);
    let h = std::f32::consts::FRAC_1_SQRT_2;
    let turns = d.short_quats(&[[0.0, 0.0, 0.0, 1.0], [0.0, h, 0.0, h]]);
    let nodes = json!([
        {"translation": [0.0, 1.0, 0.0], "children": [1]},
        {"children": [2]},
        {"camera": 0, "translation": [0.0, 0.0, 3.0]},
        {"camera": 1, "translation": [0.0, 0.0, 9.0]}
    ]);
    let animations = json!([
        {"samplers": [{"input": t3, "output": moves}],
         "channels": [{"sampler": 0, "target": {"node": 3, "path": "translation"}}]},
        {"samplers": [
            {"input": t3, "output": moves, "interpolation": "LINEAR"},
            {"input": t2, "output": turns, "interpolation": "STEP"}
         ],
         "channels": [
            {"sampler": 0, "target": {"node": 1, "path": "translation"}},
            {"sampler": 1, "target": {"node": 1, "path": "rotation"}}
         ]}
    ]);
    d.finish(nodes, animations)
}

fn write(name: &str, doc: &Value) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-camera-path-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_vec_pretty(doc).unwrap()).unwrap();
    path
}

fn assert_near(got: Vec3, want: Vec3, what: &str) {
    assert!(
        (got - want).length() < 1e-3,
        "{what}: eye {got} but want {want}"
    );
}

#[test]
fn a_camera_under_an_animated_parent_follows_it() {
    let scene = load_gltf(&write("rig", &rig()), &SceneOptions::default()).unwrap();
    let path = scene
        .camera_path
        .expect("animation 1 moves the camera's parent");
    assert_eq!(path.duration(), 2.0);
    assert_eq!(path.start(), 0.0);
    // eye = (0,1,0) + translation(t) + rotation(t) * (0,0,3); 90 degrees about +y takes
    // (0,0,3) to (3,0,0).
    let expected = [
        (-1.0, Vec3::new(0.0, 1.0, 3.0)),
        (0.0, Vec3::new(0.0, 1.0, 3.0)),
        (0.5, Vec3::new(1.0, 1.0, 3.0)),
        (1.0, Vec3::new(2.0, 1.0, 3.0)),
        (1.5, Vec3::new(5.0, 1.0, 2.0)),
        (2.0, Vec3::new(5.0, 1.0, 4.0)),
        (7.0, Vec3::new(5.0, 1.0, 4.0)),
    ];
    for (t, eye) in expected {
        assert_near(path.sample(t).eye(), eye, &format!("t = {t}"));
    }
    // The still camera is the rest pose, and the path keeps the camera's projection.
    let rest = scene.camera.unwrap();
    assert_near(rest.eye(), Vec3::new(0.0, 1.0, 3.0), "rest pose");
    assert_eq!(path.sample(1.0).projection, rest.projection);
}

#[test]
fn cubic_spline_on_the_camera_node_itself() {
    // Keys (in-tangent, value, out-tangent) at 0 s and 2 s; by hand at 0.5 s the Hermite
    // weights are 0.84375, 0.28125 (out-tangent x dt), 0.15625, -0.09375 (in-tangent x dt).
    let mut doc = rig();
    let mut d = Doc::default();
    let times = d.times(&[0.0, 2.0]);
    let keys = d.vec3s(&[
        [9.0, 9.0, 9.0],
        [1.0, 2.0, 0.0],
        [1.0, 0.0, -2.0],
        [0.0, 4.0, 2.0],
        [3.0, 2.0, 4.0],
        [9.0, 9.0, 9.0],
    ]);
    let animations = json!([{
        "samplers": [{"input": times, "output": keys, "interpolation": "CUBICSPLINE"}],
        "channels": [{"sampler": 0, "target": {"node": 2, "path": "translation"}}]
    }]);
    let nodes = doc["nodes"].take();
    doc = d.finish(nodes, animations);
    let scene = load_gltf(&write("cubic", &doc), &SceneOptions::default()).unwrap();
    let path = scene.camera_path.expect("the camera's node is animated");
    let up = Vec3::new(0.0, 1.0, 0.0);
    assert_near(
        path.sample(0.5).eye(),
        up + Vec3::new(1.59375, 1.625, -0.125),
        "t = 0.5",
    );
    assert_near(
        path.sample(0.0).eye(),
        up + Vec3::new(1.0, 2.0, 0.0),
        "t = 0",
    );
    assert_near(
        path.sample(2.0).eye(),
        up + Vec3::new(3.0, 2.0, 4.0),
        "t = 2",
    );
}

#[test]
fn a_camera_no_animation_moves_has_no_path() {
    let mut doc = rig();
    let second = SceneOptions {
        camera: Some(1),
        ..SceneOptions::default()
    };
    // Camera 1's node is moved by animation 0 only, so it does get a path.
    let moved = load_gltf(&write("second", &doc), &second).unwrap();
    let path = moved.camera_path.expect("animation 0 moves node 3");
    assert_near(path.sample(2.0).eye(), Vec3::new(2.0, 0.0, 4.0), "node 3");
    // Without animations, neither camera has a path.
    doc.as_object_mut().unwrap().remove("animations");
    let path = write("still", &doc);
    for opts in [SceneOptions::default(), second] {
        let scene = load_gltf(&path, &opts).unwrap();
        assert!(scene.camera.is_some());
        assert!(scene.camera_path.is_none());
    }
    // An animation that moves only another node gives no path either.
    let mut doc = rig();
    doc["animations"] = json!([doc["animations"][0].clone()]);
    let scene = load_gltf(&write("other-node", &doc), &SceneOptions::default()).unwrap();
    assert!(scene.camera_path.is_none());
}

#[test]
fn corpus_animated_cameras_play() {
    let Some(corpus) = common::corpus::corpus("corpus_animated_cameras_play") else {
        return;
    };
    let mut played = 0;
    for file in common::corpus::gltf_files(&corpus.join("gltf")) {
        // Only files that mention animations can animate a camera; the rest are not loaded.
        let bytes = std::fs::read(&file).unwrap();
        if !bytes.windows(12).any(|w| w == b"\"animations\"") {
            continue;
        }
        let Ok(scene) = load_gltf(&file, &SceneOptions::default()) else {
            continue;
        };
        let Some(path) = scene.camera_path else {
            continue;
        };
        for i in 0..=8 {
            let t = path.duration() * i as f32 / 8.0;
            let camera = path.sample(t);
            assert!(camera.view.is_finite(), "{}: t = {t}", file.display());
        }
        played += 1;
    }
    if played == 0 {
        eprintln!("SKIPPED: no glTF file in the corpus animates its camera");
    }
}
