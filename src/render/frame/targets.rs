//! The offscreen targets a frame draws into (colour and depth, made once per renderer; with MSAA
//! a multisampled colour and depth, resolved into the single-sample colour as rendering ends),
//! the barriers that hand them from one frame to the next, and the copy of the colour image into
//! a host-visible buffer when the frame is to be read back.

use std::sync::Arc;

use ash::vk;

use super::surface_pass::{COLOR_FORMAT, DEPTH_FORMAT};
use crate::vk::{
    transition_images, whole_color_region, Context, Image, ImageDesc, ImageTransition, Readback,
    Recording, VkResult,
};

/// Background colour (linear).
const CLEAR: [f32; 4] = [0.015, 0.02, 0.03, 1.0];

/// Colour and depth targets of one size.
pub struct Targets {
    /// The frame's colour, one sample per pixel: what is read back and presented.
    pub color: Image,
    /// Depth, with as many samples as the colour drawn into.
    pub depth: Image,
    /// With MSAA, the multisampled colour the passes draw into, resolved into `color`.
    msaa_color: Option<Image>,
    /// The depth is kept and can be read back (the shadow probe).
    keep_depth: bool,
}

impl Targets {
    /// Creates the targets at `width` x `height` with `samples` samples per pixel; `keep_depth`
    /// lets frames read the depth back (one sample only).
    pub fn new(
        ctx: &Arc<Context>,
        width: u32,
        height: u32,
        keep_depth: bool,
        samples: u32,
    ) -> VkResult<Targets> {
        if keep_depth && samples > 1 {
            return Err(crate::vk::VkError::Invalid(
                "a depth read back needs single-sample targets".into(),
            ));
        }
        let depth_usage = if keep_depth {
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC
        } else {
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
        };
        let desc = |format, usage, aspect| ImageDesc {
            width,
            height,
            format,
            mip_levels: 1,
            usage,
            aspect,
        };
        Ok(Targets {
            color: Image::new(
                ctx,
                desc(
                    COLOR_FORMAT,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                    vk::ImageAspectFlags::COLOR,
                ),
                "colour target",
            )?,
            depth: Image::new_multisampled(
                ctx,
                desc(DEPTH_FORMAT, depth_usage, vk::ImageAspectFlags::DEPTH),
                samples,
                "depth target",
            )?,
            msaa_color: (samples > 1)
                .then(|| {
                    // Transient: the samples live only until the resolve.
                    let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT
                        | vk::ImageUsageFlags::TRANSIENT_ATTACHMENT;
                    let d = desc(COLOR_FORMAT, usage, vk::ImageAspectFlags::COLOR);
                    Image::new_multisampled(ctx, d, samples, "multisampled colour target")
                })
                .transpose()?,
            keep_depth,
        })
    }

    /// Bytes of one read-back colour image (RGBA8).
    pub fn readback_bytes(&self) -> u64 {
        let desc = self.color.desc();
        u64::from(desc.width) * u64::from(desc.height) * 4
    }

    /// A host-visible buffer a frame's colour is copied into.
    pub fn readback_buffer(&self, ctx: &Arc<Context>, name: &str) -> VkResult<Readback> {
        Readback::new(ctx, self.readback_bytes(), name)
    }

    /// Begins rendering into both targets, cleared. The previous frame may still be drawing or
    /// copying them (same queue), so the transitions wait for those stages; the old contents are
    /// discarded.
    pub fn begin(&self, rec: &Recording) {
        // ALL_TRANSFER: a presenter may have blitted the previous frame out of the colour target.
        let color_stages = vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT
            | vk::PipelineStageFlags2::ALL_TRANSFER;
        let depth_stages = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
        let depth_access = vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ;
        let color = |image| ImageTransition {
            image,
            aspect: vk::ImageAspectFlags::COLOR,
            base_mip: 0,
            mip_count: 1,
            old: vk::ImageLayout::UNDEFINED,
            new: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
            src: (color_stages, vk::AccessFlags2::COLOR_ATTACHMENT_WRITE),
            dst: (
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
        };
        let mut transitions = vec![
            color(&self.color),
            ImageTransition {
                image: &self.depth,
                aspect: vk::ImageAspectFlags::DEPTH,
                base_mip: 0,
                mip_count: 1,
                old: vk::ImageLayout::UNDEFINED,
                new: vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                // ALL_TRANSFER: the previous frame may have copied the depth out.
                src: (
                    depth_stages | vk::PipelineStageFlags2::ALL_TRANSFER,
                    vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                ),
                dst: (depth_stages, depth_access),
            },
        ];
        if let Some(msaa) = &self.msaa_color {
            transitions.push(color(msaa));
        }
        transition_images(rec, &transitions);
        match &self.msaa_color {
            Some(msaa) => rec.begin_rendering_resolved(
                msaa,
                Some(&self.color),
                Some(&self.depth),
                CLEAR,
                self.keep_depth,
            ),
            None => rec.begin_rendering(&self.color, Some(&self.depth), CLEAR, self.keep_depth),
        }
    }

    /// Ends rendering and, if `readback` is given, copies the colour image into it and makes the
    /// copy visible to the host; likewise the depth into `depth_readback` (targets made to keep
    /// their depth).
    pub fn end(
        &self,
        rec: &Recording,
        readback: Option<&Readback>,
        depth_readback: Option<&Readback>,
    ) -> VkResult<()> {
        rec.end_rendering();
        if let Some(buffer) = depth_readback.filter(|_| self.keep_depth) {
            self.copy_depth(rec, buffer)?;
        }
        let Some(buffer) = readback else {
            return Ok(());
        };
        transition_images(
            rec,
            &[ImageTransition {
                image: &self.color,
                aspect: vk::ImageAspectFlags::COLOR,
                base_mip: 0,
                mip_count: 1,
                old: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                new: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                src: (
                    vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                    vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
                ),
                dst: (
                    vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::TRANSFER_READ,
                ),
            }],
        );
        let desc = self.color.desc();
        let region = whole_color_region(desc.width, desc.height);
        buffer.record_copy_from_image(rec, &self.color, region)
    }

    /// Copies the depth target into `buffer` (one f32 per pixel).
    fn copy_depth(&self, rec: &Recording, buffer: &Readback) -> VkResult<()> {
        let depth_stages = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
        transition_images(
            rec,
            &[ImageTransition {
                image: &self.depth,
                aspect: vk::ImageAspectFlags::DEPTH,
                base_mip: 0,
                mip_count: 1,
                old: vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                new: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
                src: (
                    depth_stages,
                    vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE,
                ),
                dst: (
                    vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::TRANSFER_READ,
                ),
            }],
        );
        let desc = self.depth.desc();
        let mut region = whole_color_region(desc.width, desc.height);
        region.image_subresource.aspect_mask = vk::ImageAspectFlags::DEPTH;
        buffer.record_copy_from_image(rec, &self.depth, region)
    }
}
