//! Loads the external corpus (../shared/corpus, see its README): real scenes must load with the
//! expected content, and malformed files must load or fail cleanly, never panic.

mod common;

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};

use relief::scene::{load_gltf, Filter, Scene, SceneOptions, TextureSlot, Wrap};

/// A folder of the corpus, or `None` after printing SKIPPED.
fn corpus(sub: &str) -> Option<PathBuf> {
    common::corpus::corpus(sub).map(|root| root.join(sub))
}

fn gltf_files(dir: &Path) -> Vec<PathBuf> {
    common::corpus::gltf_files(dir)
}

fn load(path: &Path) -> Scene {
    load_gltf(path, &SceneOptions::default()).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn good_scenes_load() {
    let Some(dir) = corpus("gltf") else { return };
    for path in gltf_files(&dir) {
        let s = load(&path);
        println!(
            "{}: {} meshes, {} materials, {} images, {} lights, camera {}",
            path.strip_prefix(&dir).unwrap().display(),
            s.meshes.len(),
            s.materials.len(),
            s.images.len(),
            s.lights.len(),
            s.camera.is_some()
        );
        for m in &s.meshes {
            assert!(m.indices.iter().all(|&i| (i as usize) < m.vertices.len()));
            for v in &m.vertices {
                let t = glam::Vec4::from(v.tangent);
                assert!(
                    t.is_finite() && (t.truncate().length() - 1.0).abs() < 1e-3 && t.w.abs() == 1.0,
                    "{}: {:?}",
                    path.display(),
                    v.tangent
                );
            }
        }
    }
}

#[test]
fn box_textured_gltf_and_glb_agree() {
    let Some(dir) = corpus("gltf/BoxTextured") else {
        return;
    };
    let a = load(&dir.join("BoxTextured.gltf"));
    let b = load(&dir.join("BoxTextured.glb"));
    // The two upstream copies differ only in the sampler's wrap modes (the .gltf was edited to
    // exercise them), which also checks sampler conversion.
    let (mut ma, mb) = (a.materials.clone(), b.materials.clone());
    let (sa, sb) = (
        ma[0].base_color_texture.unwrap().sampler,
        mb[0].base_color_texture.unwrap().sampler,
    );
    assert_eq!(
        (sa.wrap_u, sa.wrap_v),
        (Wrap::MirroredRepeat, Wrap::ClampToEdge)
    );
    assert_eq!((sb.wrap_u, sb.wrap_v), (Wrap::Repeat, Wrap::Repeat));
    assert_eq!(
        (sa.mag, sa.min, sa.mipmaps),
        (Filter::Linear, Filter::Nearest, Some(Filter::Linear))
    );
    ma[0].base_color_texture.as_mut().unwrap().sampler = sb;
    assert_eq!(ma, mb);
    assert_eq!(a.meshes.len(), b.meshes.len());
    for (x, y) in a.meshes.iter().zip(&b.meshes) {
        assert_eq!(
            (&x.vertices, &x.indices, x.material, x.transform),
            (&y.vertices, &y.indices, y.material, y.transform)
        );
    }
    assert_eq!(a.images.len(), 1);
    assert_eq!(a.images[0].pixels.as_bytes(), b.images[0].pixels.as_bytes());
    assert!(a.materials[0].base_color_texture.is_some());
}

#[test]
fn flight_helmet_materials() {
    let Some(dir) = corpus("gltf/FlightHelmet") else {
        return;
    };
    let s = load(&dir.join("FlightHelmet.gltf"));
    assert_eq!(s.materials.len(), 6);
    for m in &s.materials {
        assert!(
            m.normal_texture.is_some() && m.occlusion_texture.is_some(),
            "{}",
            m.name
        );
        for slot in TextureSlot::ALL {
            if let Some(t) = m.texture(slot) {
                assert!(t.image < s.images.len());
            }
        }
    }
}

fn all_tangents(s: &Scene) -> impl Iterator<Item = [f32; 4]> + '_ {
    s.meshes
        .iter()
        .flat_map(|m| m.vertices.iter().map(|v| v.tangent))
}

#[test]
fn normal_tangent_test_generates_tangents() {
    let Some(dir) = corpus("gltf/NormalTangentTest") else {
        return;
    };
    let s = load(&dir.join("NormalTangentTest.glb"));
    assert!(!s.meshes.is_empty());
    for t in all_tangents(&s) {
        let v = glam::Vec4::from(t);
        assert!(
            v.is_finite() && (v.truncate().length() - 1.0).abs() < 1e-4 && v.w.abs() == 1.0,
            "{t:?}"
        );
    }
}

#[test]
fn normal_tangent_mirror_keeps_negative_w() {
    let Some(dir) = corpus("gltf/NormalTangentMirrorTest") else {
        return;
    };
    let s = load(&dir.join("NormalTangentMirrorTest.glb"));
    let (neg, pos) =
        all_tangents(&s).fold(
            (0, 0),
            |(n, p), t| if t[3] < 0.0 { (n + 1, p) } else { (n, p + 1) },
        );
    println!("mirror test: {neg} tangents with w = -1, {pos} with w = +1");
    assert!(neg > 0 && pos > 0);
}

#[test]
fn texture_transform_test() {
    let Some(dir) = corpus("gltf/TextureTransformTest") else {
        return;
    };
    let s = load(&dir.join("TextureTransformTest.gltf"));
    let transforms: Vec<_> = s
        .materials
        .iter()
        .filter_map(|m| m.base_color_texture)
        .map(|t| t.transform)
        .collect();
    assert!(transforms.iter().any(|t| t.rotation != 0.0));
    assert!(transforms.iter().any(|t| t.offset != [0.0; 2]));
    assert!(transforms.iter().any(|t| t.scale != [1.0; 2]));
}

#[test]
fn blender_orm_two_uvmaps_and_empty_scenes() {
    let Some(dir) = corpus("gltf/blender-io-roundtrip") else {
        return;
    };
    let s = load(&dir.join("12_orm_two_uvmaps/12_orm_two_uvmaps.gltf"));
    let occ: Vec<_> = s
        .materials
        .iter()
        .filter_map(|m| m.occlusion_texture)
        .collect();
    assert!(
        !occ.is_empty() && occ.iter().all(|t| t.tex_coord == 1),
        "{occ:?}"
    );
    // No default scene but a scene list: scene 0 is used, which holds the one mesh.
    let s = load(&dir.join("00_no_scene/00_no_scene.gltf"));
    assert_eq!(s.meshes.len(), 1);
    for name in ["00_empty_scene", "00_no_nodes", "00_no_scenes"] {
        let s = load(&dir.join(format!("{name}/{name}.gltf")));
        assert!(
            s.meshes.is_empty() && s.camera.is_none() && s.lights.is_empty(),
            "{name}"
        );
    }
}

/// The validator's verdict on a file: whether its report lists errors (`None`: no report).
fn validator_errors(path: &Path) -> Option<Vec<String>> {
    let report = std::fs::read_to_string(format!("{}.report.json", path.display())).ok()?;
    let report: serde_json::Value = serde_json::from_str(&report).ok()?;
    let messages = report["issues"]["messages"].as_array()?;
    Some(
        messages
            .iter()
            .filter(|m| m["severity"] == 0)
            .map(|m| m["code"].as_str().unwrap_or("?").to_owned())
            .collect(),
    )
}

#[test]
fn bad_input_never_panics() {
    let Some(dir) = corpus("bad-input") else {
        return;
    };
    let (mut loaded, mut rejected, mut panicked) = (0, 0, Vec::new());
    let (mut loaded_with_errors, mut rejected_valid) = (Vec::new(), Vec::new());
    for path in gltf_files(&dir) {
        let name = path.strip_prefix(&dir).unwrap().display().to_string();
        let errors = validator_errors(&path);
        let result = catch_unwind(AssertUnwindSafe(|| {
            load_gltf(&path, &SceneOptions::default())
        }));
        match result {
            Err(_) => panicked.push(name),
            Ok(Ok(_)) => {
                loaded += 1;
                if let Some(e) = errors.filter(|e| !e.is_empty()) {
                    loaded_with_errors.push(format!("{name}: {}", e.join(", ")));
                }
            }
            Ok(Err(e)) => {
                rejected += 1;
                println!("rejected {name}: {e}");
                if errors.is_some_and(|e| e.is_empty()) {
                    rejected_valid.push(format!("{name}: {e}"));
                }
            }
        }
    }
    println!(
        "\nloaded {loaded}, rejected {rejected}, panicked {}",
        panicked.len()
    );
    println!(
        "loaded despite validator errors ({}):",
        loaded_with_errors.len()
    );
    for l in &loaded_with_errors {
        println!("  {l}");
    }
    println!(
        "rejected though the validator found no errors ({}):",
        rejected_valid.len()
    );
    for r in &rejected_valid {
        println!("  {r}");
    }
    assert!(panicked.is_empty(), "panicked on: {panicked:#?}");
    // Every file the validator finds errors in must be rejected, animations and skins included.
    assert!(
        loaded_with_errors.is_empty(),
        "loaded despite validator errors: {loaded_with_errors:#?}"
    );
}
