//! The deferred frame's shading inputs: three attachments the surface pass draws after the
//! G-buffer's (locations 5 to 7) and the lighting pass reads. The shaded point (xyz, world; w: 1
//! plus its depth below the relief's top plane, 0 where nothing deferred was drawn); the shading
//! normal, the polygon's plane and its interpolated normal (octahedral, 2 x 16 bits each) with
//! roughness and metallic (16 bits each); the height field's own shadow toward the first four
//! lights (8 bits each). The world point is kept whole rather than unprojected from a depth, so
//! the lights see the very point the forward pass shades.

use std::sync::Arc;

use ash::vk;

use crate::render::kit::formats::SHADING_INPUT_FORMATS;
use crate::vk::{ColorTarget, Context, Image, ImageDesc, ImageTransition, VkResult};

/// The names of the three attachments, in location order.
const NAMES: [&str; 3] = ["shaded point", "shading frame", "self-shadow"];

/// The three single-sample images.
pub struct ShadingInputs {
    images: Vec<Image>,
}

impl ShadingInputs {
    /// The inputs of a `width` x `height` frame.
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32) -> VkResult<ShadingInputs> {
        let images = SHADING_INPUT_FORMATS
            .iter()
            .zip(NAMES)
            .map(|(&format, name)| {
                let desc = ImageDesc {
                    width,
                    height,
                    format,
                    mip_levels: 1,
                    usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::STORAGE,
                    aspect: vk::ImageAspectFlags::COLOR,
                };
                Image::new(ctx, desc, &format!("deferred {name}"))
            })
            .collect::<VkResult<Vec<_>>>()?;
        Ok(ShadingInputs { images })
    }

    /// Every image into the colour attachment layout, old contents discarded; the previous
    /// frame's lighting pass may still be reading them (same queue).
    pub fn transitions(&self) -> Vec<ImageTransition<'_>> {
        let attachment = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        let before = (
            attachment.0 | vk::PipelineStageFlags2::COMPUTE_SHADER,
            attachment.1,
        );
        let layouts = (
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
        self.images
            .iter()
            .map(|image| ImageTransition::color(image, layouts, before, attachment))
            .collect()
    }

    /// The attachments, cleared to zero (nothing deferred drawn).
    pub fn targets(&self) -> Vec<ColorTarget<'_>> {
        self.images
            .iter()
            .zip(SHADING_INPUT_FORMATS)
            .map(|(image, format)| ColorTarget {
                image,
                resolve: None,
                clear: if format == vk::Format::R32G32B32A32_UINT {
                    vk::ClearColorValue { uint32: [0; 4] }
                } else {
                    vk::ClearColorValue { float32: [0.0; 4] }
                },
            })
            .collect()
    }

    /// The images, in location order.
    pub fn images(&self) -> &[Image] {
        &self.images
    }
}
