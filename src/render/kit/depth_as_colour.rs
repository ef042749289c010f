//! A depth rendered twice: into a float colour image that later fragment shaders sample, and
//! into a depth attachment whose test keeps the nearest. The shadow atlas and the occluder
//! bounds are both made this way.

use std::sync::Arc;

use ash::vk;

use crate::vk::{
    transition_images, Context, Image, ImageDesc, ImageTransition, Recording, VkResult,
};

/// The sampled depths' format: one float per texel.
pub const DEPTH_COLOUR_FORMAT: vk::Format = vk::Format::R32_SFLOAT;
/// The depth test's format.
const TEST_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The sampled depths and their depth test, of one size.
pub struct DepthAsColour {
    /// What fragment shaders sample (cleared to 1, the far plane).
    pub depths: Image,
    /// The depth test's attachment, never sampled.
    test: Image,
}

impl DepthAsColour {
    /// Both images at `width` x `height`, named after `name`.
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32, name: &str) -> VkResult<DepthAsColour> {
        let desc = |format, usage, aspect| ImageDesc {
            width,
            height,
            format,
            mip_levels: 1,
            usage,
            aspect,
        };
        let depths = Image::new(
            ctx,
            desc(
                DEPTH_COLOUR_FORMAT,
                vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED,
                vk::ImageAspectFlags::COLOR,
            ),
            name,
        )?;
        let test = Image::new(
            ctx,
            desc(
                TEST_FORMAT,
                vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
                vk::ImageAspectFlags::DEPTH,
            ),
            &format!("{name} depth test"),
        )?;
        Ok(DepthAsColour { depths, test })
    }

    /// Begins rendering into both, cleared to the far plane. The previous frame (same queue)
    /// may still sample the depths, so its fragment shaders finish first.
    pub fn begin(&self, rec: &Recording) {
        let depth_stages = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
        transition_images(
            rec,
            &[
                ImageTransition {
                    image: &self.depths,
                    aspect: vk::ImageAspectFlags::COLOR,
                    base_mip: 0,
                    mip_count: 1,
                    old: vk::ImageLayout::UNDEFINED,
                    new: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                    src: (
                        vk::PipelineStageFlags2::FRAGMENT_SHADER,
                        vk::AccessFlags2::NONE,
                    ),
                    dst: (
                        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                    ),
                },
                ImageTransition {
                    image: &self.test,
                    aspect: vk::ImageAspectFlags::DEPTH,
                    base_mip: 0,
                    mip_count: 1,
                    old: vk::ImageLayout::UNDEFINED,
                    new: vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                    src: (
                        depth_stages,
                        vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                    ),
                    dst: (
                        depth_stages,
                        vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
                            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                    ),
                },
            ],
        );
        rec.begin_rendering(&self.depths, Some(&self.test), [1.0; 4], false);
    }

    /// Ends the rendering and hands the depths to later fragment shaders.
    pub fn end(&self, rec: &Recording) {
        rec.end_rendering();
        transition_images(
            rec,
            &[ImageTransition {
                image: &self.depths,
                aspect: vk::ImageAspectFlags::COLOR,
                base_mip: 0,
                mip_count: 1,
                old: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                new: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                src: (
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                ),
                dst: (
                    vk::PipelineStageFlags2::FRAGMENT_SHADER,
                    vk::AccessFlags2::SHADER_SAMPLED_READ,
                ),
            }],
        );
    }
}
