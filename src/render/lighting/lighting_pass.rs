//! The lighting pass (`shaders/passes/lighting.comp`): after the scene's rendering ends, one
//! invocation per pixel lights what the deferred surface variants drew, reading the G-buffer's
//! albedo and the shading inputs as storage images and adding to the radiance in place; set 0 is
//! the frame's plain set (uniforms, shadow atlas, environment maps), as the surface pass binds.

use std::sync::Arc;

use ash::vk;

use super::shading_inputs::ShadingInputs;
use crate::method::Method;
use crate::render::kit::set_layouts::plain_frame_layout;
use crate::render::plan::frame_plan::Plan;
use crate::render::shader_interface::{
    TracedLightingParams, BINDING_LIGHTING_FRAME, BINDING_LIGHTING_MATERIAL,
    BINDING_LIGHTING_MOTION, BINDING_LIGHTING_POINT, BINDING_LIGHTING_RADIANCE,
    BINDING_LIGHTING_SELF_SHADOW, BINDING_OCCLUSION_PRISMS, BINDING_OCCLUSION_SCENE,
    SPEC_BUDGET_EXTENT_LIMIT, SPEC_BUDGET_LEAF_EXACT, SPEC_BUDGET_MAX_STEPS,
    SPEC_BUDGET_REFINE_STEPS, SPEC_SHADOW_FILTER,
};
use crate::render::shadows::shadow_plan::shadow_filter_max;
use crate::render::traced::traced_scene::TracedScene;
use crate::shaders;
use crate::vk::{
    compute_pipeline, memory_barrier, transition_images, Bind, Context, DescriptorLayout,
    DescriptorPool, DescriptorSet, Image, ImageTransition, Pipeline, Recording, SpecConstants,
    VkError, VkResult,
};

/// Pixels per workgroup along each axis (`local_size` in lighting.comp).
const TILE: u32 = 8;

/// The images the pass reads and writes, all single-sample, in the colour attachment layout
/// when it begins and ends.
pub struct LitImages<'a> {
    /// The radiance, holding the surfaces' emission.
    pub radiance: &'a Image,
    /// The G-buffer's albedo and occlusion.
    pub material: &'a Image,
    /// The G-buffer's motion and shadow share.
    pub motion: &'a Image,
    /// The shading inputs.
    pub inputs: &'a ShadingInputs,
}

impl<'a> LitImages<'a> {
    fn all(&self) -> Vec<&'a Image> {
        let mut images = vec![self.radiance, self.material, self.motion];
        images.extend(self.inputs.images());
        images
    }
}

/// The lighting pass over `images` (the frame's targets' own) when `plan` is lit deferred,
/// looking shadow maps up as the plan's lights do, or with `traced` casting shadow rays.
pub fn lighting_pass_for(
    ctx: &Arc<Context>,
    plan: &Plan,
    images: Option<LitImages>,
    traced: Option<TracedShadows>,
) -> VkResult<Option<LightingPass>> {
    if !plan.deferred {
        return Ok(None);
    }
    let images = images.ok_or_else(|| {
        VkError::Invalid("deferred lighting on targets made without shading inputs".into())
    })?;
    LightingPass::new(ctx, &images, shadow_filter_max(plan), traced).map(Some)
}

/// Shadows by ray query: the scene's structures, and how its rays are cast.
pub struct TracedShadows<'a> {
    /// The scene's occluders on the GPU.
    pub scene: &'a TracedScene,
    /// How far a shadow ray starts off its receiver, along the ray (world units; the exact
    /// reference's own offset for the scene).
    pub offset: f32,
    /// Rays per side of the grid over a light with a size.
    pub samples_per_side: u32,
}

/// The pass's pipeline and its set over one frame's targets.
pub struct LightingPass {
    // Declared first so they are destroyed before the layouts they were made with.
    pipeline: Pipeline,
    set: DescriptorSet,
    /// With ray-traced shadows: set 2 (the scene's structures, prisms and height map) and the
    /// push constants.
    traced: Option<(DescriptorSet, TracedLightingParams)>,
    _pool: DescriptorPool,
    _layouts: Vec<DescriptorLayout>,
    size: (u32, u32),
}

impl LightingPass {
    /// The pass over `images`, looking shadow maps up with filters up to `shadow_filter`
    /// (`SPEC_SHADOW_FILTER`).
    pub fn new(
        ctx: &Arc<Context>,
        images: &LitImages,
        shadow_filter: u32,
        traced: Option<TracedShadows>,
    ) -> VkResult<LightingPass> {
        let frame_layout = plain_frame_layout(ctx)?;
        let storage = vk::DescriptorType::STORAGE_IMAGE;
        let bindings = [
            BINDING_LIGHTING_RADIANCE,
            BINDING_LIGHTING_MATERIAL,
            BINDING_LIGHTING_MOTION,
            BINDING_LIGHTING_POINT,
            BINDING_LIGHTING_FRAME,
            BINDING_LIGHTING_SELF_SHADOW,
        ];
        let set_layout = DescriptorLayout::new(
            ctx,
            &bindings.map(|b| (b, storage)),
            vk::ShaderStageFlags::COMPUTE,
            "lighting layout",
        )?;
        let key = if traced.is_some() {
            "lighting.comp:traced"
        } else {
            "lighting.comp"
        };
        let spirv = shaders::spirv(key)
            .ok_or_else(|| VkError::Invalid(format!("no compiled shader {key}")))?;
        // The prisms are walked as the traced path walks them: maxmip's budget.
        let budget = Method::MAXMIP.info().default_budget;
        let spec = SpecConstants::default()
            .u32(SPEC_SHADOW_FILTER, shadow_filter)
            .u32(SPEC_BUDGET_MAX_STEPS, budget.max_steps)
            .u32(SPEC_BUDGET_REFINE_STEPS, budget.refine_steps)
            .u32(SPEC_BUDGET_LEAF_EXACT, budget.leaf.spec_value())
            .u32(SPEC_BUDGET_EXTENT_LIMIT, budget.extent_limit);
        let traced_layout = traced
            .as_ref()
            .map(|t| {
                let mut list = t.scene.heights().layout_bindings();
                list.extend([
                    (
                        BINDING_OCCLUSION_SCENE,
                        vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
                    ),
                    (BINDING_OCCLUSION_PRISMS, vk::DescriptorType::STORAGE_BUFFER),
                ]);
                DescriptorLayout::new(
                    ctx,
                    &list,
                    vk::ShaderStageFlags::COMPUTE,
                    "traced lighting layout",
                )
            })
            .transpose()?;
        let mut layouts = vec![&frame_layout, &set_layout];
        layouts.extend(traced_layout.as_ref());
        let push = if traced.is_some() {
            std::mem::size_of::<TracedLightingParams>() as u32
        } else {
            0
        };
        let pipeline = compute_pipeline(ctx, spirv, &layouts, push, &spec, key)?;
        let pool = DescriptorPool::new(ctx, 2, bindings.len() as u32, "lighting sets")?;
        let binds: Vec<_> = bindings
            .iter()
            .zip(images.all())
            .map(|(&b, image)| Bind::StorageImage(b, image.view()))
            .collect();
        let set = pool.allocate(&set_layout, &binds)?;
        let traced_set = match (&traced, &traced_layout) {
            (Some(t), Some(layout)) => {
                let mut binds = t.scene.heights().binds();
                binds.extend([
                    Bind::Structure(BINDING_OCCLUSION_SCENE, t.scene.top()),
                    Bind::Storage(BINDING_OCCLUSION_PRISMS, t.scene.records()),
                ]);
                let params = TracedLightingParams {
                    height_info: t.scene.heights().shader_info(),
                    rays: [t.offset, t.samples_per_side.max(1) as f32, 0.0, 0.0],
                };
                Some((pool.allocate(layout, &binds)?, params))
            }
            _ => None,
        };
        let d = images.radiance.desc();
        let mut kept = vec![frame_layout, set_layout];
        kept.extend(traced_layout);
        Ok(LightingPass {
            pipeline,
            set,
            traced: traced_set,
            _pool: pool,
            _layouts: kept,
            size: (d.width, d.height),
        })
    }

    /// Lights the frame: `images` (those the pass was made over) from the colour attachment
    /// layout into the general one and back around one dispatch, `frame_set` the frame slot's
    /// plain set 0.
    pub fn record(
        &self,
        rec: &Recording,
        frame_set: &DescriptorSet,
        images: &LitImages,
    ) -> VkResult<()> {
        let drawn = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        let lit = (
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        // The shadow atlas and environment maps were made visible to fragment shaders; the
        // compute stage reads them too.
        memory_barrier(
            rec,
            drawn,
            (
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_SAMPLED_READ,
            ),
        );
        let to_general = (
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            vk::ImageLayout::GENERAL,
        );
        let all = images.all();
        let before: Vec<_> = all
            .iter()
            .map(|&image| ImageTransition::color(image, to_general, drawn, lit))
            .collect();
        transition_images(rec, &before);
        self.pipeline.bind(rec, Some(frame_set));
        self.pipeline.bind_set(rec, 1, &self.set);
        if let Some((set, params)) = &self.traced {
            self.pipeline.bind_set(rec, 2, set);
            self.pipeline.push(rec, bytemuck::bytes_of(params))?;
        }
        let (w, h) = self.size;
        rec.dispatch([w.div_ceil(TILE), h.div_ceil(TILE), 1]);
        // Back to where the rendering left them, so what follows (copies, the tone map) reads
        // them as it reads a frame lit forward.
        let back = (to_general.1, to_general.0);
        let attachment = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE | vk::AccessFlags2::COLOR_ATTACHMENT_READ,
        );
        let after: Vec<_> = all
            .iter()
            .map(|&image| ImageTransition::color(image, back, lit, attachment))
            .collect();
        transition_images(rec, &after);
        Ok(())
    }
}
