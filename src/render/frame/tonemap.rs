//! The tone-mapping pass: the scene passes draw linear radiance into a half-float target, and one
//! full-frame pass scales it by the exposure, maps it into [0, 1] with the chosen curve (the
//! kit's `tone_curves`) and writes the sRGB frame (encoded once, by the hardware on write).

use std::sync::Arc;

use ash::vk;

use crate::render::kit::tone_curves::ToneMapping;
use crate::render::shader_interface::ToneMapPush;
use crate::shaders;
use crate::vk::{
    graphics_pipeline, Bind, Context, DescriptorLayout, DescriptorPool, DescriptorSet,
    GraphicsDesc, ImageView, Pipeline, Recording, Sampler, SpecConstants, VkError, VkResult,
};

/// The full-frame pass: its pipeline, set layout and sampler; each target set owns its set.
pub struct ToneMapPass {
    pipeline: Pipeline,
    layout: DescriptorLayout,
    sampler: Sampler,
    /// Samples per texel of the radiance it reads.
    samples: u32,
}

impl ToneMapPass {
    /// The pass writing into `color_format` targets from a radiance of `samples` samples per
    /// texel: with more than one, the pass is also the resolve, tone mapping every sample before
    /// averaging them (`tonemap_resolve.frag`).
    pub fn new(
        ctx: &Arc<Context>,
        color_format: vk::Format,
        samples: u32,
    ) -> VkResult<ToneMapPass> {
        let missing = |k: &str| VkError::Invalid(format!("no compiled shader {k}"));
        let vertex = shaders::spirv("tonemap.vert").ok_or_else(|| missing("tonemap.vert"))?;
        let key = if samples > 1 {
            "tonemap_resolve.frag"
        } else {
            "tonemap.frag"
        };
        let fragment = shaders::spirv(key).ok_or_else(|| missing(key))?;
        let layout = DescriptorLayout::new(
            ctx,
            &[(0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER)],
            vk::ShaderStageFlags::FRAGMENT,
            "tone map layout",
        )?;
        let desc = GraphicsDesc {
            vertex,
            fragment,
            fragment_spec: &SpecConstants::default(),
            vertex_stride: 0,
            attributes: &[],
            color_format,
            extra_colors: &[],
            writes_extra: false,
            depth_format: vk::Format::UNDEFINED,
            cull: vk::CullModeFlags::NONE,
            set_layouts: &[&layout],
            push_bytes: std::mem::size_of::<ToneMapPush>() as u32,
            blend: false,
            samples: 1,
        };
        let pipeline = graphics_pipeline(ctx, &desc, "tone map")?;
        let sampler = Sampler::new(
            ctx,
            vk::Filter::NEAREST,
            vk::SamplerAddressMode::CLAMP_TO_EDGE,
            "tone map sampler",
        )?;
        Ok(ToneMapPass {
            pipeline,
            layout,
            sampler,
            samples,
        })
    }

    /// Samples per texel of the radiance the pass reads.
    pub fn samples(&self) -> u32 {
        self.samples
    }

    /// A set reading `hdr` (in `SHADER_READ_ONLY_OPTIMAL` when the pass runs), from `pool`.
    pub fn set_for(&self, pool: &DescriptorPool, hdr: &ImageView) -> VkResult<DescriptorSet> {
        pool.allocate(&self.layout, &[Bind::Texture(0, hdr, &self.sampler)])
    }

    /// Draws the full-frame triangle with `set`, whose radiance is `scale` times the frame's
    /// size along each axis (supersampling); rendering into the frame must have begun.
    pub fn record(
        &self,
        rec: &Recording,
        set: &DescriptorSet,
        mapping: ToneMapping,
        scale: u32,
    ) -> VkResult<()> {
        let push = ToneMapPush {
            exposure: mapping.exposure_ev.exp2(),
            curve: mapping.curve.shader_value(),
            scale,
            samples: self.samples,
        };
        self.pipeline.bind(rec, Some(set));
        self.pipeline.push(rec, bytemuck::bytes_of(&push))?;
        rec.draw(3);
        Ok(())
    }
}
