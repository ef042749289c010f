//! The lighting pass (`shaders/passes/lighting.comp`): after the scene's rendering ends, one
//! invocation per pixel lights what the deferred surface variants drew, reading the G-buffer's
//! albedo and the shading inputs as storage images and adding to the radiance in place; set 0 is
//! the frame's plain set (uniforms, shadow atlas, environment maps), as the surface pass binds.

use std::sync::Arc;

use ash::vk;

use super::shading_inputs::ShadingInputs;
use crate::render::kit::set_layouts::plain_frame_layout;
use crate::render::plan::frame_plan::Plan;
use crate::render::shader_interface::{
    BINDING_LIGHTING_FRAME, BINDING_LIGHTING_MATERIAL, BINDING_LIGHTING_MOTION,
    BINDING_LIGHTING_POINT, BINDING_LIGHTING_RADIANCE, BINDING_LIGHTING_SELF_SHADOW,
    SPEC_SHADOW_FILTER,
};
use crate::render::shadows::shadow_plan::shadow_filter_max;
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
/// looking shadow maps up as the plan's lights do.
pub fn lighting_pass_for(
    ctx: &Arc<Context>,
    plan: &Plan,
    images: Option<LitImages>,
) -> VkResult<Option<LightingPass>> {
    if !plan.deferred {
        return Ok(None);
    }
    let images = images.ok_or_else(|| {
        VkError::Invalid("deferred lighting on targets made without shading inputs".into())
    })?;
    LightingPass::new(ctx, &images, shadow_filter_max(plan)).map(Some)
}

/// The pass's pipeline and its set over one frame's targets.
pub struct LightingPass {
    // Declared first so they are destroyed before the layouts they were made with.
    pipeline: Pipeline,
    set: DescriptorSet,
    _pool: DescriptorPool,
    _layouts: (DescriptorLayout, DescriptorLayout),
    size: (u32, u32),
}

impl LightingPass {
    /// The pass over `images`, looking shadow maps up with filters up to `shadow_filter`
    /// (`SPEC_SHADOW_FILTER`).
    pub fn new(
        ctx: &Arc<Context>,
        images: &LitImages,
        shadow_filter: u32,
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
        let key = "lighting.comp";
        let spirv = shaders::spirv(key)
            .ok_or_else(|| VkError::Invalid(format!("no compiled shader {key}")))?;
        let spec = SpecConstants::default().u32(SPEC_SHADOW_FILTER, shadow_filter);
        let pipeline = compute_pipeline(
            ctx,
            spirv,
            &[&frame_layout, &set_layout],
            0,
            &spec,
            "lighting",
        )?;
        let pool = DescriptorPool::new(ctx, 1, bindings.len() as u32, "lighting set")?;
        let binds: Vec<_> = bindings
            .iter()
            .zip(images.all())
            .map(|(&b, image)| Bind::StorageImage(b, image.view()))
            .collect();
        let set = pool.allocate(&set_layout, &binds)?;
        let d = images.radiance.desc();
        Ok(LightingPass {
            pipeline,
            set,
            _pool: pool,
            _layouts: (frame_layout, set_layout),
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
