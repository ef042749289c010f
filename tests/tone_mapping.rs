//! Tone mapping (`RenderOptions::tone_mapping`, `--tonemap`, `--exposure`): the GPU pass applies
//! exactly the curves `ToneMap::apply` defines (checked pixel by pixel against the untouched
//! radiance of the same frame), and an extreme light (1e4) saturates to white, with no NaN and no
//! black holes.

mod common;

use std::sync::Arc;

use common::srgb;

use glam::{Mat4, Vec3};
use relief::render::{render, RenderOptions, ToneMap, ToneMapping};
use relief::scene::{box_mesh, quad_mesh, Camera, Light, Material, Scene};

const WIDTH: u32 = 128;
const HEIGHT: u32 = 80;

fn scene(light: f32) -> Scene {
    let mut cube = box_mesh("box", Vec3::splat(0.5), 0);
    cube.transform = Mat4::from_translation(Vec3::new(0.0, 0.6, 0.0)) * Mat4::from_rotation_y(0.6);
    let ground = quad_mesh("ground", 6.0, 6.0, 1.0, 1);
    let colour = |name: &str, rgb: [f32; 3], roughness: f32| Material {
        name: name.into(),
        base_color: [rgb[0], rgb[1], rgb[2], 1.0],
        roughness,
        ..Material::default()
    };
    Scene {
        meshes: vec![cube, ground],
        materials: vec![
            colour("box", [0.9, 0.5, 0.2], 0.3),
            colour("ground", [0.4, 0.45, 0.5], 0.8),
        ],
        lights: vec![Light {
            color: Vec3::splat(light),
            ..Light::default_light()
        }],
        camera: Some(Camera::look_at(
            Vec3::new(1.8, 1.9, 2.4),
            Vec3::new(0.0, 0.4, 0.0),
            0.8,
            0.1,
            30.0,
        )),
        ..Scene::default()
    }
}

fn draw(ctx: &Arc<relief::vk::Context>, scene: &Scene, tone_mapping: ToneMapping) -> Vec<u8> {
    let opts = RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT)
        .with_tone_mapping(tone_mapping);
    let frame = render(ctx, scene, None, &opts).expect("renders");
    common::assert_no_validation_errors(ctx);
    assert_eq!(frame.plan.tone_mapping, tone_mapping);
    frame.rgba
}

#[test]
fn the_pass_applies_the_curves_as_defined() {
    let Some(ctx) = common::device("the_pass_applies_the_curves_as_defined") else {
        return;
    };
    // Bright enough that highlights pass 1 (compressed by the curves); the reference frame is
    // drawn one stop down so that it clips nowhere.
    let scene = scene(6.0);
    let down = ToneMapping {
        curve: ToneMap::None,
        exposure_ev: -1.0,
    };
    let radiance = draw(&ctx, &scene, down);
    for curve in [ToneMap::PbrNeutral, ToneMap::Aces] {
        let mapping = ToneMapping {
            curve,
            exposure_ev: 0.0,
        };
        let mapped = draw(&ctx, &scene, mapping);
        let (mut checked, mut off, mut worst) = (0, 0, 0.0f32);
        let mut above_one = 0;
        for (r, m) in radiance.chunks_exact(4).zip(mapped.chunks_exact(4)) {
            if r[..3].iter().any(|&c| c >= 250) {
                continue;
            }
            let linear = [0, 1, 2].map(|c| 2.0 * srgb::decode(r[c]) as f32);
            above_one += usize::from(linear.iter().any(|&l| l > 1.0));
            let expected = curve
                .apply(linear)
                .map(|l| srgb::encode(f64::from(l)) as f32);
            let error = (0..3)
                .map(|c| (f32::from(m[c]) - expected[c]).abs())
                .fold(0.0, f32::max);
            checked += 1;
            worst = worst.max(error);
            off += usize::from(error > 3.0);
        }
        eprintln!(
            "{curve}: {checked} pixels ({above_one} above 1 before the curve), {off} more than 3 levels off, worst {worst:.1}"
        );
        assert!(above_one > 50, "{curve}: the frame tests no highlight");
        assert!(
            off * 200 <= checked,
            "{curve}: {off} of {checked} pixels off the curve"
        );
    }
}

#[test]
fn a_blinding_light_saturates_without_nan() {
    let Some(ctx) = common::device("a_blinding_light_saturates_without_nan") else {
        return;
    };
    let normal = draw(&ctx, &scene(3.0), ToneMapping::NONE);
    let mapping = ToneMapping {
        curve: ToneMap::PbrNeutral,
        exposure_ev: 0.0,
    };
    let blinding = draw(&ctx, &scene(1e4), mapping);
    let background = normal[..4].to_vec();
    let mut lit = 0;
    let mut white = 0;
    for (n, b) in normal.chunks_exact(4).zip(blinding.chunks_exact(4)) {
        if n == background.as_slice() || n[..3].iter().all(|&c| c < 8) {
            continue;
        }
        lit += 1;
        white += usize::from(b[..3].iter().all(|&c| c >= 250));
    }
    eprintln!("{white} of {lit} lit pixels saturate under a light of 1e4");
    assert!(lit > 1000, "only {lit} lit pixels");
    assert!(white * 10 >= lit * 9, "{white} of {lit} lit pixels white");
}

#[test]
fn a_non_finite_exposure_is_refused() {
    let Some(ctx) = common::device("a_non_finite_exposure_is_refused") else {
        return;
    };
    let opts = RenderOptions::default()
        .with_width(8)
        .with_height(8)
        .with_tone_mapping(ToneMapping {
            curve: ToneMap::PbrNeutral,
            exposure_ev: f32::NAN,
        });
    let Err(err) = render(&ctx, &scene(3.0), None, &opts) else {
        panic!("a NaN exposure renders");
    };
    let err = err.to_string();
    assert!(err.contains("--exposure"), "{err}");
}
