//! The surface pass: set 0 per height map and frame slot (frame uniforms, heights, the method's
//! map) plus a plain one per slot, set 1 per material, the pipelines the plan lists, its draws
//! (`mesh_draws`: uploaded meshes and shells with their sets), and the draw recording with
//! dynamic rendering: opaque draws first, then blended ones back to front. Everything here is
//! built once per scene; a frame only rewrites its slot's uniforms.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;

use super::draw_bounds::{mesh_bounds, world_bounds};
use super::material_set::MaterialSets;
use super::mesh_draws::{mesh_draws, MeshDraw};
use super::occluders::occluder_layout;
use super::scene_ao::SceneAo;
use super::scene_textures::SceneTextures;
use super::surface_pipelines::{
    caster_pipelines, occluder_pipelines, surface_pipelines, PipelineLayouts,
};
use super::work_counters::WorkCounterBuffer;
use crate::render::environment::{stand_in_binds, EnvironmentLight};
use crate::render::heights::height_resources::HeightResources;
use crate::render::kit::caster_draws::CasterDraws;
use crate::render::kit::frame_uniforms::FrameUniforms;
use crate::render::kit::set_layouts::{material_layout, plain_frame_layout, set0_layout};
use crate::render::plan::frame_plan::{PipelineKey, Plan};
use crate::render::shader_interface::{
    BINDING_FRAME, BINDING_HEIGHT_LINEAR, BINDING_HEIGHT_MEAN, BINDING_HEIGHT_POINT,
    BINDING_METHOD_MAP, BINDING_OCCLUDER_BOUNDS, BINDING_WORK_COUNTS, SET_OCCLUDERS,
};
use crate::render::shadows::shadow_atlas::ShadowAtlas;
use crate::render::shells::shell_upload::BuiltShell;
use crate::render::terrain::layer_set::{layer_layout, LayerSets};
use crate::scene::{Frustum, Mesh, Scene};
use crate::vk::{
    Bind, Buffer, Context, DescriptorLayout, DescriptorPool, DescriptorSet, ImageView, Pipeline,
    Recording, Sampler, VkError, VkResult,
};

/// Everything the surface pass needs for one scene.
pub struct SurfacePass {
    /// By plan pipeline; `None` for a key only caster-only draws use.
    pipelines: Vec<Option<Pipeline>>,
    draws: Vec<MeshDraw>,
    materials: MaterialSets,
    layers: LayerSets,
    _textures: SceneTextures,
    _frame_pool: DescriptorPool,
    /// The plain variant's uniforms, one per frame slot (empty when nothing is drawn plain).
    plain_uniforms: Vec<Buffer>,
    /// Set 0 over them, per frame slot.
    plain_sets: Vec<DescriptorSet>,
    /// By plan pipeline: the pipeline its draws cast shadows with, when some map has them as
    /// casters.
    casters: Vec<Option<Pipeline>>,
    /// The meshes drawn as prism shells.
    shells: Vec<BuiltShell>,
    /// By plan pipeline: the pipeline its occluding draws write their bounds with.
    occluders: Vec<Option<Pipeline>>,
    /// Set 3 of the relief variants (the occluder bounds).
    occluder_layout: DescriptorLayout,
    /// By plan pipeline: whether it is a relief variant, which binds set 3.
    reads_occluders: Vec<bool>,
    /// Without the occluder pass, the set 3 relief variants bind: the white texture, which
    /// they never read (`SPEC_OCCLUDER_TAPS` 0), and its pool.
    no_occluders: Option<(DescriptorSet, DescriptorPool)>,
    _layouts: Vec<DescriptorLayout>,
}

/// The set 0 layouts: plain (uniforms only), heights, heights with a method map, heights with
/// the averaged pyramid (LOD variants of pyramid methods, binding 4).
pub(super) struct FrameLayouts {
    plain: DescriptorLayout,
    heights: DescriptorLayout,
    heights_and_map: DescriptorLayout,
    heights_and_mean: DescriptorLayout,
}

impl FrameLayouts {
    /// The set 0 layout of draws reading `h`: its bindings grow with the maps it holds.
    fn for_heights(&self, h: &HeightResources) -> &DescriptorLayout {
        if h.has_mean_binding() {
            &self.heights_and_mean
        } else if h.has_map() {
            &self.heights_and_map
        } else {
            &self.heights
        }
    }

    /// The set 0 layout of pipeline `key`: plain without a method, else the heights with what
    /// its method reads.
    pub(super) fn for_key(&self, key: &PipelineKey) -> &DescriptorLayout {
        match key.method {
            None => &self.plain,
            Some(_) if key.binds_mean_pyramid() => &self.heights_and_mean,
            Some(m) if m.info().method_map().is_some() => &self.heights_and_map,
            Some(_) => &self.heights,
        }
    }

    /// Set 0 of each height map, one per frame slot, with the scene's binds (`scene_binds`:
    /// the shadow atlas and the environment maps).
    fn height_sets(
        &self,
        pool: &DescriptorPool,
        heights: &[HeightResources],
        scene_binds: &[Bind],
        slots: usize,
    ) -> VkResult<Vec<Vec<DescriptorSet>>> {
        heights
            .iter()
            .map(|h| {
                let layout = self.for_heights(h);
                (0..slots)
                    .map(|slot| {
                        let mut binds = h.slot_binds(slot);
                        binds.extend_from_slice(scene_binds);
                        pool.allocate(layout, &binds)
                    })
                    .collect::<VkResult<Vec<_>>>()
            })
            .collect()
    }
}

/// Which materials are drawn (by meshes or cells), and the AO map each relief material reads.
fn drawn_materials(
    scene: &Scene,
    plan: &Plan,
    ao: &SceneAo,
) -> (Vec<bool>, Vec<Option<(ImageView, Sampler)>>) {
    let mut drawn = vec![false; scene.materials.len()];
    let mut relief_ao = vec![None; scene.materials.len()];
    for d in &plan.draws {
        drawn[d.material] = true;
        relief_ao[d.material] = d.ao.and_then(|k| ao.binding(k));
    }
    for c in &plan.cells {
        drawn[c.material] = true;
    }
    (drawn, relief_ao)
}

/// Which materials some draw shades with layers.
fn layered_materials(scene: &Scene, plan: &Plan) -> Vec<bool> {
    let mut layered = vec![false; scene.materials.len()];
    for d in plan
        .draws
        .iter()
        .filter(|d| plan.pipelines[d.pipeline].layers)
    {
        layered[d.material] = true;
    }
    layered
}

/// The uniforms of the plain set 0, one buffer per frame slot.
fn plain_uniform_buffers(
    ctx: &Arc<Context>,
    uniforms: &FrameUniforms,
    slots: usize,
) -> VkResult<Vec<Buffer>> {
    (0..slots)
        .map(|slot| {
            Buffer::with_data(
                ctx,
                bytemuck::bytes_of(uniforms),
                vk::BufferUsageFlags::UNIFORM_BUFFER,
                &format!("plain frame uniforms {slot}"),
            )
        })
        .collect::<VkResult<Vec<_>>>()
}

/// Fails unless every height map has uniforms for exactly `slots` frame slots.
fn check_height_slots(heights: &[HeightResources], slots: usize) -> VkResult<()> {
    match heights.iter().find(|h| h.slots() != slots) {
        Some(h) => Err(VkError::Invalid(format!(
            "height uniforms for {} frame slots, the pass has {slots}",
            h.slots()
        ))),
        None => Ok(()),
    }
}

/// The sets of the materials `plan` draws, each relief material with the AO map it reads.
fn material_sets(
    ctx: &Arc<Context>,
    scene: &Scene,
    plan: &Plan,
    ao: &SceneAo,
    layout: &DescriptorLayout,
    textures: &mut SceneTextures,
) -> VkResult<MaterialSets> {
    let (drawn, relief_ao) = drawn_materials(scene, plan, ao);
    MaterialSets::new(
        ctx,
        layout,
        &scene.materials,
        &scene.images,
        &drawn,
        &relief_ao,
        textures,
    )
}

/// The binds every set 0 ends with: the shadow atlas and the environment maps. Draws bind them
/// whether or not the frame has them; without them they bind `stand_in` (the white texture),
/// which no shader then reads.
fn scene_binds<'a>(
    stand_in: &'a (ImageView, Sampler),
    atlas: &'a ShadowAtlas,
    environment: Option<&'a EnvironmentLight>,
) -> Vec<Bind<'a>> {
    let mut binds = vec![atlas.bind(stand_in)];
    match environment {
        Some(e) => binds.extend(e.binds()),
        None => binds.extend(stand_in_binds(stand_in)),
    }
    binds
}

/// What the plain set 0 is built from.
struct PlainSetInputs<'a> {
    uniforms: &'a FrameUniforms,
    slots: usize,
    pool: &'a DescriptorPool,
    layout: &'a DescriptorLayout,
    scene_binds: &'a [Bind<'a>],
}

/// The plain set 0's uniform buffers and sets, one per frame slot; none when nothing of `plan`
/// reads it (the cells pass and the lighting pass do, besides draws without a method).
fn plain_frame_sets(
    ctx: &Arc<Context>,
    plan: &Plan,
    inputs: &PlainSetInputs,
) -> VkResult<(Vec<Buffer>, Vec<DescriptorSet>)> {
    let plain = plan.pipelines.iter().any(|p| p.method.is_none())
        || !plan.cells.is_empty()
        || plan.deferred;
    let plain_uniforms = if plain {
        plain_uniform_buffers(ctx, inputs.uniforms, inputs.slots)?
    } else {
        Vec::new()
    };
    let plain_sets = plain_uniforms
        .iter()
        .map(|b| {
            let mut binds = vec![Bind::Uniform(BINDING_FRAME, b)];
            binds.extend_from_slice(inputs.scene_binds);
            inputs.pool.allocate(inputs.layout, &binds)
        })
        .collect::<VkResult<Vec<_>>>()?;
    Ok((plain_uniforms, plain_sets))
}

/// Without the occluder pass, the set 3 that relief variants bind (over `stand_in`, which they
/// never read) and its pool; `None` with the occluder pass or without relief variants.
fn no_occluder_set(
    ctx: &Arc<Context>,
    plan: &Plan,
    occluder_layout: &DescriptorLayout,
    stand_in: &(ImageView, Sampler),
) -> VkResult<Option<(DescriptorSet, DescriptorPool)>> {
    (!plan.occluders && plan.pipelines.iter().any(|k| k.method.is_some()))
        .then(|| -> VkResult<_> {
            let pool = DescriptorPool::new(ctx, 1, 1, "no occluder bounds set")?;
            let counters = WorkCounterBuffer::new(ctx, (1, 1), false)?;
            let binds = [
                Bind::Texture(BINDING_OCCLUDER_BOUNDS, &stand_in.0, &stand_in.1),
                Bind::Storage(BINDING_WORK_COUNTS, counters.buffer()),
            ];
            Ok((pool.allocate(occluder_layout, &binds)?, pool))
        })
        .transpose()
}

/// The set 0 layouts, created.
fn frame_layouts(ctx: &Arc<Context>) -> VkResult<FrameLayouts> {
    let heights = [BINDING_FRAME, BINDING_HEIGHT_POINT, BINDING_HEIGHT_LINEAR];
    let with = |extra| {
        [
            BINDING_FRAME,
            BINDING_HEIGHT_POINT,
            BINDING_HEIGHT_LINEAR,
            extra,
        ]
    };
    Ok(FrameLayouts {
        plain: plain_frame_layout(ctx)?,
        heights: set0_layout(ctx, &heights, "height layout")?,
        heights_and_map: set0_layout(ctx, &with(BINDING_METHOD_MAP), "height and map layout")?,
        heights_and_mean: set0_layout(
            ctx,
            &with(BINDING_HEIGHT_MEAN),
            "height and averaged pyramid layout",
        )?,
    })
}

impl SurfacePass {
    /// Uploads what `plan` draws of `scene` and builds the pipelines it lists (and the caster
    /// pipelines of its shadow maps), with set 0 for each of `slots` frame slots. `heights[k]`
    /// is the uploaded height map of `plan.heights[k]`, with uniforms for every slot; `ao` holds
    /// the AO maps the materials read; `atlas` the shadow maps every draw looks up.
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        ctx: &Arc<Context>,
        scene: &Scene,
        plan: &Plan,
        heights: &[HeightResources],
        ao: &SceneAo,
        atlas: &ShadowAtlas,
        environment: Option<&EnvironmentLight>,
        uniforms: &FrameUniforms,
        slots: usize,
    ) -> VkResult<SurfacePass> {
        check_height_slots(heights, slots)?;
        let layouts = frame_layouts(ctx)?;
        let material_layout = material_layout(ctx)?;
        let mut textures = SceneTextures::new(ctx)?;
        let materials = material_sets(ctx, scene, plan, ao, &material_layout, &mut textures)?;
        let layer_layout = layer_layout(ctx)?;
        let layers = LayerSets::new(
            ctx,
            &layer_layout,
            &scene.materials,
            &scene.images,
            &layered_materials(scene, plan),
        )?;
        let sets = (heights.len() as u32 + 1) * slots as u32;
        let frame_pool = DescriptorPool::new(ctx, sets, 8 * sets, "frame sets")?;
        let stand_in = textures.white()?;
        let scene_binds = scene_binds(&stand_in, atlas, environment);
        let height_sets = layouts.height_sets(&frame_pool, heights, &scene_binds, slots)?;
        let plain = PlainSetInputs {
            uniforms,
            slots,
            pool: &frame_pool,
            layout: &layouts.plain,
            scene_binds: &scene_binds,
        };
        let (plain_uniforms, plain_sets) = plain_frame_sets(ctx, plan, &plain)?;
        let occluder_layout = occluder_layout(ctx)?;
        // Set 2 of relief variants without layers: nothing, so set 3 can follow it.
        let no_layers =
            DescriptorLayout::new(ctx, &[], vk::ShaderStageFlags::FRAGMENT, "no layers layout")?;
        let no_occluders = no_occluder_set(ctx, plan, &occluder_layout, &stand_in)?;
        let pipeline_layouts = PipelineLayouts {
            frame: &layouts,
            material: &material_layout,
            layers: &layer_layout,
            no_layers: &no_layers,
            occluders: &occluder_layout,
        };
        let pipelines = surface_pipelines(ctx, plan, &pipeline_layouts)?;
        let casters = caster_pipelines(ctx, plan, &pipeline_layouts)?;
        let (draws, shells) = mesh_draws(
            ctx,
            scene,
            plan,
            &height_sets,
            &plain_sets,
            &materials,
            &layers,
        )?;
        let occluders = occluder_pipelines(ctx, plan, &pipeline_layouts, &draws)?;
        Ok(SurfacePass {
            pipelines,
            draws,
            materials,
            layers,
            _frame_pool: frame_pool,
            plain_uniforms,
            plain_sets,
            casters,
            shells,
            occluders,
            occluder_layout,
            reads_occluders: plan.pipelines.iter().map(|k| k.method.is_some()).collect(),
            no_occluders,
            _layouts: vec![
                no_layers,
                layouts.plain,
                layouts.heights,
                layouts.heights_and_map,
                layouts.heights_and_mean,
                material_layout,
                layer_layout,
            ],
            _textures: textures,
        })
    }

    /// The meshes drawn as prism shells, with their prism counts and bytes.
    pub fn shells(&self) -> &[BuiltShell] {
        &self.shells
    }

    /// The splat image layered material `material` is shaded with, if it is drawn layered.
    pub fn layer_splat(&self, material: usize) -> Option<&crate::vk::Image> {
        self.layers.splat_image(material)
    }

    /// Draws `mesh` as scene mesh `index` from now on (an edited terrain tile): the same
    /// triangles over new vertices. The caller waits for every frame that drew the old ones.
    pub fn replace_vertices(
        &mut self,
        ctx: &Arc<Context>,
        index: usize,
        mesh: &Mesh,
    ) -> VkResult<()> {
        let Some(draw) = self.draws.iter_mut().find(|d| d.mesh == index) else {
            return Err(VkError::Invalid(format!("mesh {index} is not drawn")));
        };
        if mesh.indices.len() as u32 != draw.index_count {
            return Err(VkError::Invalid(format!(
                "mesh {:?}: {} indices replace {}",
                mesh.name,
                mesh.indices.len(),
                draw.index_count
            )));
        }
        draw.vertices = Buffer::with_data(
            ctx,
            bytemuck::cast_slice(&mesh.vertices),
            vk::BufferUsageFlags::VERTEX_BUFFER,
            &format!("{} vertices", mesh.name),
        )?;
        let (lo, hi) = mesh_bounds(&mesh.vertices);
        draw.center = mesh.transform.transform_point3((lo + hi) * 0.5);
        draw.bounds = world_bounds(mesh.transform, lo, hi);
        Ok(())
    }

    /// Set 0 without heights for frame slot `slot` (none when nothing reads it).
    pub fn plain_set(&self, slot: usize) -> Option<DescriptorSet> {
        self.plain_sets.get(slot).cloned()
    }

    /// The set of material `index`, if a draw of the plan reads it.
    pub fn material_set(&self, index: usize) -> Option<DescriptorSet> {
        self.materials.set(index)
    }

    /// Writes the plain variant's uniforms of frame slot `slot` (the height maps' own are
    /// written through their `HeightResources`).
    ///
    /// # Safety
    /// The slot's previous frame has finished on the GPU (its fence was waited for).
    pub unsafe fn write_uniforms(&mut self, slot: usize, uniforms: &FrameUniforms) -> VkResult<()> {
        match self.plain_uniforms.get_mut(slot) {
            // SAFETY: only the slot's frames bind its buffer, and the caller waited for them.
            Some(buffer) => unsafe { buffer.write(0, bytemuck::bytes_of(uniforms)) },
            None => Ok(()),
        }
    }

    /// Set 3 of the relief variants, which [`OccluderTargets`](super::occluders::OccluderTargets)
    /// allocate theirs from.
    pub fn occluder_layout(&self) -> &DescriptorLayout {
        &self.occluder_layout
    }

    /// Records the occluder pass's draws of frame slot `slot` that `frustum` may see, nearest
    /// to `eye` first (so the depth test rejects hidden polygons before they are shaded);
    /// returns how many it drew. Rendering into the occluder targets must have begun.
    pub fn record_occluders(
        &self,
        rec: &Recording,
        slot: usize,
        eye: Vec3,
        frustum: &Frustum,
    ) -> VkResult<usize> {
        let mut order: Vec<&MeshDraw> = self
            .draws
            .iter()
            .filter(|d| d.occludes && frustum.may_see_box(d.bounds.0, d.bounds.1))
            .collect();
        order.sort_by(|a, b| {
            let da = nearest_distance_squared(a.bounds, eye);
            let db = nearest_distance_squared(b.bounds, eye);
            da.total_cmp(&db)
        });
        let mut drawn = 0;
        for draw in order {
            let Some(pipeline) = self.occluders[draw.pipeline].as_ref() else {
                return Err(VkError::Invalid(format!(
                    "mesh {} has no occluder pipeline",
                    draw.mesh
                )));
            };
            let set = &draw.frame_sets[slot.min(draw.frame_sets.len() - 1)];
            pipeline.bind(rec, Some(set));
            pipeline.bind_set(rec, 1, &draw.material_set);
            pipeline.push(rec, bytemuck::bytes_of(&draw.push))?;
            rec.bind_mesh(&draw.vertices, &draw.indices);
            rec.draw_indexed(draw.index_count);
            drawn += 1;
        }
        Ok(drawn)
    }

    /// Records every draw of frame slot `slot` that `frustum` may see, from `eye`: opaque ones in
    /// plan order, then `behind` (what shows where no opaque surface was drawn), then blended
    /// ones from far to near; returns how many were skipped as out of view. Relief draws read the
    /// occluder bounds through `occluders` (required when some draw is relief). Rendering must
    /// have begun with the targets' formats.
    pub fn record_draws(
        &self,
        rec: &Recording,
        slot: usize,
        view: (Vec3, &Frustum),
        occluders: Option<&DescriptorSet>,
        behind: impl FnOnce(&Recording) -> VkResult<()>,
    ) -> VkResult<usize> {
        let (eye, frustum) = view;
        let occluders = occluders.or(self.no_occluders.as_ref().map(|(set, _)| set));
        let shaded: Vec<&MeshDraw> = self.draws.iter().filter(|d| d.shaded).collect();
        let visible = |d: &&MeshDraw| frustum.may_see_box(d.bounds.0, d.bounds.1);
        let in_view: Vec<&MeshDraw> = shaded.iter().copied().filter(visible).collect();
        let culled = shaded.len() - in_view.len();
        let opaque: Vec<&MeshDraw> = in_view.iter().copied().filter(|d| !d.blend).collect();
        let mut blended: Vec<&MeshDraw> = in_view.iter().copied().filter(|d| d.blend).collect();
        blended.sort_by(|a, b| {
            let da = a.center.distance_squared(eye);
            let db = b.center.distance_squared(eye);
            db.total_cmp(&da)
        });
        self.record_list(rec, slot, &opaque, occluders)?;
        behind(rec)?;
        self.record_list(rec, slot, &blended, occluders)?;
        Ok(culled)
    }

    /// Records `draws` of frame slot `slot` in order.
    fn record_list(
        &self,
        rec: &Recording,
        slot: usize,
        draws: &[&MeshDraw],
        occluders: Option<&DescriptorSet>,
    ) -> VkResult<()> {
        for &draw in draws {
            let Some(pipeline) = self.pipelines[draw.pipeline].as_ref() else {
                return Err(VkError::Invalid(format!(
                    "mesh {} has no surface pipeline",
                    draw.mesh
                )));
            };
            let set = &draw.frame_sets[slot.min(draw.frame_sets.len() - 1)];
            pipeline.bind(rec, Some(set));
            pipeline.bind_set(rec, 1, &draw.material_set);
            if let Some(layers) = &draw.layer_set {
                pipeline.bind_set(rec, 2, layers);
            }
            if self.reads_occluders[draw.pipeline] {
                let Some(bounds) = occluders else {
                    return Err(VkError::Invalid(format!(
                        "mesh {} is relief, and the frame has no occluder bounds",
                        draw.mesh
                    )));
                };
                pipeline.bind_set(rec, SET_OCCLUDERS, bounds);
            }
            pipeline.push(rec, bytemuck::bytes_of(&draw.push))?;
            rec.bind_mesh(&draw.vertices, &draw.indices);
            rec.draw_indexed(draw.index_count);
        }
        Ok(())
    }
}

/// The squared distance from `eye` to the nearest point of the box `bounds` (0 inside it).
fn nearest_distance_squared(bounds: (Vec3, Vec3), eye: Vec3) -> f32 {
    eye.clamp(bounds.0, bounds.1).distance_squared(eye)
}

impl CasterDraws for SurfacePass {
    /// Depth rendering into the view's tile must have begun.
    fn record_casters(
        &self,
        rec: &Recording,
        slot: usize,
        tile: u32,
        draws: &[usize],
        frustum: &Frustum,
    ) -> VkResult<usize> {
        let mut culled = 0;
        for &k in draws {
            let draw = &self.draws[k];
            let Some(pipeline) = self.casters[draw.pipeline].as_ref() else {
                return Err(VkError::Invalid(format!("draw {k} has no caster pipeline")));
            };
            let pad = Vec3::splat(draw.caster_pad);
            if !frustum.may_see_box(draw.bounds.0 - pad, draw.bounds.1 + pad) {
                culled += 1;
                continue;
            }
            let set = &draw.frame_sets[slot.min(draw.frame_sets.len() - 1)];
            pipeline.bind(rec, Some(set));
            pipeline.bind_set(rec, 1, &draw.material_set);
            pipeline.push(rec, bytemuck::bytes_of(&draw.push.for_tile(tile)))?;
            rec.bind_mesh(&draw.vertices, &draw.indices);
            rec.draw_indexed(draw.index_count);
        }
        Ok(culled)
    }
}
