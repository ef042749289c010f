//! Real glTF scenes from the shared corpus, rendered: every scene renders without error or
//! validation message; .gltf and .glb agree; texture transforms read "Correct"; mirrored tangents
//! light both halves alike; planes take relief from the command line; empty scenes render the
//! background; FlightHelmet as `relief render` draws it, under the built-in sky and under a studio
//! environment the test makes, matches golden images.

mod common;

use std::path::Path;

use glam::{Mat4, Vec3};
use relief::environment::{Environment, EnvironmentSource};
use relief::heightfield::Generator;
use relief::method::Method;
use relief::render::{render, Frame, RenderOptions};
use relief::scene::{load_gltf, Camera, Light, Projection, Scene, SceneOptions};
use relief::vk::Context;

fn options(width: u32, height: u32) -> RenderOptions {
    RenderOptions::default()
        .with_width(width)
        .with_height(height)
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
    let glb = load(&dir.join("BoxTextured.glb"));
    let mut gltf = load(&dir.join("BoxTextured.gltf"));
    // Assimp's .gltf copy names other sampler wrap modes (mirrored repeat, clamp) than the .glb
    // (repeat); with the .glb's sampler the two files must draw the same image.
    let sampler = glb.materials[0]
        .base_color_texture
        .expect("texture")
        .sampler;
    for m in &mut gltf.materials {
        if let Some(t) = &mut m.base_color_texture {
            t.sampler = sampler;
        }
    }
    let a = draw(&ctx, &gltf, 96, 72);
    let b = draw(&ctx, &glb, 96, 72);
    assert!(a.rgba == b.rgba, ".gltf and .glb draw different images");
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

/// A studio made by the test: a warm key light up front, a cool fill from the side, a grey
/// floor, in a dim room.
fn studio() -> Environment {
    let key = glam::Vec3::new(0.5, 0.6, 0.62).normalize();
    let fill = glam::Vec3::new(-0.9, 0.2, -0.1).normalize();
    Environment::from_fn("studio", 128, 64, |d| {
        let mut l = glam::Vec3::splat(if d.y < 0.0 { 0.12 } else { 0.05 });
        if d.dot(key) > 0.97 {
            l += glam::Vec3::new(40.0, 34.0, 26.0);
        }
        if d.dot(fill) > 0.9 {
            l += glam::Vec3::new(1.5, 2.0, 3.0);
        }
        l
    })
}

#[test]
fn flight_helmet_under_the_sky_and_a_studio_matches_golden_images() {
    let Some(corpus) = common::corpus::corpus("flight_helmet_golden") else {
        return;
    };
    let Some(ctx) = common::device("flight_helmet_golden") else {
        return;
    };
    let scene = load(&corpus.join("gltf/FlightHelmet/FlightHelmet.gltf"));
    for (name, environment) in [
        ("flight_helmet_sky_128", EnvironmentSource::Sky),
        (
            "flight_helmet_studio_128",
            EnvironmentSource::Image(studio()),
        ),
    ] {
        let opts = RenderOptions::finished(128, 128).with_environment(environment);
        let frame = render(&ctx, &scene, None, &opts).expect("renders");
        common::assert_no_validation_errors(&ctx);
        common::golden::check_golden(name, 128, 128, &frame.rgba);
    }
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
    // 00_no_scene has no default scene but lists one, which the loader draws (scene 0).
    for case in ["00_empty_scene", "00_no_nodes", "00_no_scenes"] {
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

/// NormalTangentMirrorTest seen head-on through an orthographic camera, lit from the upper right:
/// 320x400 pixels over x in [-1.5, 0.1], y in [-1, 1] (the front block of tiles).
fn mirror_test_frame(ctx: &std::sync::Arc<Context>, scene: &Scene) -> Vec<u8> {
    let mut scene = scene.clone();
    scene.camera = Some(Camera {
        view: Mat4::look_at_rh(
            Vec3::new(-0.7, 0.0, 5.0),
            Vec3::new(-0.7, 0.0, 0.0),
            Vec3::Y,
        ),
        projection: Projection::Orthographic {
            xmag: 0.8,
            ymag: 1.0,
            znear: 0.1,
            zfar: 10.0,
        },
    });
    scene.lights = vec![Light {
        direction: Vec3::new(-1.0, -0.5, -1.0).normalize(),
        ..Light::default_light()
    }];
    render(ctx, &scene, None, &options(320, 400))
        .expect("renders")
        .rgba
}

/// Mean channel difference between the 40x40 tile around `a` and the one around `b` (pixel
/// centres), at the best alignment within 4 pixels.
fn tile_difference(rgba: &[u8], a: (i32, i32), b: (i32, i32)) -> f64 {
    let px = |x: i32, y: i32, c: usize| f64::from(rgba[(y as usize * 320 + x as usize) * 4 + c]);
    let mut best = f64::MAX;
    for dy in -4..=4 {
        for dx in -4..=4 {
            let mut total = 0.0;
            for y in -20..20 {
                for x in -20..20 {
                    for c in 0..3 {
                        total +=
                            (px(a.0 + x, a.1 + y, c) - px(b.0 + x + dx, b.1 + y + dy, c)).abs();
                    }
                }
            }
            best = best.min(total / (40.0 * 40.0 * 3.0));
        }
    }
    best
}

/// The worst difference between a normal-mapped tile (columns "Normal", "V Mirror", "U Mirror")
/// and the geometric bump in the same row (column "Geometry").
fn worst_mirror_difference(rgba: &[u8]) -> f64 {
    const COLUMNS: [i32; 4] = [45, 110, 175, 242];
    const ROWS: [i32; 5] = [40, 120, 200, 280, 360];
    let mut worst: f64 = 0.0;
    for &y in &ROWS {
        for &x in &COLUMNS[1..] {
            worst = worst.max(tile_difference(rgba, (COLUMNS[0], y), (x, y)));
        }
    }
    worst
}

#[test]
fn mirrored_tangents_light_like_the_geometry() {
    let Some(corpus) = common::corpus::corpus("mirrored_tangents_light_like_the_geometry") else {
        return;
    };
    let Some(ctx) = common::device("mirrored_tangents_light_like_the_geometry") else {
        return;
    };
    let scene = load(&corpus.join("gltf/NormalTangentMirrorTest/NormalTangentMirrorTest.glb"));
    let worst = worst_mirror_difference(&mirror_test_frame(&ctx, &scene));
    eprintln!("worst normal-mapped tile against the geometry: {worst:.2}");
    // The control: the same model with every bitangent sign flipped lights the mirrored
    // columns from the wrong side, so the comparison can tell right from wrong.
    let mut flipped = scene.clone();
    for mesh in &mut flipped.meshes {
        for v in &mut mesh.vertices {
            v.tangent[3] = -v.tangent[3];
        }
    }
    let wrong = worst_mirror_difference(&mirror_test_frame(&ctx, &flipped));
    eprintln!("with flipped bitangents: {wrong:.2}");
    assert!(
        worst < 4.0,
        "a normal-mapped tile differs from the geometry by {worst:.2}"
    );
    assert!(
        wrong > 2.0 * worst,
        "the control does not fail: {wrong:.2} vs {worst:.2}"
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn malformed_files_that_load_render_without_validation_errors() {
    let Some(corpus) = common::corpus::corpus("malformed_files_that_load_render") else {
        return;
    };
    let Some(ctx) = common::device("malformed_files_that_load_render") else {
        return;
    };
    let files = common::corpus::gltf_files(&corpus.join("bad-input"));
    let (mut rendered, mut rejected) = (0, 0);
    for path in &files {
        // The loader's own walk (gltf_corpus_load.rs) proves no file panics it.
        let Ok(scene) = load_gltf(path, &SceneOptions::default()) else {
            rejected += 1;
            continue;
        };
        let frame = render(&ctx, &scene, None, &options(24, 16));
        if let Err(e) = &frame {
            panic!("{} loads but does not render: {e}", path.display());
        }
        assert_eq!(
            ctx.messages().errors(),
            0,
            "{}: validation errors:\n{}",
            path.display(),
            ctx.messages().kept_messages().join("\n")
        );
        rendered += 1;
    }
    eprintln!(
        "bad-input: {} files, {rendered} load and render, {rejected} rejected by the loader",
        files.len()
    );
    assert_eq!(rendered + rejected, files.len());
}

/// An orthographic camera looking down -z at the whole scene, and a light from the camera.
fn orthographic_front(scene: &mut Scene, aspect: f32) {
    let (lo, hi) = scene.bounds().expect("not empty");
    let centre = (lo + hi) * 0.5;
    let half = (hi - lo) * 0.5 * 1.05;
    let (xmag, ymag) = (half.x.max(half.y * aspect), half.y.max(half.x / aspect));
    scene.camera = Some(Camera {
        view: Mat4::look_at_rh(centre + Vec3::Z * (half.z + 1.0), centre, Vec3::Y),
        projection: Projection::Orthographic {
            xmag,
            ymag,
            znear: 0.01,
            zfar: 2.0 * half.z + 2.0,
        },
    });
    scene.lights = vec![Light {
        direction: Vec3::NEG_Z,
        ..Light::default_light()
    }];
}

/// Pixels (x, y) of `rgba` (width `w`) whose colour `pick` accepts.
fn pixels_where(rgba: &[u8], w: usize, pick: impl Fn(&[u8]) -> bool) -> Vec<(i32, i32)> {
    rgba.chunks_exact(4)
        .enumerate()
        .filter(|(_, p)| pick(p))
        .map(|(i, _)| ((i % w) as i32, (i / w) as i32))
        .collect()
}

#[test]
fn texture_transform_test_reads_correct() {
    let Some(corpus) = common::corpus::corpus("texture_transform_test_reads_correct") else {
        return;
    };
    let Some(ctx) = common::device("texture_transform_test_reads_correct") else {
        return;
    };
    let mut scene = load(&corpus.join("gltf/TextureTransformTest/TextureTransformTest.gltf"));
    let (w, h) = (480usize, 320usize);
    orthographic_front(&mut scene, w as f32 / h as f32);
    let rgba = draw(&ctx, &scene, w as u32, h as u32).rgba;
    let evidence = common::evidence_dir("corpus").join("texture_transform_test.png");
    image::save_buffer(
        &evidence,
        &rgba,
        w as u32,
        h as u32,
        image::ColorType::Rgba8,
    )
    .expect("writes evidence");
    // Top row: uv offsets show the green "U", blue "V" and cyan "UV" quarters of UV.png; the
    // olive "not supported" quarter must not appear.
    let olive: Vec<_> = pixels_where(&rgba, w, |p| p[0] > 120 && p[1] > 120 && p[2] < 60)
        .into_iter()
        .filter(|&(_, y)| y < h as i32 / 2)
        .collect();
    let count = |pick: fn(&[u8]) -> bool| pixels_where(&rgba, w, pick).len();
    let green = count(|p| p[1] > 110 && p[0] < 60 && p[2] < 60);
    let blue = count(|p| p[2] > 110 && p[0] < 40 && p[1] < 40);
    let cyan = count(|p| p[1] > 100 && p[2] > 100 && p[0] < 60);
    assert!(
        olive.len() < 20,
        "{} olive 'not supported' pixels",
        olive.len()
    );
    let square = w * h / 40;
    assert!(
        green > square && blue > square && cyan > square,
        "{green} {blue} {cyan}"
    );
    // Bottom row: every arrow (rotation, scale, all three) ends at a green "correct" marker, none
    // at a red "error" marker: the arrow's dark pixels reach into the marker's box. (Olive
    // markers there show where an arrow would point without the extension.)
    let lower = |pick: fn(&[u8]) -> bool| -> Vec<(i32, i32)> {
        pixels_where(&rgba, w, pick)
            .into_iter()
            .filter(|&(_, y)| y > h as i32 / 2)
            .collect()
    };
    let dark = lower(|p| p[0] < 40 && p[1] < 40 && p[2] < 40);
    // Distance in pixels from a marker to the nearest arrow pixel.
    let gap = |marker: &[(i32, i32)]| {
        marker
            .iter()
            .flat_map(|&(mx, my)| {
                dark.iter()
                    .map(move |&(x, y)| (x - mx).abs().max((y - my).abs()))
            })
            .min()
            .unwrap_or(i32::MAX)
    };
    let third = w as i32 / 3;
    let correct = split_columns(&lower(|p| p[1] > 110 && p[0] < 60 && p[2] < 60), third);
    let unsupported = split_columns(&lower(|p| p[0] > 120 && p[1] > 120 && p[2] < 60), third);
    let error = lower(|p| p[0] > 150 && p[1] < 60 && p[2] < 60);
    assert_eq!(correct.len(), 3, "one correct marker per arrow square");
    assert!(!error.is_empty(), "the error marker is drawn");
    for (k, marker) in correct.iter().enumerate() {
        let ok = gap(marker);
        assert!(ok <= 16, "arrow {k} ends {ok} px from its correct marker");
        assert!(gap(&error) > ok, "arrow {k} is nearer the error marker");
        if let Some(other) = unsupported.get(k) {
            assert!(
                gap(other) > ok,
                "arrow {k} is nearer the 'not supported' marker"
            );
        }
    }
    common::assert_no_validation_errors(&ctx);
}

/// Groups points by the third of the image they fall in, dropping empty thirds.
fn split_columns(points: &[(i32, i32)], third: i32) -> Vec<Vec<(i32, i32)>> {
    (0..3)
        .map(|k| {
            points
                .iter()
                .copied()
                .filter(|&(x, _)| x / third == k)
                .collect::<Vec<_>>()
        })
        .filter(|g| !g.is_empty())
        .collect()
}
