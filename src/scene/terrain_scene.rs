//! The built-in terrain scene: a tiled grid over an elevation map, covered by one layered relief
//! material (up to four ground layers, weighed by altitude and slope rules or a given splat map,
//! blended by heights) and traced with QDM, lit by a low sun that casts soft shadows, with
//! horizon AO. The layers come from images (the corpus's ground materials) or, when none are
//! given, are made here: four procedural height fields with flat colours shaded by height.

use std::sync::Arc;

use glam::Vec3;
use image::{DynamicImage, ImageBuffer, Luma, Rgba};

use super::{
    AoMode, Camera, HeightSource, LayerWeights, Layers, Light, Material, MaterialLayer, Relief,
    SamplerDesc, Scene, SceneImage, ShadowMode, ShadowSettings, TextureRef, Wrap,
};
use crate::heightfield::{Channel, Generator, Heightfield};
use crate::method::Method;
use crate::terrain::{
    terrain_tiles, BlendMode, GridOptions, LayerError, LayerRule, RuleWeights, SplatMap,
};

/// The name of the terrain scene's tiles (`{TERRAIN_MESH} tile C,R`); they are its meshes 0.., in
/// `terrain_tiles` order, all with material 0.
pub const TERRAIN_MESH: &str = "ground";

/// One ground layer's images (height required; the others optional).
#[derive(Debug, Clone)]
pub struct GroundLayer {
    /// The layer's name, for messages and the images' names.
    pub name: String,
    /// Heights, white high.
    pub height: DynamicImage,
    /// Colour, sRGB.
    pub albedo: Option<DynamicImage>,
    /// Tangent-space normals.
    pub normal: Option<DynamicImage>,
    /// Roughness.
    pub roughness: Option<DynamicImage>,
}

/// How the terrain scene is built.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TerrainOptions {
    /// The tiled ground mesh.
    pub grid: GridOptions,
    /// The method that traces the blended layers.
    pub method: Method,
    /// How the layers blend.
    pub mode: BlendMode,
    /// Repeats of every layer across the terrain.
    pub tiling: f32,
    /// Depth of the layers' relief, as a fraction of one layer tile.
    pub tile_depth: f32,
    /// Side of the blended field the method traces.
    pub resolution: u32,
    /// Side of the splat map the rules paint.
    pub splat_size: u32,
}

impl Default for TerrainOptions {
    fn default() -> TerrainOptions {
        TerrainOptions {
            grid: GridOptions {
                extent: 10.0,
                height: 1.5,
                tile_quads: 32,
                step: 4,
            },
            method: Method::QDM,
            mode: BlendMode::Height,
            tiling: 8.0,
            tile_depth: 0.04,
            resolution: 2048,
            splat_size: 128,
        }
    }
}

/// The layers used when none are given: sand, grass, rock, cliff, from procedural heights.
pub fn procedural_layers(size: u32) -> Vec<GroundLayer> {
    let looks = [
        ("sand", Generator::Fbm, [0.78, 0.70, 0.52]),
        ("grass", Generator::Fbm, [0.32, 0.45, 0.20]),
        ("rock", Generator::Bricks, [0.48, 0.45, 0.42]),
        ("cliff", Generator::Fbm, [0.36, 0.33, 0.31]),
    ];
    looks
        .iter()
        .enumerate()
        .map(|(k, (name, generator, colour))| {
            let field = generator.generate(size, size, 40 + k as u64);
            let height = ImageBuffer::from_fn(size, size, |i, j| {
                Luma([(field.get(i, j) * 65535.0).round() as u16])
            });
            // Darker in the hollows, so the blend of colours follows the relief.
            let albedo = ImageBuffer::from_fn(size, size, |i, j| {
                let shade = 0.65 + 0.35 * field.get(i, j);
                let c = colour.map(|c| (crate::srgb::encode(c * shade) * 255.0).round() as u8);
                Rgba([c[0], c[1], c[2], 255])
            });
            GroundLayer {
                name: (*name).into(),
                height: DynamicImage::ImageLuma16(height),
                albedo: Some(DynamicImage::ImageRgba8(albedo)),
                normal: None,
                roughness: None,
            }
        })
        .collect()
}

/// The splat map the built-in rules paint over `elevation` for `layers` layers.
pub fn rules_splat(
    elevation: &Heightfield,
    layers: usize,
    opts: &TerrainOptions,
) -> Result<SplatMap, LayerError> {
    ground_rules(elevation, layers, opts)?.splat(elevation)
}

/// The built-in rules for `layers` layers over `elevation` as loaded, to weigh it again where
/// strokes move it.
pub fn ground_rules(
    elevation: &Heightfield,
    layers: usize,
    opts: &TerrainOptions,
) -> Result<RuleWeights, LayerError> {
    // With fewer layers, the first ones keep their bands and the last takes the rest.
    let rules = &LayerRule::GROUND[..layers.min(LayerRule::GROUND.len())];
    let texel = opts.grid.extent / elevation.width().max(elevation.height()) as f32;
    RuleWeights::new(elevation, rules, texel, opts.grid.height, opts.splat_size)
}

/// The terrain scene over `elevation` with `layers` weighed by `splat`.
pub fn terrain_scene(
    elevation: &Heightfield,
    layers: Vec<GroundLayer>,
    splat: &SplatMap,
    opts: &TerrainOptions,
) -> Scene {
    let mut images = Vec::new();
    let mut add = |name: String, pixels: DynamicImage| {
        images.push(SceneImage {
            name,
            pixels: Arc::new(pixels),
        });
        images.len() - 1
    };
    let tiled = |image: usize| TextureRef {
        image,
        tex_coord: 0,
        transform: Default::default(),
        sampler: SamplerDesc::default(),
    };
    let material_layers: Vec<MaterialLayer> = layers
        .into_iter()
        .map(|l| {
            let name = l.name.clone();
            let mut optional = |what: &str, image: Option<DynamicImage>| {
                image.map(|p| tiled(add(format!("{name} {what}"), p)))
            };
            let albedo = optional("albedo", l.albedo);
            let normal = optional("normal", l.normal);
            let roughness = optional("roughness", l.roughness);
            let height = tiled(add(format!("{name} height"), l.height));
            MaterialLayer {
                name: l.name,
                height,
                height_channel: Channel::Luma,
                albedo,
                normal,
                roughness,
                tiling: opts.tiling,
                depth: 1.0,
            }
        })
        .collect();
    let splat_image = add("splat map".into(), splat_pixels(splat));
    let splat = TextureRef {
        sampler: SamplerDesc {
            wrap_u: Wrap::ClampToEdge,
            wrap_v: Wrap::ClampToEdge,
            mipmaps: None,
            ..SamplerDesc::default()
        },
        ..tiled(splat_image)
    };
    let relief = Relief {
        height: HeightSource::Layers,
        shadows: ShadowSettings::new(ShadowMode::Cone),
        ao: AoMode::Horizon {
            directions: 8,
            rotated: false,
        },
        ..Relief::new(opts.tile_depth / opts.tiling, opts.method)
    };
    let material = Material {
        name: "ground".into(),
        base_color: [1.0; 4],
        roughness: 0.9,
        relief: Some(relief),
        layers: Some(Layers {
            layers: material_layers,
            weights: LayerWeights::Splat(splat),
            mode: opts.mode,
            resolution: opts.resolution,
        }),
        ..Material::default()
    };
    let meshes = terrain_tiles(elevation, &opts.grid, TERRAIN_MESH, 0);
    let e = opts.grid.extent;
    let camera = Camera::look_at(
        Vec3::new(0.32 * e, 0.42 * e, 0.55 * e),
        Vec3::new(0.0, 0.0, 0.05 * e),
        45f32.to_radians(),
        0.01 * e,
        4.0 * e,
    );
    let sun = Light {
        casts_shadows: true,
        // About 25 degrees up: the relief's shadows are longer than its bumps are wide.
        direction: -Vec3::new(-0.8, 0.45, -0.35).normalize(),
        radius: 1.5f32.to_radians(),
        ..Light::default_light()
    };
    Scene {
        meshes,
        materials: vec![material],
        images,
        camera: Some(camera),
        lights: vec![sun],
        camera_path: None,
    }
}

/// The splat map as a 16-bit RGBA image.
fn splat_pixels(splat: &SplatMap) -> DynamicImage {
    let (w, h) = splat.size();
    let image = ImageBuffer::from_fn(w, h, |i, j| {
        let texel = splat.texel(i, j);
        Rgba(texel.map(|x| (x.clamp(0.0, 1.0) * 65535.0).round() as u16))
    });
    DynamicImage::ImageRgba16(image)
}
