//! Image-based light (`RenderOptions::environment`, `--environment`): the GPU's irradiance map,
//! prefiltered specular levels and BRDF table against brute-force integration of the same image
//! on the CPU (`environment::reference`), a white furnace (white spheres in a uniform white
//! environment render to its radiance within 1%), and no NaN with a 1e4 sun or a black void.

mod common;

use std::sync::Arc;

use glam::{Mat4, Vec3};
use relief::environment::{reference, Environment, EnvironmentSource};
use relief::render::{render, EnvironmentLight, RenderOptions};
use relief::scene::{box_mesh, quad_mesh, sphere_mesh, Camera, Light, Material, Scene};
use relief::vk::Context;

/// A sky with a gradient, a coloured band and a bright disc: enough structure that a wrong
/// weight, axis or level shows.
fn structured(width: u32, height: u32, sun: f32) -> Environment {
    let sun_dir = Vec3::new(0.4, 0.6, -0.7).normalize();
    Environment::from_fn("structured", width, height, |d| {
        let mut l = Vec3::new(0.2, 0.3, 0.5) * (d.y + 1.2);
        if d.x > 0.3 && d.y.abs() < 0.4 {
            l += Vec3::new(1.5, 0.4, 0.1);
        }
        if d.dot(sun_dir) > 0.95 {
            l += Vec3::splat(sun);
        }
        l
    })
}

fn direction_of(size: [u32; 2], i: usize) -> Vec3 {
    let (x, y) = (i as u32 % size[0], i as u32 / size[0]);
    relief::environment::direction(
        (x as f32 + 0.5) / size[0] as f32,
        (y as f32 + 0.5) / size[1] as f32,
    )
}

/// Mean and largest error of `gpu` against `cpu` over a map's texels, relative to the CPU's
/// luminance.
fn relative_errors(texels: &[[f32; 4]], size: [u32; 2], cpu: impl Fn(Vec3) -> Vec3) -> (f64, f64) {
    let (mut sum, mut worst) = (0.0f64, 0.0f64);
    for (i, t) in texels.iter().enumerate() {
        let want = cpu(direction_of(size, i));
        let got = Vec3::new(t[0], t[1], t[2]);
        assert!(got.is_finite(), "texel {i} is {got}");
        let e = f64::from((got - want).abs().max_element() / want.max_element().max(1e-3));
        sum += e;
        worst = worst.max(e);
    }
    (sum / texels.len() as f64, worst)
}

#[test]
fn maps_match_brute_force_integration_of_the_same_image() {
    let Some(ctx) = common::device("environment maps") else {
        return;
    };
    let env = structured(128, 64, 20.0);
    let light = EnvironmentLight::build(&ctx, &env, false).expect("builds");
    let baked = light.read_back(&ctx).expect("reads back");
    common::assert_no_validation_errors(&ctx);

    let (size, texels) = &baked.irradiance;
    let (mean, worst) = relative_errors(texels, *size, |n| {
        // The kernel sums the 64-wide level; so does the reference.
        reference::irradiance(&env.halved(), n)
    });
    println!("irradiance vs brute force: mean {mean:.4}, worst {worst:.4} (relative)");
    assert!(worst < 0.01, "irradiance off by {worst:.4}");

    for (level, (size, texels)) in baked.specular.iter().enumerate().skip(1) {
        let roughness = level as f32 / (baked.specular.len() - 1) as f32;
        let (mean, worst) = relative_errors(texels, *size, |r| {
            reference::prefiltered(&env, r, roughness)
        });
        println!(
            "prefiltered roughness {roughness:.1} ({}x{}) vs brute force: mean {mean:.4}, worst {worst:.4}",
            size[0], size[1]
        );
        assert!(
            mean < 0.04 && worst < 0.1,
            "roughness {roughness}: {mean} {worst}"
        );
    }

    // The integrand grows as 1 / (n.v): at grazing views both estimates carry more error.
    let (size, texels) = &baked.brdf;
    let (mut worst, mut worst_grazing) = (0.0f32, 0.0f32);
    for (i, t) in texels.iter().enumerate() {
        let nv = ((i as u32 % size[0]) as f32 + 0.5) / size[0] as f32;
        let roughness = ((i as u32 / size[0]) as f32 + 0.5) / size[1] as f32;
        let (scale, bias) = reference::brdf_scale_bias(nv, roughness, 256);
        let e = (t[0] - scale).abs().max((t[1] - bias).abs());
        if nv < 0.1 {
            worst_grazing = worst_grazing.max(e);
        } else {
            worst = worst.max(e);
        }
    }
    println!(
        "BRDF table vs midpoint integration: worst {worst:.4} (n.v >= 0.1), {worst_grazing:.4} (below)"
    );
    assert!(
        worst < 0.01 && worst_grazing < 0.05,
        "BRDF table off by {worst}, {worst_grazing}"
    );
}

/// Options for a `width` x `height` frame lit by `env`, its radiance read back.
fn lit_by(env: Environment, width: u32, height: u32) -> RenderOptions {
    RenderOptions::default()
        .with_width(width)
        .with_height(height)
        .with_keep_radiance(true)
        .with_environment(EnvironmentSource::Image(env))
}

/// Two white spheres (diffuse, roughness 1; dielectric, roughness 0.4) and a black light.
fn sphere_scene() -> Scene {
    let mut diffuse = sphere_mesh("diffuse", 0.5, 24, 48, 0);
    diffuse.transform = Mat4::from_translation(Vec3::new(-0.6, 0.0, 0.0));
    let mut glossy = sphere_mesh("glossy", 0.5, 24, 48, 1);
    glossy.transform = Mat4::from_translation(Vec3::new(0.6, 0.0, 0.0));
    let white = |name: &str, roughness: f32| Material {
        name: name.into(),
        base_color: [1.0; 4],
        roughness,
        metallic: 0.0,
        ..Material::default()
    };
    Scene {
        meshes: vec![diffuse, glossy],
        materials: vec![white("diffuse", 1.0), white("glossy", 0.4)],
        // A black light: the environment is the only light.
        lights: vec![Light {
            color: Vec3::ZERO,
            ..Light::default_light()
        }],
        camera: Some(Camera::look_at(
            Vec3::new(0.0, 0.4, 3.0),
            Vec3::ZERO,
            0.7,
            0.1,
            10.0,
        )),
        ..Scene::default()
    }
}

#[test]
fn white_spheres_in_a_white_furnace_show_its_radiance() {
    let Some(ctx) = common::device("white furnace") else {
        return;
    };
    let (w, h) = (96, 48);
    let frame = render(
        &ctx,
        &sphere_scene(),
        None,
        &lit_by(Environment::uniform([1.0; 3]), w, h),
    )
    .expect("renders");
    common::assert_no_validation_errors(&ctx);
    assert!(frame.plan.environment.is_some());
    // Pixels whose view ray passes well inside a sphere (not its 1-pixel rim).
    let camera = sphere_scene().camera.expect("the scene has a camera");
    let inverse = camera.view_projection(w as f32 / h as f32).inverse();
    let eye = camera.eye();
    let inside = |x: u32, y: u32, centre: Vec3| {
        let ndc_x = (x as f32 + 0.5) / w as f32 * 2.0 - 1.0;
        let ndc_y = (y as f32 + 0.5) / h as f32 * 2.0 - 1.0;
        let far = inverse.project_point3(Vec3::new(ndc_x, ndc_y, 1.0));
        let dir = (far - eye).normalize();
        let to_centre = centre - eye;
        (to_centre - dir * to_centre.dot(dir)).length() < 0.45
    };
    for (centre, name) in [(-0.6, "diffuse"), (0.6, "dielectric, roughness 0.4")] {
        let centre = Vec3::new(centre, 0.0, 0.0);
        let (mut n, mut worst) = (0, 0.0f32);
        for y in 0..h {
            for x in 0..w {
                if !inside(x, y, centre) {
                    continue;
                }
                n += 1;
                let p = frame.radiance[(y * w + x) as usize];
                for c in &p[..3] {
                    worst = worst.max((c - 1.0).abs());
                }
            }
        }
        println!("white furnace, {name}: {n} pixels, worst |radiance - 1| = {worst:.4}");
        assert!(n > 200, "{name}: only {n} pixels inside");
        assert!(worst <= 0.01, "{name}: off by {worst}");
    }
}

fn lit_scene() -> Scene {
    let mut cube = box_mesh("box", Vec3::splat(0.5), 0);
    cube.transform = Mat4::from_translation(Vec3::new(0.0, 0.6, 0.0));
    let ground = quad_mesh("ground", 6.0, 6.0, 1.0, 1);
    let colour = |name: &str, rgb: [f32; 3], roughness: f32, metallic: f32| Material {
        name: name.into(),
        base_color: [rgb[0], rgb[1], rgb[2], 1.0],
        roughness,
        metallic,
        ..Material::default()
    };
    Scene {
        meshes: vec![cube, ground],
        materials: vec![
            colour("box", [0.9, 0.8, 0.7], 0.05, 1.0),
            colour("ground", [0.4, 0.45, 0.5], 0.8, 0.0),
        ],
        lights: vec![Light {
            color: Vec3::ZERO,
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

fn radiance(ctx: &Arc<Context>, env: Environment) -> Vec<[f32; 4]> {
    let frame = render(ctx, &lit_scene(), None, &lit_by(env, 96, 64)).expect("renders");
    common::assert_no_validation_errors(ctx);
    frame.radiance
}

#[test]
fn a_blinding_sun_and_a_black_void_give_finite_frames() {
    let Some(ctx) = common::device("extreme environments") else {
        return;
    };
    // The sun's disc holds 1e4 (and the 65504 half floats top out at), on a glossy metal box.
    let bright = radiance(&ctx, structured(256, 128, 1e4));
    let covered: Vec<_> = bright.iter().collect();
    assert!(
        covered
            .iter()
            .all(|p| p.iter().all(|c| c.is_finite() && *c >= 0.0)),
        "a pixel is not a finite radiance"
    );
    let peak = covered.iter().map(|p| p[0]).fold(0.0f32, f32::max);
    println!("1e4 sun: peak radiance {peak:.1}");
    assert!(peak > 10.0, "the sun is not reflected at all ({peak})");

    let black = radiance(&ctx, Environment::uniform([0.0; 3]));
    // Every pixel is black, or the background's clear colour (no geometry).
    let background = [0.015, 0.02, 0.03];
    let is_background = |p: &[f32; 4]| {
        p[..3]
            .iter()
            .zip(background)
            .all(|(c, b)| (c - b).abs() < 1e-3)
    };
    let black_pixels = black.iter().filter(|p| p[..3] == [0.0; 3]).count();
    let lit = black
        .iter()
        .filter(|p| !is_background(p) && p[..3] != [0.0; 3])
        .count();
    assert!(black_pixels > 1000, "only {black_pixels} black pixels");
    assert_eq!(
        lit, 0,
        "{lit} pixels lit by a black environment and a black light"
    );
}
