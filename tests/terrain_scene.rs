//! The terrain scene: a layered relief material over tiled ground, its blended field traced by
//! QDM with soft shadows and AO. One-hot layers render the same image as that layer alone as a
//! plain height map; the built-in scene with procedural layers matches its golden image; the
//! corpus's four ground layers over its real elevation map render (when the corpus is present).
//! Regenerate the golden image after an intended change with
//! `RELIEF_UPDATE_GOLDEN=1 cargo test --test terrain_scene`.

mod common;

use relief::heightfield::{Generator, Heightfield};
use relief::render::{render, RenderOptions};
use relief::terrain::{
    procedural_layers, rules_splat, terrain_scene, GridOptions, SplatMap, TerrainOptions,
};

const WIDTH: u32 = 192;
const HEIGHT: u32 = 128;

fn small_options() -> TerrainOptions {
    TerrainOptions {
        grid: GridOptions {
            extent: 10.0,
            height: 1.5,
            tile_quads: 16,
            step: 2,
        },
        tiling: 4.0,
        resolution: 256,
        splat_size: 32,
        ..TerrainOptions::default()
    }
}

fn elevation() -> Heightfield {
    Generator::Fbm.generate(64, 64, 3)
}

fn options() -> RenderOptions {
    RenderOptions {
        width: WIDTH,
        height: HEIGHT,
        ..RenderOptions::default()
    }
}

#[test]
fn the_built_in_terrain_matches_its_golden_image() {
    let Some(ctx) = common::device("the_built_in_terrain_matches_its_golden_image") else {
        return;
    };
    let opts = small_options();
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
