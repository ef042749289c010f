//! The plan: what a scene needs before anything is built. From the meshes that are drawn and
//! their materials it derives the surface pipelines, the height maps with the pyramid and the
//! precomputed map their methods read, and the passes; everything else is listed as skipped, with
//! the reason. The frame builds exactly what the plan lists (`relief render --explain`).

use super::msaa::MsaaPlan;
pub use super::plan_sources::PlanError;
use super::plan_sources::{check_silhouettes, height_source};
use crate::render::environment::EnvironmentPlan;
use crate::render::kit::tone_curves::ToneMapping;
use serde::Serialize;

use super::lod_note;
use crate::cells::MeshSelection;
use crate::heightfield::{Address, Channel, Heightfield};
use crate::method::{MapKind, Method};
use crate::render::cells::cells_plan::{plan_cells, CellsPlan};
use crate::render::kit::frame_uniforms::MAX_LIGHTS;
use crate::render::kit::pass::Pass;
use crate::render::shadows::shadow_plan::ShadowMapPlan;
use crate::scene::{
    AlphaMode, AoMode, HeightSource, Layers, Light, Lod, Material, Scene, ShadowMode,
    ShadowSettings, Silhouettes,
};

/// Where a planned height map comes from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum HeightKey {
    /// The frame's height map (`--heightmap`, or the default scene's).
    Frame,
    /// A scene image, one channel of it.
    Image {
        /// Index into the scene's images.
        image: usize,
        /// The channel that holds the heights.
        channel: Channel,
        /// White is low rather than high.
        invert: bool,
        /// Clamp if either wrap mode of the material's sampler clamps, else repeat.
        address: Address,
    },
    /// The blend of material `material`'s layers (clamp-addressed: a splat map covers its uv once).
    Layers {
        /// Index into the scene's materials.
        material: usize,
    },
}

/// One surface pipeline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PipelineKey {
    /// `None`: the plain variant, without relief.
    pub method: Option<Method>,
    /// Iteration cap instead of the method's default (a material's `budget`).
    pub max_steps: Option<u32>,
    /// Back faces are drawn too (no culling).
    pub double_sided: bool,
    /// Alpha-blended (glTF `alphaMode` `BLEND`) rather than opaque or masked.
    pub blend: bool,
    /// How the height field shadows it (mode `none` without relief or without a shadow-casting
    /// light).
    pub shadows: ShadowSettings,
    /// Level of detail (relief only): the `:lod` variant with these constants.
    pub lod: Option<Lod>,
    /// Shaded from height-blended layers (set 2): the `:layers` variant.
    pub layers: bool,
    /// Curved relief (`Silhouettes::Curved`): the `:curved` variant.
    pub curved: bool,
    /// Prism shells (`Silhouettes::Shells`): the `:shells` variant, drawn from each mesh's
    /// prisms instead of its triangles.
    pub shells: bool,
    /// Relief fragments write their displaced hit's depth (`Relief::write_depth`), else the
    /// polygon's: a specialization constant, so both come from one shader.
    pub write_depth: bool,
}

impl PipelineKey {
    /// The SPIR-V variant it is built from.
    pub fn shader(&self) -> String {
        match (self.method, self.lod) {
            (Some(m), None) if self.curved => format!("{}:curved", m.surface_shader_key()),
            (Some(m), None) if self.shells => format!("{}:shells", m.surface_shader_key()),
            (Some(m), None) if self.layers => format!("{}:layers", m.surface_shader_key()),
            (Some(m), Some(_)) if self.layers => format!("{}:lod:layers", m.surface_shader_key()),
            (Some(m), None) => m.surface_shader_key(),
            (Some(m), Some(_)) => format!("{}:lod", m.surface_shader_key()),
            (None, _) => "surface.frag:plain".into(),
        }
    }

    /// Whether its set 0 has binding 4, the averaged pyramid (LOD variants of pyramid methods).
    pub fn binds_mean_pyramid(&self) -> bool {
        self.lod.is_some() && self.method.is_some_and(|m| m.info().reads_pyramid())
    }
}

/// One height map to upload: its pyramid when a method reads it, its precomputed map if any.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightPlan {
    /// Where the heights come from; with `map` and `mean_binding` it identifies the upload.
    pub key: HeightKey,
    /// For messages and `--explain`: the file or image it comes from.
    pub source: String,
    /// Width and height in texels.
    pub size: (u32, u32),
    /// The max pyramid is built, because its method, shadow mode or horizon AO reads it.
    pub pyramid: bool,
    /// The precomputed map its method reads besides the heights; `None` if it reads none.
    pub map: Option<MapKind>,
    /// The method whose map it is (maps are built per method row).
    pub map_method: Option<Method>,
    /// Its draws bind binding 4 (LOD pipelines of pyramid methods); uploads differ in this.
    pub mean_binding: bool,
    /// The averaged pyramid is built for binding 4 (else the max pyramid stands in, unread).
    pub mean_pyramid: bool,
}

/// One mesh's draw: which pipeline, which height map (relief only), which material.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DrawPlan {
    /// Index into the scene's meshes.
    pub mesh: usize,
    /// Index into the scene's materials.
    pub material: usize,
    /// Index into [`Plan::pipelines`].
    pub pipeline: usize,
    /// Index into [`Plan::heights`]; `None` for a material without relief.
    pub heights: Option<usize>,
    /// The AO map its material reads (`Plan::ao_maps`), if it asks for one.
    pub ao: Option<usize>,
    /// Whether the surface pass shades it or it only casts.
    pub role: DrawRole,
}

/// What a planned draw renders.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DrawRole {
    /// Shaded by the surface pass, and cast into shadow maps unless blended.
    Surface,
    /// Only cast into shadow maps: a mesh the cells pass draws, whose triangles are the surface
    /// its complex traces.
    CasterOnly,
}

/// One AO map to build: of which height map, how, at which depth scale (the normals and
/// horizons depend on it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AoPlan {
    /// Index into [`Plan::heights`]: the height map it is built from.
    pub heights: usize,
    /// How the occlusion is computed (horizon queries on the max pyramid, or the exact sweep).
    pub mode: AoMode,
    /// The material's depth scale: depth of height 0 below the polygon, in uv units.
    pub depth_scale: f32,
    /// How far (texels of the longer side) the horizons look; `None` is the whole map. Bounded
    /// for layered materials, so that painting their weights rebuilds the AO near the strokes
    /// only (`AoJob::influence_texels`).
    pub reach_texels: Option<f32>,
}

/// How far a layered material's horizons look, in texels of its blended field: a quarter of its
/// most repeated layer's tile. Its AO shades the layers' detail (cracks, stones), whose features
/// are smaller than a tile; the ground's own shape is drawn by its mesh, not by this field.
/// Bounded, it lets painted weights rebuild the AO near the strokes alone.
pub fn layered_ao_reach(layers: &Layers) -> f32 {
    let tiling = layers
        .layers
        .iter()
        .map(|l| l.tiling)
        .fold(1.0f32, f32::max);
    (layers.resolution as f32 / tiling / 4.0).max(LAYERED_AO_MIN_REACH)
}

/// The shortest reach of a layered material's AO, in texels.
const LAYERED_AO_MIN_REACH: f32 = 8.0;

/// Something the scene does not need, and why.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Skipped {
    /// What is not built: a material, map, pass or shader variant, named for `--explain`.
    pub what: String,
    /// Why the scene does not need it, one line.
    pub why: String,
}

/// A pass the frame records, and why the scene needs it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PassPlan {
    /// The pass (serialized as `name`).
    #[serde(rename = "name")]
    pub pass: Pass,
    /// Why the scene needs it, one line.
    pub why: String,
}

/// Everything a frame builds.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// The surface pipelines, each once; draws refer to them by index.
    pub pipelines: Vec<PipelineKey>,
    /// The height maps to upload, each once; draws and AO maps refer to them by index.
    pub heights: Vec<HeightPlan>,
    /// AO maps, built once in the first frame.
    pub ao_maps: Vec<AoPlan>,
    /// One per mesh drawn by the surface pass, in scene order (empty meshes and cell meshes
    /// have none).
    pub draws: Vec<DrawPlan>,
    /// Meshes drawn through cell complexes instead of the surface pass (`--cells`).
    pub cells: Vec<CellsPlan>,
    /// The passes recorded, in order.
    pub passes: Vec<PassPlan>,
    /// What the scene does not need, for `--explain`.
    pub skipped: Vec<Skipped>,
    /// The lights the frame is lit by (the scene's, or the default one).
    pub lights: Vec<Light>,
    /// The lights' shadow maps (added by the renderer from its shadow options).
    pub shadow_maps: Vec<ShadowMapPlan>,
    /// Samples per pixel of the raster passes (set by the renderer from its options and the
    /// device).
    pub msaa: MsaaPlan,
    /// How the frame's radiance is tone mapped (set by the renderer from its options).
    pub tone_mapping: ToneMapping,
    /// The scene is drawn this many times the frame's size per axis and averaged down
    /// (supersampling; 1: not at all; set by the renderer from its options).
    pub supersample: u32,
    /// The environment maps built for the ambient light, `None` for flat ambient light (set by
    /// the renderer from its options).
    pub environment: Option<EnvironmentPlan>,
    /// Relief fragments behind the occluder pass's bounds skip their trace (set by the renderer
    /// from its options: the pass runs when some opaque draw can occlude relief).
    pub occluders: bool,
    /// The surface pass writes the G-buffer beside the radiance (set by the renderer from its
    /// options).
    pub gbuffer: bool,
    /// The surface pass writes shading inputs and the lighting pass lights each pixel once
    /// after it (set by the renderer from `RenderOptions::lighting`; `SPEC_DEFERRED`).
    pub deferred: bool,
    /// The lighting pass casts shadow rays by ray query instead of reading shadow maps (set by
    /// the renderer from `RenderOptions::traced_shadows`).
    pub traced_shadows: bool,
    /// Relief fragments count their traces and steps per pixel (set by the renderer from its
    /// options; `SPEC_COUNT_WORK`).
    pub count_work: bool,
}

impl Plan {
    /// Plans `scene`; `frame_heights` is the height map of materials whose relief has no
    /// texture of its own.
    pub fn derive(scene: &Scene, frame_heights: Option<&Heightfield>) -> Result<Plan, PlanError> {
        Plan::derive_with_cells(scene, frame_heights, None)
    }

    /// [`Plan::derive`], drawing the meshes `cells` selects through cell complexes.
    pub fn derive_with_cells(
        scene: &Scene,
        frame_heights: Option<&Heightfield>,
        cells: Option<&MeshSelection>,
    ) -> Result<Plan, PlanError> {
        let cells = match cells {
            Some(selection) => plan_cells(scene, selection)?,
            None => Vec::new(),
        };
        let lights = scene.effective_lights();
        let casts_shadows = lights.iter().take(MAX_LIGHTS).any(|l| l.casts_shadows);
        let mut plan = Plan {
            pipelines: Vec::new(),
            heights: Vec::new(),
            ao_maps: Vec::new(),
            draws: Vec::new(),
            cells,
            passes: Vec::new(),
            skipped: Vec::new(),
            lights,
            shadow_maps: Vec::new(),
            msaa: MsaaPlan::SINGLE,
            tone_mapping: ToneMapping::NONE,
            environment: None,
            supersample: 1,
            occluders: false,
            gbuffer: false,
            deferred: false,
            traced_shadows: false,
            count_work: false,
        };
        let mut used = vec![false; scene.materials.len()];
        for c in &plan.cells {
            used[c.material] = true;
        }
        for (index, mesh) in scene.meshes.iter().enumerate() {
            if plan.cells.iter().any(|c| c.meshes.contains(&index)) {
                continue;
            }
            if mesh.indices.is_empty() {
                plan.skip(format!("mesh {:?}", mesh.name), "it has no triangles");
                continue;
            }
            let material =
                scene
                    .materials
                    .get(mesh.material)
                    .ok_or_else(|| PlanError::NoMaterial {
                        mesh: mesh.name.clone(),
                        material: mesh.material,
                        count: scene.materials.len(),
                    })?;
            used[mesh.material] = true;
            let heights = match &material.relief {
                None => None,
                Some(relief) => {
                    check_silhouettes(material, relief)?;
                    let (key, source, size) = height_source(
                        scene,
                        frame_heights,
                        material,
                        mesh.material,
                        relief.height,
                    )?;
                    let shadows = if casts_shadows {
                        relief.shadows.mode
                    } else {
                        ShadowMode::None
                    };
                    let mean = lod_mean(relief.method, relief.lod);
                    let reads = (shadows, relief.ao, mean);
                    Some(plan.height_for(key, source, size, relief.method, reads))
                }
            };
            let ao = match (material.relief, heights) {
                (Some(relief), Some(h)) if relief.ao.is_some() => {
                    let reach = material.layers.as_ref().map(layered_ao_reach);
                    Some(plan.ao_for(h, relief.ao, relief.depth_scale, reach))
                }
                _ => None,
            };
            let pipeline = plan.pipeline_for(material, casts_shadows);
            plan.draws.push(DrawPlan {
                mesh: index,
                material: mesh.material,
                pipeline,
                heights,
                ao,
                role: DrawRole::Surface,
            });
        }
        plan.note_unused(scene, &used);
        plan.note_passes(casts_shadows);
        plan.note_cells(scene);
        Ok(plan)
    }

    /// Adds a caster-only draw for each mesh the cells pass draws: its triangles, plain (the
    /// complex traces the mesh's own surface, not a relief), cast by the shadow pass only, so
    /// that a mesh drawn through cells shadows others and itself. Called when shadow maps are
    /// planned, so a scene without them uploads nothing for it.
    pub(in crate::render) fn cast_cells_meshes(&mut self, scene: &Scene) {
        let meshes: Vec<usize> = self.cells.iter().flat_map(|c| c.meshes.clone()).collect();
        for index in meshes {
            self.cast_cells_mesh(scene, index);
        }
    }

    fn cast_cells_mesh(&mut self, scene: &Scene, index: usize) {
        let mesh = &scene.meshes[index];
        let Some(material) = scene.materials.get(mesh.material) else {
            return;
        };
        if mesh.indices.is_empty() {
            return;
        }
        let plain = Material {
            relief: None,
            ..material.clone()
        };
        let pipeline = self.pipeline_for(&plain, false);
        self.draws.push(DrawPlan {
            mesh: index,
            material: mesh.material,
            pipeline,
            heights: None,
            ao: None,
            role: DrawRole::CasterOnly,
        });
    }

    /// The draws the surface pass shades.
    pub fn surface_draws(&self) -> impl Iterator<Item = &DrawPlan> {
        self.draws.iter().filter(|d| d.role == DrawRole::Surface)
    }

    /// The index of the pipeline `material` draws with, added if no draw used it before.
    fn pipeline_for(&mut self, material: &Material, casts_shadows: bool) -> usize {
        let pipeline = PipelineKey {
            method: material.relief.map(|r| r.method),
            max_steps: material.relief.and_then(|r| r.budget),
            double_sided: material.double_sided,
            blend: material.alpha_mode == AlphaMode::Blend,
            shadows: match material.relief {
                Some(relief) if casts_shadows => relief.shadows,
                _ => ShadowSettings::new(ShadowMode::None),
            },
            lod: material.relief.and_then(|r| r.lod),
            layers: material
                .relief
                .is_some_and(|r| r.height == HeightSource::Layers),
            curved: material
                .relief
                .is_some_and(|r| r.silhouettes == Silhouettes::Curved),
            shells: material
                .relief
                .is_some_and(|r| r.silhouettes == Silhouettes::Shells),
            // Plain meshes write their own depth; the switch is relief's.
            write_depth: material.relief.is_none_or(|r| r.write_depth),
        };
        match self.pipelines.iter().position(|p| *p == pipeline) {
            Some(k) => k,
            None => {
                self.pipelines.push(pipeline);
                self.pipelines.len() - 1
            }
        }
    }

    /// The index of the height plan for `key` read by `method`, added or widened as needed.
    fn height_for(
        &mut self,
        key: HeightKey,
        source: String,
        size: (u32, u32),
        method: Method,
        (shadows, ao, (mean_binding, mean_pyramid)): (ShadowMode, AoMode, (bool, bool)),
    ) -> usize {
        let pyramid = method.info().reads_pyramid()
            || shadows.reads_pyramid()
            || matches!(ao, AoMode::Horizon { .. });
        let map = method.info().method_map();
        let found = self
            .heights
            .iter()
            .position(|h| h.key == key && h.map == map && h.mean_binding == mean_binding);
        match found {
            Some(k) => {
                self.heights[k].pyramid |= pyramid;
                self.heights[k].mean_pyramid |= mean_pyramid;
                k
            }
            None => {
                self.heights.push(HeightPlan {
                    key,
                    source,
                    size,
                    pyramid,
                    map,
                    map_method: map.map(|_| method),
                    mean_binding,
                    mean_pyramid,
                });
                self.heights.len() - 1
            }
        }
    }

    /// The index of the AO map of height map `heights` in `mode` at `depth_scale`, added if new.
    fn ao_for(
        &mut self,
        heights: usize,
        mode: AoMode,
        depth_scale: f32,
        reach_texels: Option<f32>,
    ) -> usize {
        let wanted = AoPlan {
            heights,
            mode,
            depth_scale,
            reach_texels,
        };
        match self.ao_maps.iter().position(|a| *a == wanted) {
            Some(k) => k,
            None => {
                self.ao_maps.push(wanted);
                self.ao_maps.len() - 1
            }
        }
    }

    /// Adds `pass` before the scene's drawing (the first cells or surface pass), since what it
    /// makes (shadow maps, occluder bounds) is read there.
    pub(in crate::render) fn insert_before_scene(&mut self, pass: Pass, why: String) {
        let at = self
            .passes
            .iter()
            .position(|p| matches!(p.pass, Pass::Cells | Pass::Surface))
            .unwrap_or(self.passes.len());
        self.passes.insert(at, PassPlan { pass, why });
    }

    pub(in crate::render) fn skip(&mut self, what: impl Into<String>, why: impl Into<String>) {
        self.skipped.push(Skipped {
            what: what.into(),
            why: why.into(),
        });
    }

    fn note_unused(&mut self, scene: &Scene, used: &[bool]) {
        for (material, _) in scene.materials.iter().zip(used).filter(|(_, u)| !**u) {
            self.skip(
                format!("material {:?}", material.name),
                "no drawn mesh uses it: no textures or maps uploaded for it",
            );
        }
        let used_methods: Vec<Method> = self.pipelines.iter().filter_map(|p| p.method).collect();
        for kind in MapKind::ALL {
            let built = self
                .heights
                .iter()
                .any(|h| h.map == Some(kind) || (kind == MapKind::MaxPyramid && h.pyramid));
            if built {
                continue;
            }
            let readers: Vec<&str> = Method::all()
                .filter(|m| m.info().needs.contains(&kind))
                .map(|m| m.id())
                .collect();
            let why = if used_methods.is_empty() {
                "no material has relief".to_owned()
            } else {
                format!(
                    "only {} reads it; the scene uses {}",
                    readers.join(", "),
                    unique_ids(&used_methods)
                )
            };
            self.skip(kind.name(), why);
        }
        if !self.pipelines.iter().any(|p| p.method.is_none()) {
            self.skip("surface.frag:plain", "every drawn material has relief");
        }
        if self.lights.len() > MAX_LIGHTS {
            self.skip(
                format!("lights beyond the first {MAX_LIGHTS}"),
                format!("the surface shader reads {MAX_LIGHTS} lights"),
            );
        }
    }

    fn note_passes(&mut self, casts_shadows: bool) {
        let blended = |h: &&HeightPlan| matches!(h.key, HeightKey::Layers { .. });
        let pyramids = self
            .heights
            .iter()
            .filter(|h| {
                if blended(h) {
                    h.mean_pyramid
                } else {
                    h.pyramid
                }
            })
            .count();
        let layered = self.heights.iter().filter(blended).count();
        if layered > 0 {
            self.skip(
                format!("{} for {layered} layered height map(s)", Pass::Pyramid.name()),
                "a layered material's conservative pyramid is blended from its layers' and weights' pyramids when they are uploaded (maps: blended pyramid); with LOD the pass still builds its averaged pyramid",
            );
        }
        if pyramids > 0 {
            self.passes.push(PassPlan {
                pass: Pass::Pyramid,
                why: format!(
                    "{pyramids} height map(s) whose method, shadows or AO read the max pyramid{}",
                    lod_note::built(&self.heights)
                ),
            });
        }
        if self.ao_maps.is_empty() {
            self.skip(
                Pass::AmbientOcclusion.name(),
                "no drawn relief material asks for AO (extras.relief.ao, --ao); glTF occlusion textures are applied in the surface pass",
            );
        } else {
            let modes: Vec<String> = self.ao_maps.iter().map(|a| a.mode.to_string()).collect();
            self.passes.push(PassPlan {
                pass: Pass::AmbientOcclusion,
                why: format!(
                    "{} AO map(s) ({}) for relief materials, built once in the first frame",
                    self.ao_maps.len(),
                    modes.join(", ")
                ),
            });
        }
        if let Some(why) = lod_note::skipped(&self.pipelines, &self.heights) {
            self.skip(lod_note::MEAN_PYRAMID, why);
        }
        self.passes.push(PassPlan {
            pass: Pass::Surface,
            why: format!("{} draw(s)", self.surface_draws().count()),
        });
        let mut modes: Vec<&str> = Vec::new();
        for p in &self.pipelines {
            let mode = p.shadows.mode;
            if mode.is_some() && !modes.contains(&mode.id()) {
                modes.push(mode.id());
            }
        }
        let relief = self.pipelines.iter().any(|p| p.method.is_some());
        if !modes.is_empty() {
            self.passes.push(PassPlan {
                pass: Pass::SelfShadowRays,
                why: format!(
                    "relief materials under a light that casts shadows, mode {} (traced in the surface pass)",
                    modes.join(", ")
                ),
            });
        } else if casts_shadows && relief {
            self.skip(
                Pass::SelfShadowRays.name(),
                "every drawn relief material has shadows \"none\"",
            );
        } else if casts_shadows {
            self.skip(Pass::SelfShadowRays.name(), "no drawn material has relief");
        } else {
            self.skip(Pass::SelfShadowRays.name(), "no light casts shadows");
        }
    }
}

/// Whether a material's draws bind binding 4 and whether they read the averaged pyramid there.
fn lod_mean(method: Method, lod: Option<Lod>) -> (bool, bool) {
    let binding = lod.is_some() && method.info().reads_pyramid();
    (
        binding,
        binding && lod.is_some_and(|l| l.uses_mean_pyramid()),
    )
}

fn unique_ids(methods: &[Method]) -> String {
    let mut ids: Vec<&str> = methods.iter().map(|m| m.id()).collect();
    ids.dedup();
    ids.sort_unstable();
    ids.dedup();
    ids.join(", ")
}

#[cfg(test)]
#[path = "plan_tests.rs"]
mod tests;
