//! Real glTF scenes from the shared corpus, rendered: every scene renders without error or
//! validation message; .gltf and .glb agree; texture transforms read "Correct"; mirrored tangents
//! light both halves alike; planes take relief from the command line; empty scenes render the
//! background.

mod common;

use std::path::Path;

use glam::Vec3;
use relief::heightfield::Generator;
use relief::method::Method;
use relief::render::{render, Frame, RenderOptions};
use relief::scene::{load_gltf, Camera, Light, Scene, SceneOptions};
use relief::vk::Context;

fn options(width: u32, height: u32) -> RenderOptions {
    RenderOptions {
        width,
        height,
        ..RenderOptions::default()
    }
}

fn load(path: &Path) -> Scene {
    load_gltf(path, &SceneOptions::default())
        .unwrap_or_else(|e| panic!("{} does not load: {e}", path.display()))
}

fn draw(ctx: &std::sync::Arc<Context>, scene: &Scene, w: u32, h: u32) -> Frame {
    render(ctx, scene, None, &options(w, h)).unwrap_or_else(|e| panic!("render failed: {e}"))
}

#[test]
fn every_corpus_scene_renders() {
    let Some(corpus) = common::corpus::corpus("every_corpus_scene_renders") else {
        return;
    };
    let Some(ctx) = common::device("every_corpus_scene_renders") else {
        return;
    };
    let files = common::corpus::gltf_files(&corpus.join("gltf"));
    assert!(
        files.len() >= 20,
        "expected the corpus scenes, found {}",
        files.len()
    );
    for path in &files {
        let scene = load(path);
        let frame = draw(&ctx, &scene, 64, 48);
        eprintln!(
            "{}: {} meshes, {} materials, {} images, {} pipelines",
            path.strip_prefix(&corpus).unwrap_or(path).display(),
            scene.meshes.len(),
            scene.materials.len(),
            scene.images.len(),
            frame.plan.pipelines.len()
        );
        assert_eq!(frame.rgba.len(), 64 * 48 * 4);
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn box_textured_gltf_and_glb_render_the_same() {
    let Some(corpus) = common::corpus::corpus("box_textured_gltf_and_glb_render_the_same") else {
        return;
    };
    let Some(ctx) = common::device("box_textured_gltf_and_glb_render_the_same") else {
        return;
    };
    let dir = corpus.join("gltf/BoxTextured");
    let a = draw(&ctx, &load(&dir.join("BoxTextured.gltf")), 96, 72);
    let b = draw(&ctx, &load(&dir.join("BoxTextured.glb")), 96, 72);
    assert_eq!(a.rgba, b.rgba, ".gltf and .glb differ");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn flight_helmet_draws_six_textured_materials() {
    let Some(corpus) = common::corpus::corpus("flight_helmet_draws_six_textured_materials") else {
        return;
    };
    let Some(ctx) = common::device("flight_helmet_draws_six_textured_materials") else {
        return;
    };
    let scene = load(&corpus.join("gltf/FlightHelmet/FlightHelmet.gltf"));
    let textured = scene
        .materials
        .iter()
        .filter(|m| m.normal_texture.is_some() && m.occlusion_texture.is_some())
        .count();
    assert_eq!(textured, 6);
    let frame = draw(&ctx, &scene, 96, 96);
    // The helmet fills the middle of the frame: most centre pixels are not the background.
    let centre: Vec<&[u8]> = frame
        .rgba
        .chunks_exact(4)
        .enumerate()
        .filter(|(i, _)| {
            let (x, y) = (i % 96, i / 96);
            (32..64).contains(&x) && (24..72).contains(&y)
        })
        .map(|(_, p)| p)
        .collect();
    let background = centre.iter().filter(|p| p[..3] == frame.rgba[..3]).count();
    assert!(background * 2 < centre.len(), "the helmet is missing");
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn planes_take_relief_from_the_command_line() {
    let Some(corpus) = common::corpus::corpus("planes_take_relief_from_the_command_line") else {
        return;
    };
    let Some(ctx) = common::device("planes_take_relief_from_the_command_line") else {
        return;
    };
    let hf = Generator::Bricks.generate(128, 128, 2);
    for name in ["plane.gltf", "displacement_plane.gltf"] {
        let path = corpus.join("gltf/sascha").join(name);
        let flat = load(&path);
        let mut displaced = flat.clone();
        let qdm: Method = "qdm".parse().expect("qdm");
        assert!(displaced.apply_relief(0.08, qdm, None) > 0);
        let a = draw(&ctx, &flat, 96, 72);
        let b = render(&ctx, &displaced, Some(&hf), &options(96, 72)).expect("renders");
        let changed = a
            .rgba
            .chunks_exact(4)
            .zip(b.rgba.chunks_exact(4))
            .filter(|(p, q)| p.iter().zip(q.iter()).any(|(x, y)| x.abs_diff(*y) > 8))
            .count();
        let background = &a.rgba[..4];
        let covered = a.rgba.chunks_exact(4).filter(|p| p != &background).count();
        assert!(covered > 200, "{name}: the plane is in view");
        assert!(
            changed * 4 > covered,
            "{name}: relief changed only {changed} of the plane's {covered} pixels"
        );
    }
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn empty_scenes_render_the_background() {
    let Some(corpus) = common::corpus::corpus("empty_scenes_render_the_background") else {
        return;
    };
    let Some(ctx) = common::device("empty_scenes_render_the_background") else {
        return;
    };
    for case in [
        "00_empty_scene",
        "00_no_nodes",
        "00_no_scene",
        "00_no_scenes",
    ] {
        let path = corpus
            .join("gltf/blender-io-roundtrip")
            .join(case)
            .join(format!("{case}.gltf"));
        let scene = load(&path);
        let frame = draw(&ctx, &scene, 16, 16);
        let first = &frame.rgba[..4];
        assert!(
            frame.rgba.chunks_exact(4).all(|p| p == first),
            "{case}: an empty scene is all background"
        );
    }
    common::assert_no_validation_errors(&ctx);
}

/// A camera straight in front of the scene's bounds (looking down -z) and a light from it.
fn head_on(scene: &mut Scene) {
    let (lo, hi) = scene.bounds().expect("not empty");
    let centre = (lo + hi) * 0.5;
    let radius = (hi - lo).length() * 0.5;
    let eye = centre + Vec3::Z * radius * 2.6;
    scene.camera = Some(Camera::look_at(
        eye,
        centre,
        0.8,
        radius * 0.1,
        radius * 10.0,
    ));
    scene.lights = vec![Light {
        direction: Vec3::new(0.0, 0.0, -1.0),
        ..Light::default_light()
    }];
}

#[test]
fn mirrored_tangents_light_both_halves_alike() {
    let Some(corpus) = common::corpus::corpus("mirrored_tangents_light_both_halves_alike") else {
        return;
    };
    let Some(ctx) = common::device("mirrored_tangents_light_both_halves_alike") else {
        return;
    };
    for name in ["NormalTangentMirrorTest", "NormalTangentTest"] {
        let mut scene = load(&corpus.join(format!("gltf/{name}/{name}.glb")));
        head_on(&mut scene);
        let (w, h) = (128usize, 128usize);
        let frame = draw(&ctx, &scene, w as u32, h as u32);
        // Compare each pixel of the left half with its mirror image in the right half: the
        // test models are symmetric, and so is their lighting when tangents are right.
        let mut total = 0u64;
        let mut count = 0u64;
        for y in 0..h {
            for x in 0..w / 2 {
                let a = &frame.rgba[(y * w + x) * 4..][..3];
                let b = &frame.rgba[(y * w + (w - 1 - x)) * 4..][..3];
                total += a
                    .iter()
                    .zip(b)
                    .map(|(p, q)| u64::from(p.abs_diff(*q)))
                    .sum::<u64>();
                count += 3;
            }
        }
        let mean = total as f64 / count as f64;
        eprintln!("{name}: mean mirrored difference {mean:.2}");
        assert!(mean < 6.0, "{name}: halves differ by {mean:.2} on average");
    }
    common::assert_no_validation_errors(&ctx);
}
