//! The offscreen targets a frame draws into (made once per renderer): the scene passes' linear
//! radiance and depth (with MSAA multisampled, the radiance resolved as rendering ends), and the
//! sRGB frame the tone-mapping pass writes from the radiance; the barriers that hand them from one
//! frame to the next, and the copy of the frame into a host-visible buffer when it is read back.

use std::sync::Arc;

use ash::vk;

use super::gbuffer::GBuffer;
use super::target_images::{depth_target, radiance_targets, target_desc};
use super::tonemap::ToneMapPass;
use crate::render::kit::formats::COLOR_FORMAT;
use crate::render::kit::tone_curves::ToneMapping;
use crate::render::lighting::{LightingPass, LitImages, ShadingInputs};
use crate::render::plan::frame_plan::Plan;
use crate::vk::{
    transition_images, whole_color_region, ColorTarget, Context, DescriptorPool, DescriptorSet,
    Image, ImageTransition, Readback, Recording, VkResult,
};

/// Background colour (linear).
const CLEAR: [f32; 4] = [0.015, 0.02, 0.03, 1.0];

/// The host-visible buffers a frame is copied into, each when given.
#[derive(Clone, Copy, Default)]
pub struct FrameReadbacks<'a> {
    /// The frame (RGBA8 sRGB).
    pub color: Option<&'a Readback>,
    /// The depth (f32), with a shadow probe.
    pub depth: Option<&'a Readback>,
    /// The radiance before tone mapping (RGBA half floats).
    pub radiance: Option<&'a Readback>,
    /// The G-buffer's channels, in location order (targets made to keep them).
    pub gbuffer: Option<&'a [Readback]>,
}

/// Colour and depth targets of one size.
pub struct Targets {
    /// The frame's colour, one sample per pixel, tone mapped and sRGB-encoded: what is read back
    /// and presented.
    pub color: Image,
    /// Depth, with as many samples as the radiance drawn into.
    pub depth: Image,
    /// The scene passes' linear radiance, one sample per pixel (with MSAA, the resolve's target,
    /// written only when the radiance is kept).
    hdr: Image,
    /// With MSAA, the multisampled radiance the passes draw into, which the tone-mapping pass
    /// reads sample by sample.
    msaa_hdr: Option<Image>,
    /// With MSAA, resolve the radiance into `hdr` as rendering ends (for its read-back).
    resolve_radiance: bool,
    /// The tone-mapping pass's set reading the radiance, and its pool.
    tone_map_set: DescriptorSet,
    _pool: DescriptorPool,
    /// The depth is kept and can be read back (the shadow probe).
    keep_depth: bool,
    /// Supersampling: the radiance and depth are this many times the frame's size per axis.
    scale: u32,
    /// The G-buffer the surface pass writes beside the radiance, when frames keep it or the
    /// frame is lit deferred.
    pub gbuffer: Option<GBuffer>,
    /// The deferred frame's shading inputs, drawn after the G-buffer.
    shading_inputs: Option<ShadingInputs>,
}

/// How targets are made: samples per pixel, supersampling, and whether the depth is kept.
#[derive(Debug, Clone, Copy)]
pub struct TargetOptions {
    /// Samples per pixel of the scene's rendering (MSAA).
    pub samples: u32,
    /// The scene is drawn this many times larger per axis and averaged down (1: not at all).
    pub scale: u32,
    /// Frames may read the depth back (one sample, no supersampling).
    pub keep_depth: bool,
    /// Frames may read the radiance back (with MSAA, it is resolved for them).
    pub keep_radiance: bool,
    /// The surface pass writes the G-buffer, and frames may read it back (no supersampling).
    pub gbuffer: bool,
    /// The frame is lit deferred: the G-buffer and the shading inputs are drawn, and the
    /// lighting pass reads them and adds to the radiance (one sample, no supersampling).
    pub deferred: bool,
}

impl TargetOptions {
    /// How `plan`'s targets are made (`keep_depth`: the shadow probe reads the depth back;
    /// `keep_radiance`: frames read the radiance back).
    pub fn of(plan: &Plan, keep_depth: bool, keep_radiance: bool) -> TargetOptions {
        TargetOptions {
            samples: plan.msaa.samples,
            scale: plan.supersample,
            keep_depth,
            keep_radiance,
            gbuffer: plan.gbuffer,
            deferred: plan.deferred,
        }
    }
}

impl Targets {
    /// Creates the targets of a `width` x `height` frame as `options` say, tone mapped by
    /// `tone_map`.
    pub fn new(
        ctx: &Arc<Context>,
        width: u32,
        height: u32,
        options: TargetOptions,
        tone_map: &ToneMapPass,
    ) -> VkResult<Targets> {
        options.check(tone_map)?;
        let TargetOptions {
            samples,
            scale,
            keep_depth,
            keep_radiance,
            gbuffer,
            deferred,
        } = options;
        let gbuffer = (gbuffer || deferred)
            .then(|| GBuffer::new(ctx, (width, height), samples, (gbuffer, deferred)))
            .transpose()?;
        let shading_inputs = deferred
            .then(|| ShadingInputs::new(ctx, width, height))
            .transpose()?;
        let scene_size = (width * scale, height * scale);
        let (hdr, msaa_hdr) = radiance_targets(ctx, scene_size, samples, deferred)?;
        let pool = DescriptorPool::new(ctx, 1, 1, "tone map set")?;
        let radiance = msaa_hdr.as_ref().unwrap_or(&hdr);
        let tone_map_set = tone_map.set_for(&pool, radiance.view())?;
        Ok(Targets {
            color: Image::new(
                ctx,
                target_desc(
                    (width, height),
                    COLOR_FORMAT,
                    vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
                    vk::ImageAspectFlags::COLOR,
                ),
                "colour target",
            )?,
            depth: depth_target(ctx, scene_size, samples, keep_depth)?,
            hdr,
            msaa_hdr,
            resolve_radiance: keep_radiance,
            tone_map_set,
            _pool: pool,
            keep_depth,
            scale,
            gbuffer,
            shading_inputs,
        })
    }

    /// What the deferred frame's lighting pass reads and writes; `None` unless the targets
    /// were made for it.
    pub fn lit_images(&self) -> Option<LitImages<'_>> {
        let (material, motion) = self.gbuffer.as_ref()?.material_and_motion();
        Some(LitImages {
            radiance: &self.hdr,
            material,
            motion,
            inputs: self.shading_inputs.as_ref()?,
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

    /// A host-visible buffer a frame's linear radiance (RGBA half floats, at the radiance
    /// target's size: [`Targets::scale`] times the frame's per axis) is copied into.
    pub fn radiance_buffer(&self, ctx: &Arc<Context>, name: &str) -> VkResult<Readback> {
        let scale = u64::from(self.scale * self.scale);
        Readback::new(ctx, self.readback_bytes() * 2 * scale, name)
    }

    /// How many times the frame's size per axis the scene is drawn at.
    pub fn scale(&self) -> u32 {
        self.scale
    }

    /// Begins rendering the scene into the radiance and depth targets, cleared. The previous
    /// frame may still be drawing into them or tone mapping from the radiance (same queue), so
    /// the transitions wait for those stages; the old contents are discarded.
    pub fn begin(&self, rec: &Recording) {
        let depth_stages = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
            | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS;
        let depth_access = vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
            | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ;
        let attachment = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        // The previous frame's tone mapping read it in the fragment stage.
        let drawn_or_read = (
            attachment.0 | vk::PipelineStageFlags2::FRAGMENT_SHADER,
            attachment.1,
        );
        let to_attachment = (
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
        let radiance =
            |image| ImageTransition::color(image, to_attachment, drawn_or_read, attachment);
        let mut transitions = vec![
            radiance(&self.hdr),
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
        if let Some(msaa) = &self.msaa_hdr {
            transitions.push(radiance(msaa));
        }
        if let Some(g) = &self.gbuffer {
            transitions.extend(g.transitions());
        }
        if let Some(inputs) = &self.shading_inputs {
            transitions.extend(inputs.transitions());
        }
        transition_images(rec, &transitions);
        let radiance = match &self.msaa_hdr {
            Some(msaa) => ColorTarget {
                image: msaa,
                resolve: self
                    .resolve_radiance
                    .then_some((&self.hdr, vk::ResolveModeFlags::AVERAGE)),
                clear: vk::ClearColorValue { float32: CLEAR },
            },
            None => ColorTarget {
                image: &self.hdr,
                resolve: None,
                clear: vk::ClearColorValue { float32: CLEAR },
            },
        };
        let mut colors = vec![radiance];
        if let Some(g) = &self.gbuffer {
            colors.extend(g.targets());
        }
        if let Some(inputs) = &self.shading_inputs {
            colors.extend(inputs.targets());
        }
        rec.begin_rendering_targets(&colors, Some(&self.depth), self.keep_depth);
    }

    /// Ends the scene's rendering, lights it with `lighting` (the pass and the frame slot's
    /// plain set) when the frame is deferred, tone maps the radiance into the frame with
    /// `tone_map` and `mapping`, and copies what `into` names into its buffers, visible to the
    /// host: the frame, the depth (targets made to keep their depth), the radiance before tone
    /// mapping.
    pub fn end(
        &self,
        rec: &Recording,
        tone_map: (&ToneMapPass, ToneMapping),
        lighting: Option<(&LightingPass, &DescriptorSet)>,
        into: FrameReadbacks,
    ) -> VkResult<()> {
        rec.end_rendering();
        if let (Some((pass, frame_set)), Some(images)) = (lighting, self.lit_images()) {
            pass.record(rec, frame_set, &images)?;
        }
        if let Some(buffer) = into.depth.filter(|_| self.keep_depth) {
            self.copy_depth(rec, buffer)?;
        }
        if let (Some(g), Some(buffers)) = (self.gbuffer.as_ref().filter(|g| g.kept()), into.gbuffer)
        {
            g.copy_out(rec, buffers)?;
        }
        let radiance_layout = match into.radiance {
            Some(buffer) => {
                self.copy_radiance(rec, buffer)?;
                vk::ImageLayout::TRANSFER_SRC_OPTIMAL
            }
            None => vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        };
        self.tone_map(rec, tone_map.0, tone_map.1, radiance_layout)?;
        match into.color {
            Some(buffer) => copy_out(rec, &self.color, buffer),
            None => Ok(()),
        }
    }

    /// Copies the radiance (resolved, before tone mapping) into `buffer`, leaving it in the
    /// transfer source layout.
    fn copy_radiance(&self, rec: &Recording, buffer: &Readback) -> VkResult<()> {
        copy_out(rec, &self.hdr, buffer)
    }

    /// The full-frame pass from the radiance into the frame, which is left in the colour
    /// attachment layout. The single-sample radiance is in `radiance_layout`; a multisampled one,
    /// which the pass reads instead, is still the attachment.
    fn tone_map(
        &self,
        rec: &Recording,
        pass: &ToneMapPass,
        mapping: ToneMapping,
        radiance_layout: vk::ImageLayout,
    ) -> VkResult<()> {
        let attachment = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        let (source, radiance_layout) = match &self.msaa_hdr {
            Some(msaa) => (msaa, vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL),
            None => (&self.hdr, radiance_layout),
        };
        // Written by the scene's rendering, or last read by the radiance's copy.
        let after = if radiance_layout == vk::ImageLayout::TRANSFER_SRC_OPTIMAL {
            (vk::PipelineStageFlags2::COPY, vk::AccessFlags2::NONE)
        } else {
            attachment
        };
        let sampled = (
            vk::PipelineStageFlags2::FRAGMENT_SHADER,
            vk::AccessFlags2::SHADER_SAMPLED_READ,
        );
        // ALL_TRANSFER: a presenter or a read-back may have copied the previous frame out of it.
        let drawn_or_copied = (
            attachment.0 | vk::PipelineStageFlags2::ALL_TRANSFER,
            attachment.1,
        );
        let read = (radiance_layout, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL);
        let draw = (
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
        transition_images(
            rec,
            &[
                ImageTransition::color(source, read, after, sampled),
                ImageTransition::color(&self.color, draw, drawn_or_copied, attachment),
            ],
        );
        rec.begin_rendering(&self.color, None, CLEAR, false);
        pass.record(rec, &self.tone_map_set, mapping, self.scale)?;
        rec.end_rendering();
        Ok(())
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

/// Copies `image`, just drawn into as a colour attachment, into `buffer`, leaving it in the
/// transfer source layout.
fn copy_out(rec: &Recording, image: &Image, buffer: &Readback) -> VkResult<()> {
    let layouts = (
        vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
    );
    let written = (
        vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
        vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
    );
    let read = (
        vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::TRANSFER_READ,
    );
    transition_images(
        rec,
        &[ImageTransition::color(image, layouts, written, read)],
    );
    let desc = image.desc();
    let region = whole_color_region(desc.width, desc.height);
    buffer.record_copy_from_image(rec, image, region)
}

/// `texels` (rows of `width` texels) averaged over `scale` x `scale` blocks: a supersampled
/// radiance at the frame's size.
pub fn average_blocks(texels: &[[f32; 4]], width: u32, scale: u32) -> Vec<[f32; 4]> {
    if scale <= 1 {
        return texels.to_vec();
    }
    let (w, s) = (width as usize, scale as usize);
    let rows = texels.len() / w;
    let (out_w, out_h) = (w / s, rows / s);
    let n = (s * s) as f32;
    let mut out = Vec::with_capacity(out_w * out_h);
    for y in 0..out_h {
        for x in 0..out_w {
            let mut sum = [0.0f32; 4];
            for dy in 0..s {
                for dx in 0..s {
                    let t = texels[(y * s + dy) * w + x * s + dx];
                    for c in 0..4 {
                        sum[c] += t[c];
                    }
                }
            }
            out.push(sum.map(|c| c / n));
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::average_blocks;

    #[test]
    fn blocks_average_to_one_texel_each() {
        let texels: Vec<[f32; 4]> = (0..16).map(|i| [i as f32; 4]).collect();
        let out = average_blocks(&texels, 4, 2);
        assert_eq!(
            out.iter().map(|t| t[0]).collect::<Vec<_>>(),
            [2.5, 4.5, 10.5, 12.5]
        );
        assert_eq!(average_blocks(&texels, 4, 1), texels);
    }
}
