//! Golden images of scenes beyond the default one: a material showcase built in code (every
//! texture slot, uv transforms, alpha mask and blend, point and spot lights) and a displaced glTF
//! file written by the test (height map in the material's extras, read by the loader).
//! Regenerate after an intended change with `RELIEF_UPDATE_GOLDEN=1 cargo test --test golden_scenes`.

mod common;

use std::sync::Arc;

use glam::{Mat4, Vec3};
use image::{DynamicImage, Rgba, RgbaImage};
use relief::heightfield::Generator;
use relief::render::{render, RenderOptions};
use relief::scene::{
    box_mesh, load_gltf, quad_mesh, AlphaMode, Camera, Filter, Light, LightKind, Material,
    SamplerDesc, Scene, SceneImage, SceneOptions, TextureRef, UvTransform,
};

const WIDTH: u32 = 160;
const HEIGHT: u32 = 120;

fn image(name: &str, img: RgbaImage) -> SceneImage {
    SceneImage {
        name: name.into(),
        pixels: Arc::new(DynamicImage::ImageRgba8(img)),
    }
}

fn texture(image: usize) -> TextureRef {
    TextureRef {
        image,
        tex_coord: 0,
        transform: UvTransform::default(),
        sampler: SamplerDesc::default(),
    }
}

/// Every material feature on plain surfaces, lit by a point and a spot light.
fn materials_scene() -> Scene {
    let checker = RgbaImage::from_fn(32, 32, |x, y| {
        if (x / 4 + y / 4) % 2 == 0 {
            Rgba([230, 220, 200, 255])
        } else {
            Rgba([60, 70, 90, 255])
        }
    });
    // Round bumps in tangent space: the normal map's x, y follow the bump's slope.
    let bumps = RgbaImage::from_fn(64, 64, |x, y| {
        let (u, v) = ((x % 16) as f32 / 16.0 - 0.5, (y % 16) as f32 / 16.0 - 0.5);
        let n = Vec3::new(-u * 1.5, -v * 1.5, 1.0).normalize();
        let enc = |c: f32| ((c * 0.5 + 0.5) * 255.0) as u8;
        Rgba([enc(n.x), enc(n.y), enc(n.z), 255])
    });
    // Roughness in G, metalness in B; occlusion in R darkens the cell edges.
    let orm = RgbaImage::from_fn(16, 16, |x, y| {
        let edge = x == 0 || y == 0;
        Rgba([
            if edge { 80 } else { 255 },
            90,
            if x < 8 { 255 } else { 0 },
            255,
        ])
    });
    let glow = RgbaImage::from_fn(16, 16, |x, _| Rgba([255, (x * 16) as u8, 0, 255]));
    let holes = RgbaImage::from_fn(32, 32, |x, y| {
        let (dx, dy) = (x as i32 % 8 - 4, y as i32 % 8 - 4);
        let alpha = if dx * dx + dy * dy < 6 { 0 } else { 255 };
        Rgba([120, 200, 120, alpha])
    });
    let images = vec![
        image("checker", checker),
        image("bumps", bumps),
        image("orm", orm),
        image("glow", glow),
        image("holes", holes),
    ];
    let nearest = SamplerDesc {
        mag: Filter::Nearest,
        ..SamplerDesc::default()
    };
    let ground = Material {
        name: "ground".into(),
        base_color_texture: Some(TextureRef {
            transform: UvTransform {
                offset: [0.25, 0.0],
                rotation: 0.3,
                scale: [3.0, 3.0],
            },
            sampler: nearest,
            ..texture(0)
        }),
        roughness: 0.8,
        ..Material::default()
    };
    let crate_material = Material {
        name: "bumpy metal".into(),
        base_color: [0.9, 0.75, 0.5, 1.0],
        normal_texture: Some(texture(1)),
        metallic_roughness_texture: Some(texture(2)),
        occlusion_texture: Some(texture(2)),
        metallic: 1.0,
        roughness: 1.0,
        ..Material::default()
    };
    let lamp = Material {
        name: "lamp".into(),
        base_color: [0.1, 0.1, 0.1, 1.0],
        emissive: [1.0, 1.0, 1.0],
        emissive_texture: Some(texture(3)),
        ..Material::default()
    };
    let fence = Material {
        name: "fence".into(),
        base_color_texture: Some(texture(4)),
        alpha_mode: AlphaMode::Mask { cutoff: 0.5 },
        double_sided: true,
        ..Material::default()
    };
    let glass = Material {
        name: "glass".into(),
        base_color: [0.9, 0.2, 0.2, 0.45],
        alpha_mode: AlphaMode::Blend,
        roughness: 0.2,
        ..Material::default()
    };
    let mut meshes = vec![quad_mesh("ground", 6.0, 6.0, 1.0, 0)];
    let mut cube = box_mesh("cube", Vec3::splat(0.5), 1);
    cube.transform = Mat4::from_translation(Vec3::new(-0.8, 0.5, 0.0)) * Mat4::from_rotation_y(0.5);
    meshes.push(cube);
    let mut lamp_box = box_mesh("lamp", Vec3::new(0.3, 0.15, 0.3), 2);
    lamp_box.transform = Mat4::from_translation(Vec3::new(1.2, 0.15, -0.8));
    meshes.push(lamp_box);
    let mut fence_quad = quad_mesh("fence", 1.4, 1.0, 1.0, 3);
    fence_quad.transform = Mat4::from_translation(Vec3::new(0.9, 0.6, 0.3))
        * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    meshes.push(fence_quad);
    let mut glass_quad = quad_mesh("glass", 1.0, 1.0, 1.0, 4);
    glass_quad.transform = Mat4::from_translation(Vec3::new(-0.2, 0.5, 1.2))
        * Mat4::from_rotation_x(std::f32::consts::FRAC_PI_2);
    meshes.push(glass_quad);
    Scene {
        meshes,
        materials: vec![ground, crate_material, lamp, fence, glass],
        images,
        camera: Some(Camera::look_at(
            Vec3::new(0.5, 2.4, 4.2),
            Vec3::new(0.0, 0.3, 0.0),
            45f32.to_radians(),
            0.05,
            50.0,
        )),
        lights: vec![
            Light {
                kind: LightKind::Point,
                position: Vec3::new(-1.5, 2.0, 1.5),
                direction: Vec3::NEG_Y,
                color: Vec3::new(12.0, 10.0, 8.0),
                range: Some(10.0),
                casts_shadows: true,
                radius: 0.0,
                shadow_map_size: None,
                shadow_cascades: None,
            },
            Light {
                kind: LightKind::Spot {
                    inner_cone: 0.3,
                    outer_cone: 0.5,
                },
                position: Vec3::new(1.5, 3.0, 0.5),
                direction: Vec3::new(-0.3, -1.0, -0.1).normalize(),
                color: Vec3::new(6.0, 8.0, 14.0),
                range: None,
                casts_shadows: true,
                radius: 0.0,
                shadow_map_size: None,
                shadow_cascades: None,
            },
        ],
        camera_path: None,
    }
}

#[test]
fn material_showcase_matches_golden() {
    let Some(ctx) = common::device("material_showcase_matches_golden") else {
        return;
    };
    let opts = RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT);
    let frame = render(&ctx, &materials_scene(), None, &opts).expect("renders");
    // No relief anywhere: one plain variant per (sidedness, blending), no heights, no maps.
    assert!(frame.plan.heights.is_empty());
    assert!(frame.plan.pipelines.iter().all(|p| p.method.is_none()));
    assert_eq!(frame.plan.pipelines.len(), 3, "{:?}", frame.plan.pipelines);
    common::assert_no_validation_errors(&ctx);
    common::golden::check_golden("materials_160x120", WIDTH, HEIGHT, &frame.rgba);
}

/// A displaced plane as a glTF file: heights in the material's extras (texture 0, red channel),
/// a base colour texture, a point light and a camera.
fn write_displaced_gltf(dir: &std::path::Path) -> std::path::PathBuf {
    let heights = Generator::Bricks.generate(128, 128, 7);
    heights
        .save_png16(&dir.join("height.png"))
        .expect("writes height PNG");
    let colour = RgbaImage::from_fn(64, 64, |x, y| {
        Rgba([150 + (x % 32) as u8 * 3, 90 + (y % 16) as u8 * 4, 70, 255])
    });
    colour.save(dir.join("colour.png")).expect("writes PNG");
    let (bin, views, accessors) = common::plane_gltf::plane_buffer(None);
    std::fs::write(dir.join("plane.bin"), &bin).expect("writes bin");
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"},
        "extensionsUsed": ["KHR_lights_punctual"],
        "extensions": {"KHR_lights_punctual": {"lights": [
            {"type": "point", "color": [1.0, 0.95, 0.9], "intensity": 6.0}
        ]}},
        "scene": 0,
        "scenes": [{"nodes": [0, 1, 2]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0.0, 1.3, 1.9], "rotation": [-0.3007058, 0.0, 0.0, 0.953717]},
            {"translation": [-1.0, 1.5, 1.0], "extensions": {"KHR_lights_punctual": {"light": 0}}}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 50.0}}],
        "meshes": [{"primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2},
            "indices": 3, "material": 0
        }]}],
        "materials": [{
            "name": "bricks",
            "pbrMetallicRoughness": {"baseColorTexture": {"index": 1}, "metallicFactor": 0.0, "roughnessFactor": 0.7},
            "extras": {"relief": {
                "height": {"index": 0, "channel": "r"},
                "depth_scale": 0.05, "method": "qdm", "budget": 96
            }}
        }],
        "textures": [{"source": 0}, {"source": 1}],
        "images": [{"uri": "height.png"}, {"uri": "colour.png"}],
        "buffers": [{"uri": "plane.bin", "byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors
    });
    let path = dir.join("displaced.gltf");
    std::fs::write(&path, serde_json::to_vec_pretty(&gltf).expect("json")).expect("writes gltf");
    path
}

#[test]
fn displaced_gltf_matches_golden() {
    let Some(ctx) = common::device("displaced_gltf_matches_golden") else {
        return;
    };
    let dir = common::scratch_dir("displaced_gltf");
    let path = write_displaced_gltf(&dir);
    let scene = load_gltf(&path, &SceneOptions::default()).expect("loads");
    assert!(scene.camera.is_some(), "the file's camera");
    assert_eq!(scene.lights.len(), 1, "the file's point light");
    let opts = RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT);
    let frame = render(&ctx, &scene, None, &opts).expect("renders");
    let plan = &frame.plan;
    assert_eq!(plan.pipelines.len(), 1, "{:?}", plan.pipelines);
    assert_eq!(plan.pipelines[0].method.map(|m| m.id()), Some("qdm"));
    assert_eq!(
        plan.pipelines[0].max_steps,
        Some(96),
        "the material's budget"
    );
    assert!(
        plan.pipelines[0].shadows.mode.is_some(),
        "glTF lights cast shadows"
    );
    assert_eq!(plan.heights.len(), 1);
    assert!(plan.heights[0].pyramid && plan.heights[0].size == (128, 128));
    common::assert_no_validation_errors(&ctx);
    common::golden::check_golden("displaced_gltf_160x120", WIDTH, HEIGHT, &frame.rgba);
}
