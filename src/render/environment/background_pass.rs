//! The environment drawn behind the scene (`--background environment`): one full-frame triangle
//! at the far plane, drawn into the radiance target after the opaque surfaces (so the depth test
//! leaves it only the pixels nothing covers) and before the blended ones, looking each pixel's
//! view direction up in the uploaded environment image.

use std::sync::Arc;

use ash::vk;
use glam::Mat4;

use super::environment_light::EnvironmentLight;
use crate::render::kit::formats::DEPTH_FORMAT;
use crate::render::kit::formats::HDR_FORMAT;
use crate::render::shader_interface::BackgroundPush;
use crate::shaders;
use crate::vk::{
    graphics_pipeline, Context, DescriptorLayout, DescriptorPool, DescriptorSet, GraphicsDesc,
    Pipeline, Recording, SpecConstants, VkError, VkResult,
};

/// The background's pipeline and the set reading the environment.
pub struct BackgroundPass {
    // Declared first: destroyed before the layout it was made with.
    pipeline: Pipeline,
    set: DescriptorSet,
    _layout: DescriptorLayout,
}

impl BackgroundPass {
    /// The pass drawing `light`'s environment (built with its source kept) into targets of
    /// `samples` samples per pixel, whose colour attachments after the radiance are
    /// `extra_colors` (it leaves them as cleared).
    pub fn new(
        ctx: &Arc<Context>,
        light: &EnvironmentLight,
        samples: u32,
        extra_colors: &[vk::Format],
    ) -> VkResult<BackgroundPass> {
        let bind = light.background_bind(0).ok_or_else(|| {
            VkError::Invalid("the environment was built without its image".into())
        })?;
        let missing = |k: &str| VkError::Invalid(format!("no compiled shader {k}"));
        let vertex = shaders::spirv("background.vert").ok_or_else(|| missing("background.vert"))?;
        let fragment =
            shaders::spirv("background.frag").ok_or_else(|| missing("background.frag"))?;
        let layout = DescriptorLayout::new(
            ctx,
            &[(0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER)],
            vk::ShaderStageFlags::FRAGMENT,
            "background layout",
        )?;
        let pool = DescriptorPool::new(ctx, 1, 1, "background set")?;
        let set = pool.allocate(&layout, &[bind])?;
        let desc = GraphicsDesc {
            vertex,
            fragment,
            fragment_spec: &SpecConstants::default(),
            vertex_stride: 0,
            attributes: &[],
            color_format: HDR_FORMAT,
            extra_colors,
            writes_extra: false,
            // At depth 1 it passes the cleared depth's less-or-equal test and leaves it at 1.
            depth_format: DEPTH_FORMAT,
            cull: vk::CullModeFlags::NONE,
            set_layouts: &[&layout],
            push_bytes: std::mem::size_of::<BackgroundPush>() as u32,
            blend: false,
            samples,
        };
        let pipeline = graphics_pipeline(ctx, &desc, "background")?;
        Ok(BackgroundPass {
            pipeline,
            set,
            _layout: layout,
        })
    }

    /// Draws the background seen through `view_proj`; the scene's rendering must have begun.
    pub fn record(&self, rec: &Recording, view_proj: Mat4) -> VkResult<()> {
        let push = BackgroundPush {
            inverse_view_proj: view_proj.inverse().to_cols_array_2d(),
        };
        self.pipeline.bind(rec, Some(&self.set));
        self.pipeline.push(rec, bytemuck::bytes_of(&push))?;
        rec.draw(3);
        Ok(())
    }
}
