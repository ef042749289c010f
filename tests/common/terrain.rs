//! A terrain small enough for lavapipe in debug: 4x4 tiles of 16 quads, a 256^2 blended field
//! with every layer repeated 4 times, a 32^2 splat map.

use relief::scene::TerrainOptions;
use relief::terrain::GridOptions;

pub fn small_terrain() -> TerrainOptions {
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
