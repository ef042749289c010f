//! Small glTF files written on the fly: node placement, scene and camera choice, lights,
//! relief extras and the errors for broken input.

mod common;

use std::path::PathBuf;

use glam::{Mat4, Quat, Vec3};
use relief::heightfield::Channel;
use relief::scene::{load_gltf, load_gltf_with_report, HeightSource, LightKind, SceneOptions};
use serde_json::{json, Value};

use common::base64::base64;

/// One triangle (0,0,0) (1,0,0) (0,1,0), counter-clockwise seen from +z, indexed 0 1 2.
fn triangle_doc(positions: [[f32; 3]; 3], index: [u16; 3]) -> Value {
    let mut bytes: Vec<u8> = positions
        .iter()
        .flatten()
        .flat_map(|v| v.to_le_bytes())
        .collect();
    bytes.extend(index.iter().flat_map(|i| i.to_le_bytes()));
    bytes.extend([0, 0]);
    // uvs at byte 44, for tests that add TEXCOORD attributes.
    bytes.extend(
        [0.0f32, 0.0, 1.0, 0.0, 0.0, 1.0]
            .iter()
            .flat_map(|v| v.to_le_bytes()),
    );
    let lo: Vec<f32> = (0..3)
        .map(|c| positions.iter().map(|p| p[c]).fold(f32::INFINITY, f32::min))
        .collect();
    let hi: Vec<f32> = (0..3)
        .map(|c| {
            positions
                .iter()
                .map(|p| p[c])
                .fold(f32::NEG_INFINITY, f32::max)
        })
        .collect();
    json!({
        "asset": {"version": "2.0"},
        "buffers": [{"byteLength": bytes.len(), "uri": format!("data:application/octet-stream;base64,{}", base64(&bytes))}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": 36},
            {"buffer": 0, "byteOffset": 36, "byteLength": 6},
            {"buffer": 0, "byteOffset": 44, "byteLength": 24}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": 5126, "count": 3, "type": "VEC3", "min": lo, "max": hi},
            {"bufferView": 1, "componentType": 5123, "count": 3, "type": "SCALAR"},
            {"bufferView": 2, "componentType": 5126, "count": 3, "type": "VEC2"}
        ],
        "meshes": [{"name": "Tri", "primitives": [{"attributes": {"POSITION": 0}, "indices": 1}]}],
        "nodes": [{"mesh": 0}],
        "scenes": [{"nodes": [0]}]
    })
}

fn plain_triangle() -> Value {
    triangle_doc(
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [0, 1, 2],
    )
}

fn write(name: &str, doc: &Value) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("relief-loader-tests-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{name}.gltf"));
    std::fs::write(&path, serde_json::to_vec_pretty(doc).unwrap()).unwrap();
    path
}

fn load_err(name: &str, doc: &Value, opts: SceneOptions) -> String {
    let path = write(name, doc);
    let err = load_gltf(&path, &opts)
        .expect_err("the file should be rejected")
        .to_string();
    assert!(err.starts_with(&format!("scene {:?}: ", path)), "{err}");
    err
}

#[test]
fn mirrored_node_flips_winding() {
    let mut doc = plain_triangle();
    doc["nodes"] = json!([{"mesh": 0}, {"mesh": 0, "scale": [-1.0, 1.0, 1.0]}]);
    doc["scenes"] = json!([{"nodes": [0, 1]}]);
    let s = load_gltf(&write("mirror", &doc), &SceneOptions::default()).unwrap();
    assert_eq!(s.meshes.len(), 2);
    let [plain, mirrored] = [&s.meshes[0], &s.meshes[1]];
    // No NORMAL: flat normals, so the triangle is unwelded (indices 0 1 2 over 3 vertices).
    assert_eq!(plain.indices, vec![0, 1, 2]);
    assert_eq!(mirrored.indices, vec![0, 2, 1]);
    for m in [plain, mirrored] {
        assert_eq!(m.vertices[0].normal, [0.0, 0.0, 1.0]);
    }
    // In world space both front faces are counter-clockwise seen from +z.
    for m in [plain, mirrored] {
        let p = |i: u32| {
            m.transform
                .transform_point3(Vec3::from(m.vertices[i as usize].position))
        };
        let n = (p(m.indices[1]) - p(m.indices[0])).cross(p(m.indices[2]) - p(m.indices[0]));
        assert!(n.z > 0.0, "{n}");
    }
    assert_eq!(
        s.materials.len(),
        1,
        "a default material for the primitive without one"
    );
    assert_eq!(plain.material, 0);
}

#[test]
fn nested_transforms_compose() {
    let mut doc = plain_triangle();
    doc["nodes"] = json!([{"children": [1], "translation": [1.0, 2.0, 3.0]}, {"mesh": 0, "scale": [2.0, 2.0, 2.0]}]);
    let s = load_gltf(&write("nested", &doc), &SceneOptions::default()).unwrap();
    let want =
        Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0)) * Mat4::from_scale(Vec3::splat(2.0));
    assert!(s.meshes[0].transform.abs_diff_eq(want, 1e-6));
}

#[test]
fn scene_choice() {
    let mut doc = plain_triangle();
    doc["scenes"] = json!([{"nodes": [0]}, {}]);
    doc["scene"] = json!(1);
    let s = load_gltf(&write("scenes", &doc), &SceneOptions::default()).unwrap();
    assert!(s.meshes.is_empty(), "the default scene (1) is empty");
    let opts = SceneOptions {
        scene: Some(0),
        camera: None,
    };
    assert_eq!(
        load_gltf(&write("scenes", &doc), &opts)
            .unwrap()
            .meshes
            .len(),
        1
    );
    let err = load_err(
        "scenes",
        &doc,
        SceneOptions {
            scene: Some(2),
            camera: None,
        },
    );
    assert!(
        err.contains("scene 2 requested but the file has 2 scenes"),
        "{err}"
    );
}

#[test]
fn camera_choice() {
    let mut doc = plain_triangle();
    doc["cameras"] = json!([
        {"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.1, "aspectRatio": 1.5}},
        {"type": "orthographic", "orthographic": {"xmag": 2.0, "ymag": 1.0, "znear": 0.0, "zfar": 10.0}}
    ]);
    doc["nodes"] =
        json!([{"mesh": 0}, {"camera": 0, "translation": [0.0, 0.0, 5.0]}, {"camera": 1}]);
    doc["scenes"] = json!([{"nodes": [0, 1, 2]}]);
    let path = write("cameras", &doc);
    let first = load_gltf(&path, &SceneOptions::default())
        .unwrap()
        .camera
        .unwrap();
    assert!((first.eye() - Vec3::new(0.0, 0.0, 5.0)).length() < 1e-6);
    match first.projection {
        relief::scene::Projection::Perspective { aspect, zfar, .. } => {
            assert_eq!(aspect, Some(1.5));
            assert!(zfar > 100.0, "no zfar: a far plane far away");
        }
        other => panic!("{other:?}"),
    }
    let second = load_gltf(
        &path,
        &SceneOptions {
            scene: None,
            camera: Some(1),
        },
    )
    .unwrap()
    .camera
    .unwrap();
    assert!(matches!(
        second.projection,
        relief::scene::Projection::Orthographic { .. }
    ));
    let err = load_err(
        "cameras",
        &doc,
        SceneOptions {
            scene: None,
            camera: Some(2),
        },
    );
    assert!(
        err.contains("camera 2 requested but the scene has 2 cameras"),
        "{err}"
    );
    assert!(
        load_gltf(&write("nocam", &plain_triangle()), &SceneOptions::default())
            .unwrap()
            .camera
            .is_none()
    );
}

#[test]
fn spot_light_in_world_space() {
    let mut doc = plain_triangle();
    doc["extensionsUsed"] = json!(["KHR_lights_punctual"]);
    doc["extensions"] = json!({"KHR_lights_punctual": {"lights": [
        {"type": "spot", "color": [1.0, 0.5, 0.25], "intensity": 4.0, "range": 9.0,
         "spot": {"innerConeAngle": 0.2, "outerConeAngle": 0.5}}
    ]}});
    let q = Quat::from_rotation_x(-std::f32::consts::FRAC_PI_2); // -z turns to -y: pointing down
    doc["nodes"] = json!([{"mesh": 0}, {"translation": [1.0, 3.0, 0.0], "rotation": q.to_array(),
        "extensions": {"KHR_lights_punctual": {"light": 0}}}]);
    doc["scenes"] = json!([{"nodes": [0, 1]}]);
    let s = load_gltf(&write("light", &doc), &SceneOptions::default()).unwrap();
    let l = s.lights[0];
    assert_eq!(
        l.kind,
        LightKind::Spot {
            inner_cone: 0.2,
            outer_cone: 0.5
        }
    );
    assert!((l.position - Vec3::new(1.0, 3.0, 0.0)).length() < 1e-6);
    assert!(
        (l.direction - Vec3::NEG_Y).length() < 1e-6,
        "{}",
        l.direction
    );
    assert_eq!(l.color, Vec3::new(4.0, 2.0, 1.0));
    assert_eq!(l.range, Some(9.0));
    assert!(l.casts_shadows);
}

fn with_relief_material(extras: Value) -> Value {
    let mut png = Vec::new();
    image::DynamicImage::ImageLuma8(image::GrayImage::from_pixel(2, 2, image::Luma([128])))
        .write_to(&mut std::io::Cursor::new(&mut png), image::ImageFormat::Png)
        .unwrap();
    let mut doc = plain_triangle();
    doc["images"] = json!([{"uri": format!("data:image/png;base64,{}", base64(&png))}]);
    doc["samplers"] = json!([{"magFilter": 9728, "minFilter": 9729, "wrapS": 33071}]);
    doc["textures"] = json!([{"source": 0, "sampler": 0}]);
    doc["materials"] = json!([{"name": "Bricks", "extras": extras}]);
    let prim = &mut doc["meshes"][0]["primitives"][0];
    prim["material"] = json!(0);
    prim["attributes"] = json!({"POSITION": 0, "TEXCOORD_0": 2, "TEXCOORD_1": 2});
    doc
}

#[test]
fn relief_from_extras() {
    let doc = with_relief_material(
        json!({"relief": {"depth_scale": 0.05, "method": "qdm", "budget": 64,
        "height": {"index": 0, "texCoord": 1, "channel": "a", "invert": true}}}),
    );
    let s = load_gltf(&write("relief", &doc), &SceneOptions::default()).unwrap();
    assert_eq!(s.images.len(), 1);
    assert_eq!(s.images[0].pixels.width(), 2);
    let r = s.materials[0].relief.unwrap();
    assert_eq!(
        (r.depth_scale, r.method.to_string(), r.budget),
        (0.05, "qdm".to_owned(), Some(64))
    );
    let HeightSource::Texture {
        texture,
        channel,
        invert,
    } = r.height
    else {
        panic!("{:?}", r.height)
    };
    assert_eq!(
        (texture.image, texture.tex_coord, channel, invert),
        (0, 1, Channel::A, true)
    );
    assert_eq!(texture.sampler.mag, relief::scene::Filter::Nearest);
    assert_eq!(texture.sampler.mipmaps, None);
    assert_eq!(texture.sampler.wrap_u, relief::scene::Wrap::ClampToEdge);
}

#[test]
fn relief_errors_name_file_material_and_field() {
    let doc = with_relief_material(json!({"relief": {"depth_scale": 0.05, "method": "foo"}}));
    let err = load_err("relief-bad", &doc, SceneOptions::default());
    assert!(
        err.contains(
            ": material \"Bricks\": extras.relief.method: unknown method \"foo\"; known methods: "
        ),
        "{err}"
    );
    let doc =
        with_relief_material(json!({"relief": {"depth_scale": 0.05, "height": {"index": 7}}}));
    let err = load_err("relief-bad", &doc, SceneOptions::default());
    assert!(err.contains("material \"Bricks\": extras.relief.height.index: texture 7 does not exist (the file has 1)"), "{err}");
    // A height map read through uv set 1 on a primitive that has no uvs.
    let mut doc = with_relief_material(
        json!({"relief": {"depth_scale": 0.05, "height": {"index": 0, "texCoord": 1}}}),
    );
    doc["meshes"][0]["primitives"][0]["attributes"] = json!({"POSITION": 0});
    let err = load_err("relief-no-uv", &doc, SceneOptions::default());
    assert!(
        err.contains("reads TEXCOORD_1 for relief height but the primitive has 0 uv sets"),
        "{err}"
    );
}

#[test]
fn broken_input_is_rejected_with_the_mesh_named() {
    let doc = triangle_doc(
        [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [0, 1, 3],
    );
    let err = load_err("oob", &doc, SceneOptions::default());
    assert!(
        err.contains(
            "mesh \"Tri\": primitive 0: indices accessor 1: index 3 is out of range for 3 vertices"
        ),
        "{err}"
    );

    let mut doc = triangle_doc(
        [[0.0, 0.0, 0.0], [f32::NAN, 0.0, 0.0], [0.0, 1.0, 0.0]],
        [0, 1, 2],
    );
    doc["accessors"][0]["min"] = json!([0.0, 0.0, 0.0]);
    doc["accessors"][0]["max"] = json!([1.0, 1.0, 0.0]);
    let err = load_err("nan", &doc, SceneOptions::default());
    assert!(
        err.contains(
            "mesh \"Tri\": primitive 0: POSITION accessor 0: holds NaN or infinite floats"
        ),
        "{err}"
    );

    let mut doc = plain_triangle();
    doc["accessors"][0]["count"] = json!(4);
    let err = load_err("overrun", &doc, SceneOptions::default());
    assert!(err.contains("overrun bufferView 0"), "{err}");

    let mut doc = plain_triangle();
    doc["nodes"] = json!([{"children": [1], "mesh": 0}, {"children": [0]}]);
    let err = load_err("cycle", &doc, SceneOptions::default());
    assert!(
        err.contains("is its own ancestor") || err.contains("child of both"),
        "{err}"
    );
}

#[test]
fn non_triangle_primitives_are_skipped_and_counted() {
    let mut doc = plain_triangle();
    doc["meshes"][0]["primitives"][0]["mode"] = json!(1);
    let (s, report) =
        load_gltf_with_report(&write("lines", &doc), &SceneOptions::default()).unwrap();
    assert!(s.meshes.is_empty());
    assert_eq!(report.skipped_primitives, 1);
}

#[test]
fn deep_node_chains_load_and_self_loops_fail() {
    let n = 50_000;
    let mut doc = plain_triangle();
    let mut nodes: Vec<Value> = (1..n)
        .map(|i| json!({"children": [i], "translation": [0.0, 0.0, 1.0]}))
        .collect();
    nodes.push(json!({"mesh": 0}));
    doc["nodes"] = Value::Array(nodes);
    let s = load_gltf(&write("deep", &doc), &SceneOptions::default()).unwrap();
    let z = s.meshes[0].transform.w_axis.z;
    assert_eq!(z, (n - 1) as f32);

    let mut doc = plain_triangle();
    doc["nodes"] = json!([{"children": [0], "mesh": 0}]);
    let err = load_err("self-loop", &doc, SceneOptions::default());
    assert!(err.contains("node 0"), "{err}");
}
