//! `relief render --terrain ELEVATION.png`: the built-in terrain scene over a real elevation map,
//! with ground layers from files (`--layer PREFIX`, up to four, each `PREFIX_height.png` and
//! optionally `_albedo.png`, `_normal.png`, `_roughness.png`) or procedural ones, weighed by
//! altitude and slope rules, blended as `--blend` says.

use std::path::{Path, PathBuf};

use anyhow::Context as _;
use clap::Args;
use relief::heightfield::{Heightfield, LoadOptions};
use relief::method::Method;
use relief::scene::{
    ground_rules, procedural_layers, terrain_scene, GroundLayer, Scene, TerrainOptions,
    MAX_LAYERED_RESOLUTION, TERRAIN_MESH,
};
use relief::terrain::{BlendMode, TerrainEditor, MAX_LAYERS};

use super::terrain_edits::{PaintedLayers, TerrainEdits};

/// Side of the procedural layers' maps.
const PROCEDURAL_LAYER_SIDE: u32 = 256;

#[derive(Args, Debug, Clone)]
pub struct TerrainArgs {
    /// Draw the built-in terrain scene over this elevation map (8- or 16-bit PNG, white high)
    /// instead of a glTF scene.
    #[arg(long, value_name = "ELEVATION.png")]
    pub terrain: Option<PathBuf>,
    /// A ground layer, low to high (up to four): reads PREFIX_height.png and, when present,
    /// PREFIX_albedo.png, PREFIX_normal.png, PREFIX_roughness.png. Procedural layers without it.
    #[arg(long = "layer", value_name = "PREFIX", requires = "terrain")]
    pub layers: Vec<PathBuf>,
    /// How the layers blend: alpha, height or height-intersect.
    #[arg(
        long,
        value_name = "MODE",
        default_value = "height",
        requires = "terrain"
    )]
    pub blend: BlendMode,
    /// Repeats of every layer across the terrain.
    #[arg(long, value_name = "N", default_value_t = 8.0, requires = "terrain")]
    pub tiling: f32,
    /// Side of the blended field the method traces, in texels across the terrain.
    #[arg(
        long,
        value_name = "TEXELS",
        default_value_t = 2048,
        requires = "terrain"
    )]
    pub terrain_resolution: u32,
    /// World height of the elevation map's white, the terrain being 10 units across.
    #[arg(long, value_name = "H", default_value_t = 1.5, requires = "terrain")]
    pub terrain_height: f32,
    /// Brush strokes between frames: a JSON array with one array of strokes per frame (kinds
    /// raise, lower, flatten, crater and paint; see docs/terrain.md); frame 1 is unedited, and
    /// the sequence runs until every list is shown.
    #[arg(long, value_name = "STROKES.json", requires = "terrain")]
    pub edits: Option<PathBuf>,
}

impl TerrainArgs {
    /// The terrain scene the flags ask for, with `method` and `depth_scale` (as a fraction of
    /// one layer tile), or `None` without `--terrain`.
    pub fn scene(
        &self,
        method: Method,
        depth_scale: Option<f32>,
    ) -> anyhow::Result<Option<(Scene, Option<TerrainEdits>)>> {
        let Some(path) = &self.terrain else {
            return Ok(None);
        };
        if self.layers.len() > MAX_LAYERS {
            anyhow::bail!(
                "--layer: a terrain blends at most {MAX_LAYERS} layers, got {}",
                self.layers.len()
            );
        }
        if !(self.tiling.is_finite() && self.tiling > 0.0) {
            anyhow::bail!(
                "--tiling must be a finite number above 0, got {}",
                self.tiling
            );
        }
        if !(self.terrain_height.is_finite() && self.terrain_height > 0.0) {
            anyhow::bail!(
                "--terrain-height must be a finite number above 0, got {}",
                self.terrain_height
            );
        }
        let r = self.terrain_resolution;
        if !(16..=MAX_LAYERED_RESOLUTION).contains(&r) {
            anyhow::bail!(
                "--terrain-resolution must be within 16..={MAX_LAYERED_RESOLUTION}, got {r}"
            );
        }
        let elevation = Heightfield::load_png(path, &LoadOptions::default())
            .context("--terrain: the elevation map")?;
        let layers = if self.layers.is_empty() {
            procedural_layers(PROCEDURAL_LAYER_SIDE)
        } else {
            self.layers
                .iter()
                .map(|p| read_layer(p))
                .collect::<anyhow::Result<_>>()?
        };
        let mut opts = TerrainOptions {
            method,
            mode: self.blend,
            tiling: self.tiling,
            resolution: r,
            ..TerrainOptions::default()
        };
        opts.grid.height = self.terrain_height;
        if let Some(depth) = depth_scale {
            opts.tile_depth = depth;
        }
        let rules = ground_rules(&elevation, layers.len(), &opts)
            .with_context(|| format!("weighing layers over {}", path.display()))?;
        let splat = rules
            .splat(&elevation)
            .with_context(|| format!("weighing layers over {}", path.display()))?;
        let layer_count = layers.len();
        let scene = terrain_scene(&elevation, layers, &splat, &opts);
        let edits = match &self.edits {
            Some(file) => {
                // The terrain scene's one material is the layered one.
                let painted = PaintedLayers::of(0, layer_count, &splat);
                let editor = TerrainEditor::new(elevation, &opts.grid, TERRAIN_MESH, 0);
                Some(TerrainEdits::load(file, editor, painted, Some(rules))?)
            }
            None => None,
        };
        Ok(Some((scene, edits)))
    }
}

/// The layer `prefix` names: its height map (required) and whichever other maps exist.
fn read_layer(prefix: &Path) -> anyhow::Result<GroundLayer> {
    let file = |suffix: &str| {
        let mut name = prefix.as_os_str().to_owned();
        name.push(format!("_{suffix}.png"));
        PathBuf::from(name)
    };
    let open = |path: &Path| {
        image::open(path).with_context(|| format!("--layer: cannot read {}", path.display()))
    };
    let height_path = file("height");
    if !height_path.exists() {
        anyhow::bail!(
            "--layer {}: no height map {} (a layer needs PREFIX_height.png)",
            prefix.display(),
            height_path.display()
        );
    }
    let optional = |suffix: &str| {
        let path = file(suffix);
        path.exists().then(|| open(&path)).transpose()
    };
    Ok(GroundLayer {
        name: prefix
            .file_name()
            .map_or_else(|| "layer".into(), |n| n.to_string_lossy().into_owned()),
        height: open(&height_path)?,
        albedo: optional("albedo")?,
        normal: optional("normal")?,
        roughness: optional("roughness")?,
    })
}
