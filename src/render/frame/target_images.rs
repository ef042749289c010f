//! The images a frame's targets are made of: the checks on the options they are made with, the
//! radiance targets (with MSAA, the multisampled one the passes draw into too) and the depth
//! target.

use std::sync::Arc;

use ash::vk;

use super::targets::TargetOptions;
use super::tonemap::ToneMapPass;
use crate::render::kit::formats::{DEPTH_FORMAT, HDR_FORMAT};
use crate::vk::{Context, Image, ImageDesc, VkError, VkResult};

impl TargetOptions {
    /// Fails where the options cannot be had together, or `tone_map` reads another sample
    /// count.
    pub(super) fn check(&self, tone_map: &ToneMapPass) -> VkResult<()> {
        let (samples, scale) = (self.samples, self.scale);
        if tone_map.samples() != samples {
            return Err(VkError::Invalid(format!(
                "a tone-mapping pass for {} samples on {samples}-sample targets",
                tone_map.samples()
            )));
        }
        if self.keep_depth && (samples > 1 || scale > 1) {
            return Err(VkError::Invalid(
                "a depth read back needs single-sample targets".into(),
            ));
        }
        if self.gbuffer && scale > 1 {
            return Err(VkError::Invalid(
                "the G-buffer channels (--exr-out) are read at the frame's size: leave out --supersample".into(),
            ));
        }
        if self.deferred && (samples > 1 || scale > 1) {
            return Err(VkError::Invalid(
                "deferred lighting needs single-sample targets at the frame's size".into(),
            ));
        }
        Ok(())
    }
}

/// A single-level target image of `size`.
pub(super) fn target_desc(
    size: (u32, u32),
    format: vk::Format,
    usage: vk::ImageUsageFlags,
    aspect: vk::ImageAspectFlags,
) -> ImageDesc {
    ImageDesc {
        width: size.0,
        height: size.1,
        format,
        mip_levels: 1,
        usage,
        aspect,
    }
}

/// The radiance target of the scene's `size`, and with MSAA (`samples` > 1) the multisampled
/// one the passes draw into; a `deferred` frame's lighting pass writes the radiance as storage.
pub(super) fn radiance_targets(
    ctx: &Arc<Context>,
    size: (u32, u32),
    samples: u32,
    deferred: bool,
) -> VkResult<(Image, Option<Image>)> {
    // The lighting pass adds to the radiance in place.
    let lit = if deferred {
        vk::ImageUsageFlags::STORAGE
    } else {
        vk::ImageUsageFlags::empty()
    };
    let color_aspect = vk::ImageAspectFlags::COLOR;
    let hdr = Image::new(
        ctx,
        target_desc(
            size,
            HDR_FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_SRC
                | lit,
            color_aspect,
        ),
        "radiance target",
    )?;
    let msaa_hdr = (samples > 1)
        .then(|| {
            let usage = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::SAMPLED;
            let d = target_desc(size, HDR_FORMAT, usage, color_aspect);
            Image::new_multisampled(ctx, d, samples, "multisampled radiance target")
        })
        .transpose()?;
    Ok((hdr, msaa_hdr))
}

/// The depth target of the scene's `size` with `samples` per pixel, which can be copied out
/// when `keep_depth`.
pub(super) fn depth_target(
    ctx: &Arc<Context>,
    size: (u32, u32),
    samples: u32,
    keep_depth: bool,
) -> VkResult<Image> {
    let usage = if keep_depth {
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC
    } else {
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT
    };
    let desc = target_desc(size, DEPTH_FORMAT, usage, vk::ImageAspectFlags::DEPTH);
    Image::new_multisampled(ctx, desc, samples, "depth target")
}
