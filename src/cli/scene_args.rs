//! The flags that say what to draw and how, shared by `relief render` and `relief view`: the
//! scene (a glTF file or the built-in default), its relief (height map, method, depth scale,
//! shading, LOD), the image size, height storage and addressing, and the device.

use std::path::{Path, PathBuf};
use std::sync::Arc;

use clap::{Args, ValueEnum};
use relief::environment::{Background, EnvironmentSource};
use relief::heightfield::{Address, Heightfield, MAX_SIDE};
use relief::method::Method;
use relief::render::{
    HeightFormat, Lighting, RenderOptions, ToneMap, ToneMapping, MAX_SUPERSAMPLE, SAMPLE_COUNTS,
};
use relief::scene::{
    default_heightfield, default_scene, load_gltf_with_report, Scene, SceneOptions,
    DEFAULT_SCENE_METHOD,
};
use relief::vk::Context;

use super::cells_render_args::CellsRenderArgs;
use super::heightmap_args::HeightmapArgs;
use super::lod_args::LodArgs;
use super::reference_args::DisplacedReferenceArgs;
use super::shading_args::ShadingArgs;
use super::shadow_map_args::ShadowMapArgs;
use super::terrain_args::TerrainArgs;
use super::terrain_edits::TerrainEdits;
use super::usage;

/// A feature switched on or off.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Toggle {
    On,
    Off,
}

/// Where surfaces are lit (`--lighting`).
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum LightingArg {
    Forward,
    Deferred,
}

#[derive(Clone, Copy, Debug, ValueEnum)]
pub enum FormatArg {
    R16,
    R32f,
}

#[derive(Args)]
pub struct SceneArgs {
    /// glTF scenes (.gltf or .glb), drawn one after another (`render` only: a batch, each
    /// scene's files tagged with its name); the built-in default scene when left out.
    scenes: Vec<PathBuf>,
    /// Image width in pixels (`view`: the window's first width).
    #[arg(long, default_value_t = 960, value_parser = image_side)]
    pub(super) width: u32,
    /// Image height in pixels (`view`: the window's first height).
    #[arg(long, default_value_t = 540, value_parser = image_side)]
    pub(super) height: u32,
    #[command(flatten)]
    heights: HeightmapArgs,
    #[command(flatten)]
    shading: ShadingArgs,
    #[command(flatten)]
    shadow_maps: ShadowMapArgs,
    /// Depth of height 0 below the surface, in uv units (0.05 = a twentieth of the texture).
    #[arg(long, value_name = "S")]
    depth_scale: Option<f32>,
    /// Displacement method id (see `relief methods`): for the default scene (default qdm), for
    /// materials given relief by --heightmap (default pom), and for every relief material of a
    /// glTF file (default: each material's own).
    #[arg(long, value_name = "ID", value_parser = method_id)]
    method: Option<Method>,
    /// Which materials --heightmap displaces: a material name, or `all`.
    #[arg(long, value_name = "NAME|all", default_value = "all")]
    material: String,
    /// Which scene of the glTF file (default: the file's default scene).
    #[arg(long = "scene", value_name = "N")]
    scene_index: Option<usize>,
    /// Which camera of the scene, in node order (default: the first; none frames the scene), or
    /// `all` (`render` only: one image per camera, each camera's files tagged camK).
    #[arg(long, value_name = "N|all", value_parser = camera_choice)]
    camera: Option<CameraChoice>,
    /// Storage of heights on the GPU.
    #[arg(long, value_enum, default_value = "r16")]
    height_format: FormatArg,
    /// Height map addressing.
    #[arg(long, value_name = "repeat|clamp", default_value_t = Address::Repeat)]
    address: Address,
    /// Samples per pixel of the raster passes: 1, 2, 4 or 8 (clamped to what the device takes;
    /// relief is traced once per pixel). Smooths geometry edges.
    #[arg(long, value_name = "N", default_value_t = 4, value_parser = msaa_samples)]
    msaa: u32,
    /// Supersampling: draw the scene K times larger along each axis and average each pixel's
    /// K x K block (1 to 4). Smooths what MSAA cannot: the relief's own silhouettes and steps.
    #[arg(long, value_name = "K", default_value_t = 1, value_parser = supersample_factor)]
    supersample: u32,
    /// Hidden relief: on lays down, before the surface pass, how far each pixel's nearest
    /// opaque surface can reach, and relief fragments behind it skip their trace (the image
    /// is the same); off traces every relief fragment (the forward reference).
    #[arg(long, value_enum, value_name = "on|off", default_value = "on")]
    occluders: Toggle,
    /// Where surfaces are lit: forward lights each fragment as it is drawn (the reference);
    /// deferred writes shading inputs beside the G-buffer and lights each pixel once after the
    /// scene is drawn (one sample per pixel: with --msaa 1).
    #[arg(
        long,
        value_enum,
        value_name = "forward|deferred",
        default_value = "forward"
    )]
    lighting: LightingArg,
    /// Shadows by ray query: every shadow-casting light is tested by rays through the scene's
    /// acceleration structures (relief prisms walked exactly, the receiver's own included)
    /// instead of shadow maps; a light with a size gets 16 rays per pixel. Needs --lighting
    /// deferred and a device with ray queries.
    #[arg(long)]
    traced_shadows: bool,
    /// Tone mapping from linear radiance to the frame's colours: pbr-neutral (Khronos PBR
    /// Neutral), aces, or none (clamped).
    #[arg(long, value_name = "CURVE", default_value = "pbr-neutral")]
    tonemap: ToneMap,
    /// Exposure in stops: radiance is scaled by 2^EV before tone mapping.
    #[arg(
        long,
        value_name = "EV",
        default_value_t = 0.0,
        allow_negative_numbers = true
    )]
    exposure: f32,
    /// Ambient light: sky (the built-in sky and ground), a Radiance .hdr file
    /// (equirectangular), or none (one flat colour, no environment maps built).
    #[arg(long, value_name = "sky|none|FILE.hdr", default_value = "sky", value_parser = environment_source)]
    environment: EnvironmentSource,
    /// What shows behind the scene: environment (the one lighting it) or colour (one dark
    /// colour, as with --environment none).
    #[arg(long, value_name = "environment|colour", default_value = "environment")]
    background: Background,
    /// Pick the Vulkan device whose name contains this text.
    #[arg(long, value_name = "SUBSTRING")]
    pub(super) device: Option<String>,
    #[command(flatten)]
    lod: LodArgs,
    #[command(flatten)]
    cells: CellsRenderArgs,
    #[command(flatten)]
    terrain: TerrainArgs,
    #[command(flatten)]
    displaced: DisplacedReferenceArgs,
}

/// Which of a glTF scene's cameras to draw through.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CameraChoice {
    /// The camera with this index, in node order.
    One(usize),
    /// Each camera in turn.
    All,
}

/// A scene ready for a renderer: the scene with every flag applied, the height map relief
/// materials without their own read (if any), and what that map is, for reports.
pub struct LoadedScene {
    pub scene: Scene,
    pub heights: Option<Heightfield>,
    pub source: String,
    /// Strokes to apply between frames (`--terrain ... --edits`).
    pub edits: Option<TerrainEdits>,
    /// Cameras the glTF scene holds (0 for the built-in scenes, which are framed).
    pub cameras: usize,
}

const DEFAULT_GLTF_DEPTH_SCALE: f32 = 0.05;

impl SceneArgs {
    /// Checks the flags, loads the one scene they name (refusing several, or every camera) and
    /// its height map, and applies shading and LOD.
    pub fn load(&self) -> anyhow::Result<LoadedScene> {
        if self.scenes.len() > 1 {
            return Err(usage(format!(
                "one scene at a time here; {} were given",
                self.scenes.len()
            )));
        }
        let camera = match self.camera {
            Some(CameraChoice::All) => {
                return Err(usage(
                    "--camera all renders one image per camera; here, choose one: --camera N",
                ))
            }
            Some(CameraChoice::One(k)) => Some(k),
            None => None,
        };
        self.check()?;
        self.load_scene(self.scenes.first().map(PathBuf::as_path), camera)
    }

    /// The scene files given, in order; one `None` (the built-in scene) when none was.
    pub fn scene_files(&self) -> Vec<Option<&Path>> {
        if self.scenes.is_empty() {
            vec![None]
        } else {
            self.scenes.iter().map(|p| Some(p.as_path())).collect()
        }
    }

    /// The camera choice (`None`: the scene's first camera, or a framing).
    pub fn camera(&self) -> Option<CameraChoice> {
        self.camera
    }

    /// Loads `scene` (the built-in one for `None`) through its `camera`-th camera, with its
    /// height map, shading and LOD. The flags must have been checked ([`SceneArgs::check`]).
    pub fn load_scene(
        &self,
        scene: Option<&Path>,
        camera: Option<usize>,
    ) -> anyhow::Result<LoadedScene> {
        let method: Method = match &self.method {
            Some(method) => *method,
            None if scene.is_none() => DEFAULT_SCENE_METHOD,
            None => Method::POM,
        };
        if let Some((mut scene, edits)) = self.terrain.scene(method, self.depth_scale)? {
            self.shading.apply(&mut scene)?;
            self.shadow_maps.apply(&mut scene)?;
            self.lod.apply(&mut scene)?;
            let source = format!(
                "terrain over {}",
                self.terrain
                    .terrain
                    .as_ref()
                    .map_or_else(String::new, |p| p.display().to_string())
            );
            return Ok(LoadedScene {
                scene,
                heights: None,
                source,
                edits,
                cameras: 0,
            });
        }
        let loaded = self.heights.load()?;
        let built_in = scene.is_none();
        let (mut scene, cameras) = self.build_scene(scene, camera, method, loaded.is_some())?;
        self.shading.apply(&mut scene)?;
        self.shadow_maps.apply(&mut scene)?;
        self.lod.apply(&mut scene)?;
        let (heights, source) = match loaded {
            Some((hf, source)) => (Some(hf), source),
            None if built_in => (
                Some(default_heightfield()),
                "built-in bricks 256x256".to_owned(),
            ),
            None => (None, "the scene's own".to_owned()),
        };
        let scene = self
            .displaced
            .apply(scene, heights.as_ref(), self.address)?;
        Ok(LoadedScene {
            scene,
            heights,
            source,
            edits: None,
            cameras,
        })
    }

    /// The render options at `width` x `height` (the flags' size, or a window's).
    pub fn render_options(&self, width: u32, height: u32) -> RenderOptions {
        RenderOptions::default()
            .with_width(width)
            .with_height(height)
            .with_height_format(match self.height_format {
                FormatArg::R16 => HeightFormat::R16Unorm,
                FormatArg::R32f => HeightFormat::R32Float,
            })
            .with_address(self.address)
            .with_cells(self.cells.options())
            .with_paintable_layers(false)
            .with_shadows(self.shadow_maps.options())
            .with_shadow_probe(None)
            .with_msaa(self.msaa)
            .with_tone_mapping(ToneMapping {
                curve: self.tonemap,
                exposure_ev: self.exposure,
            })
            .with_keep_radiance(false)
            .with_environment(self.environment.clone())
            .with_background(self.background)
            .with_supersample(self.supersample)
            .with_occluders(self.occluders == Toggle::On)
            .with_gbuffer(false)
            .with_count_work(false)
            .with_lighting(match self.lighting {
                LightingArg::Forward => Lighting::Forward,
                LightingArg::Deferred => Lighting::Deferred,
            })
            .with_traced_shadows(self.traced_shadows)
    }

    /// Whether the scene is drawn larger and averaged down (`--supersample` above 1).
    pub fn supersampled(&self) -> bool {
        self.supersample > 1
    }

    /// Refuses bad values and combinations of the flags, before anything is read or made.
    pub fn check(&self) -> anyhow::Result<()> {
        self.cells.check()?;
        if !self.exposure.is_finite() {
            return Err(usage(format!(
                "--exposure must be a finite number of stops, got {}",
                self.exposure
            )));
        }
        if self.material != "all" && self.scenes.is_empty() {
            return Err(usage(format!(
                "--material {:?} chooses materials of a glTF file for --heightmap; give the scene file",
                self.material
            )));
        }
        if let (Some(k), true) = (self.camera, self.scenes.is_empty()) {
            let k = match k {
                CameraChoice::One(k) => k.to_string(),
                CameraChoice::All => "all".into(),
            };
            return Err(usage(format!(
                "--camera {k} chooses a camera of a glTF file; the built-in scenes have none (they are framed)"
            )));
        }
        if self.terrain.terrain.is_some() {
            if let Some(path) = self.scenes.first() {
                return Err(usage(format!(
                    "--terrain draws the built-in terrain scene; leave out the scene file {}",
                    path.display()
                )));
            }
            if self.heights.heightmap.is_some() || self.heights.field.is_some() {
                return Err(usage(
                    "--terrain displaces the ground with its layers; leave out --heightmap",
                ));
            }
        }
        if let Some(s) = self.depth_scale {
            if !(s.is_finite() && s > 0.0) {
                return Err(usage(format!(
                    "--depth-scale must be a finite number above 0, got {s}"
                )));
            }
        }
        Ok(())
    }

    fn build_scene(
        &self,
        path: Option<&Path>,
        camera: Option<usize>,
        method: Method,
        heights: bool,
    ) -> anyhow::Result<(Scene, usize)> {
        let Some(path) = path else {
            let mut scene = default_scene(method);
            if let Some(s) = self.depth_scale {
                scene
                    .materials
                    .iter_mut()
                    .filter_map(|m| m.relief.as_mut())
                    .for_each(|r| r.depth_scale = s);
            }
            return Ok((scene, 0));
        };
        let options = SceneOptions {
            scene: self.scene_index,
            camera,
        };
        let (mut scene, report) = load_gltf_with_report(path, &options)?;
        let filter = (self.material != "all").then_some(self.material.as_str());
        if heights {
            let depth = self.depth_scale.unwrap_or(DEFAULT_GLTF_DEPTH_SCALE);
            if scene.apply_relief(depth, method, filter) == 0 {
                let names: Vec<&str> = scene.materials.iter().map(|m| m.name.as_str()).collect();
                return Err(usage(format!(
                    "--material {:?} names no material of {}; its materials: {}",
                    self.material,
                    path.display(),
                    names.join(", ")
                )));
            }
        } else if filter.is_some() {
            return Err(usage(
                "--material chooses which materials --heightmap displaces; give --heightmap FILE",
            ));
        } else if self.method.is_some() {
            // Like the shading flags, --method speaks for every relief material of the file;
            // what a material cannot combine with it (shells, LOD, layers) the plan refuses by
            // name.
            scene
                .materials
                .iter_mut()
                .filter_map(|m| m.relief.as_mut())
                .for_each(|r| r.method = method);
        }
        Ok((scene, report.cameras))
    }
}

impl LoadedScene {
    /// Fails if the height map is larger than the device takes.
    pub fn check_device(&self, ctx: &Arc<Context>) -> anyhow::Result<()> {
        if let Some(hf) = &self.heights {
            hf.check_max_dimension(ctx.info().max_image_dimension_2d, &self.source)?;
        }
        Ok(())
    }
}

/// An image side in pixels, 1 to `MAX_SIDE`: refused by the argument parser (exit 2), before any
/// device is made.
fn image_side(text: &str) -> Result<u32, String> {
    match text.parse::<u32>() {
        Ok(n) if (1..=MAX_SIDE).contains(&n) => Ok(n),
        _ => Err(format!("an image side is 1 to {MAX_SIDE} pixels")),
    }
}

/// `--camera`'s value: a camera index or `all`.
fn camera_choice(text: &str) -> Result<CameraChoice, String> {
    if text == "all" {
        return Ok(CameraChoice::All);
    }
    text.parse()
        .map(CameraChoice::One)
        .map_err(|_| "a camera index (0 for the first) or all".into())
}

/// `--method`'s value: a method id of the table.
fn method_id(text: &str) -> Result<Method, String> {
    text.parse::<Method>().map_err(|e| e.to_string())
}

/// `--msaa`'s value: a sample count the renderer takes (`SAMPLE_COUNTS`).
fn msaa_samples(text: &str) -> Result<u32, String> {
    match text.parse::<u32>() {
        Ok(n) if SAMPLE_COUNTS.contains(&n) => Ok(n),
        _ => Err("must be 1, 2, 4 or 8 samples per pixel".into()),
    }
}

/// `--supersample`'s value: 1 to `MAX_SUPERSAMPLE` samples per pixel along each axis.
fn supersample_factor(text: &str) -> Result<u32, String> {
    match text.parse::<u32>() {
        Ok(k) if (1..=MAX_SUPERSAMPLE).contains(&k) => Ok(k),
        _ => Err(format!(
            "must be 1 to {MAX_SUPERSAMPLE} (samples per pixel along each axis)"
        )),
    }
}

/// `--environment`'s value: `sky`, `none`, or a file.
fn environment_source(value: &str) -> Result<EnvironmentSource, String> {
    Ok(match value {
        "sky" => EnvironmentSource::Sky,
        "none" => EnvironmentSource::Flat,
        "" => return Err("give sky, none or a .hdr file".into()),
        path => EnvironmentSource::File(path.into()),
    })
}
