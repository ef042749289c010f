//! The G-buffer: what the surface pass writes beside the radiance when a frame asks for it, from
//! the very trace that shades each pixel (`shaders/passes/surface.frag`): the shading normal, and
//! the hit's uv, its depth along the camera's axis, the mesh drawn and the steps its trace took. Read
//! back as [`GBufferChannels`], written by `relief render --exr-out` as layers beside the beauty.
//!
//! With MSAA the normal is averaged over a pixel's samples (with a coverage channel), and the
//! rest comes from one sample, unfiltered, as compositors want depth and ids: the integer
//! channel is resolved with sample zero, which Vulkan allows for integer formats only.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;

use crate::scene::Camera;

use crate::vk::{
    half_floats_to_rgba, transition_images, whole_color_region, ColorTarget, Context, Image,
    ImageDesc, ImageTransition, Readback, Recording, VkResult,
};

/// The normal channel: world-space shading normal (xyz) and coverage (w, 1 where a surface was
/// drawn).
pub const GBUFFER_NORMAL_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;
/// The surface channel, as bits: uv0 at the hit (x, y: f32 bits), its depth along the camera's
/// axis (z: f32 bits), the mesh (w, low 16 bits: scene mesh index + 1, 0 for none) and the trace's
/// steps (w, high 16 bits).
pub const GBUFFER_SURFACE_FORMAT: vk::Format = vk::Format::R32G32B32A32_UINT;
/// The G-buffer's attachments after the radiance, in location order (1, 2).
pub const GBUFFER_FORMATS: [vk::Format; 2] = [GBUFFER_NORMAL_FORMAT, GBUFFER_SURFACE_FORMAT];

/// The colour formats a scene pipeline draws after the radiance: the G-buffer's when the frame
/// keeps it, else none.
pub fn scene_extra_formats(gbuffer: bool) -> &'static [vk::Format] {
    if gbuffer {
        &GBUFFER_FORMATS
    } else {
        &[]
    }
}

/// One frame's G-buffer, read back: one entry per pixel, rows top to bottom.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GBufferChannels {
    /// Frame size in pixels.
    pub width: u32,
    /// Frame size in pixels.
    pub height: u32,
    /// Linear view depth of the surface point shown (the displaced hit): its distance along the
    /// camera's axis, world units; infinite where nothing was drawn.
    pub depth: Vec<f32>,
    /// World-space shading normal, averaged over the pixel's samples and renormalised (zero
    /// where nothing was drawn).
    pub normal: Vec<[f32; 3]>,
    /// Share of the pixel's samples a surface covered.
    pub coverage: Vec<f32>,
    /// Texture coordinates (set 0) at the hit.
    pub uv: Vec<[f32; 2]>,
    /// Scene mesh index + 1 of the surface shown, 0 where nothing was drawn (or a cell complex
    /// or a blended material, which the G-buffer does not hold).
    pub mesh: Vec<u32>,
    /// Steps the pixel's view ray took through its height field (0 for plain meshes).
    pub steps: Vec<u32>,
}

impl GBufferChannels {
    /// Each pixel's world position, unprojected from its depth through `camera` (the frame's):
    /// the point along the ray through the pixel's centre whose depth along the camera's axis is
    /// the pixel's; infinite where nothing was drawn.
    pub fn positions(&self, camera: &Camera) -> Vec<[f32; 3]> {
        let aspect = self.width as f32 / self.height.max(1) as f32;
        let inverse = camera.view_projection(aspect).inverse();
        let row = -camera.view.row(2);
        let axis = row.truncate() / row.truncate().length().max(f32::MIN_POSITIVE);
        let eye = camera.eye();
        let (w, h) = (self.width as usize, self.height.max(1) as usize);
        self.depth
            .iter()
            .enumerate()
            .map(|(k, &depth)| {
                if !depth.is_finite() {
                    return [f32::INFINITY; 3];
                }
                // Framebuffer rows run with clip y (the projection flips y for Vulkan).
                let ndc_x = ((k % w) as f32 + 0.5) / w as f32 * 2.0 - 1.0;
                let ndc_y = ((k / w) as f32 + 0.5) / h as f32 * 2.0 - 1.0;
                let near = inverse.project_point3(Vec3::new(ndc_x, ndc_y, 0.0));
                let far = inverse.project_point3(Vec3::new(ndc_x, ndc_y, 1.0));
                let dir = (far - near).normalize_or_zero();
                let along = dir.dot(axis);
                if along.abs() < f32::MIN_POSITIVE {
                    return [f32::INFINITY; 3];
                }
                // From the near plane, so orthographic views (parallel rays) work alike.
                let t = (depth - (near - eye).dot(axis)) / along;
                (near + dir * t).to_array()
            })
            .collect()
    }

    /// Decodes the two read-back channels of a `width` x `height` frame.
    pub fn decode(width: u32, height: u32, normal: &[u8], surface: &[u8]) -> GBufferChannels {
        let normal = half_floats_to_rgba(normal);
        let surface: Vec<u32> = bytemuck::pod_collect_to_vec(surface);
        let mut out = GBufferChannels {
            width,
            height,
            ..GBufferChannels::default()
        };
        for (n, s) in normal.iter().zip(surface.chunks_exact(4)) {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let unit = if len > 0.0 {
                [n[0] / len, n[1] / len, n[2] / len]
            } else {
                [0.0; 3]
            };
            let mesh = s[3] & 0xffff;
            out.normal.push(unit);
            out.coverage.push(n[3]);
            out.uv.push([f32::from_bits(s[0]), f32::from_bits(s[1])]);
            out.depth.push(if mesh == 0 {
                f32::INFINITY
            } else {
                f32::from_bits(s[2])
            });
            out.mesh.push(mesh);
            out.steps.push(s[3] >> 16);
        }
        out
    }
}

/// The G-buffer's images: drawn into with the scene's samples, and with MSAA resolved into
/// single-sample images when rendering ends.
pub struct GBuffer {
    normal: Image,
    surface: Image,
    resolved: Option<(Image, Image)>,
}

impl GBuffer {
    /// The channels of a `width` x `height` scene drawn with `samples` samples per pixel.
    pub fn new(ctx: &Arc<Context>, width: u32, height: u32, samples: u32) -> VkResult<GBuffer> {
        let desc = |format| ImageDesc {
            width,
            height,
            format,
            mip_levels: 1,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            aspect: vk::ImageAspectFlags::COLOR,
        };
        let drawn = |format, name: &str| {
            Image::new_multisampled(ctx, desc(format), samples, &format!("g-buffer {name}"))
        };
        let normal = drawn(GBUFFER_NORMAL_FORMAT, "normal")?;
        let surface = drawn(GBUFFER_SURFACE_FORMAT, "surface")?;
        let resolved = (samples > 1)
            .then(|| -> VkResult<_> {
                Ok((
                    Image::new(ctx, desc(GBUFFER_NORMAL_FORMAT), "g-buffer normal resolved")?,
                    Image::new(
                        ctx,
                        desc(GBUFFER_SURFACE_FORMAT),
                        "g-buffer surface resolved",
                    )?,
                ))
            })
            .transpose()?;
        Ok(GBuffer {
            normal,
            surface,
            resolved,
        })
    }

    /// Every image into the colour attachment layout, old contents discarded; the previous
    /// frame may still be drawing into them or copying them out (same queue).
    pub fn transitions(&self) -> Vec<ImageTransition<'_>> {
        let attachment = (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        );
        let before = (
            attachment.0 | vk::PipelineStageFlags2::ALL_TRANSFER,
            attachment.1,
        );
        let layouts = (
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        );
        let mut images = vec![&self.normal, &self.surface];
        if let Some((n, s)) = &self.resolved {
            images.extend([n, s]);
        }
        images
            .into_iter()
            .map(|image| ImageTransition::color(image, layouts, before, attachment))
            .collect()
    }

    /// The two attachments after the radiance, cleared to zero (nothing drawn).
    pub fn targets(&self) -> [ColorTarget<'_>; 2] {
        let resolved = self.resolved.as_ref();
        [
            ColorTarget {
                image: &self.normal,
                resolve: resolved.map(|(n, _)| (n, vk::ResolveModeFlags::AVERAGE)),
                clear: vk::ClearColorValue { float32: [0.0; 4] },
            },
            ColorTarget {
                image: &self.surface,
                resolve: resolved.map(|(_, s)| (s, vk::ResolveModeFlags::SAMPLE_ZERO)),
                clear: vk::ClearColorValue { uint32: [0; 4] },
            },
        ]
    }

    /// Bytes of the normal channel's read-back.
    pub fn normal_bytes(&self) -> u64 {
        let d = self.normal.desc();
        u64::from(d.width) * u64::from(d.height) * 8
    }

    /// Bytes of the surface channel's read-back.
    pub fn surface_bytes(&self) -> u64 {
        let d = self.surface.desc();
        u64::from(d.width) * u64::from(d.height) * 16
    }

    /// Copies the channels (resolved, with MSAA) into `normal` and `surface`, after the scene's
    /// rendering has ended.
    pub fn copy_out(&self, rec: &Recording, normal: &Readback, surface: &Readback) -> VkResult<()> {
        let (n, s) = match &self.resolved {
            Some((n, s)) => (n, s),
            None => (&self.normal, &self.surface),
        };
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
            &[
                ImageTransition::color(n, layouts, written, read),
                ImageTransition::color(s, layouts, written, read),
            ],
        );
        let d = n.desc();
        normal.record_copy_from_image(rec, n, whole_color_region(d.width, d.height))?;
        surface.record_copy_from_image(rec, s, whole_color_region(d.width, d.height))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn channels_decode_from_their_bits() {
        let half = |x: f32| -> u16 {
            // 0.0, 1.0 and 0.5 only: exact in half precision.
            match x {
                1.0 => 0x3c00,
                0.5 => 0x3800,
                _ => 0,
            }
        };
        let normal: Vec<u16> = [0.0, 0.0, 1.0, 1.0, 0.0, 0.0, 0.0, 0.0]
            .iter()
            .map(|&x| half(x))
            .collect();
        let surface: Vec<u32> = vec![
            0.25f32.to_bits(),
            0.75f32.to_bits(),
            3.5f32.to_bits(),
            2 | (17 << 16),
            0,
            0,
            0,
            0,
        ];
        let g = GBufferChannels::decode(
            2,
            1,
            bytemuck::cast_slice(&normal),
            bytemuck::cast_slice(&surface),
        );
        assert_eq!(g.normal, [[0.0, 0.0, 1.0], [0.0; 3]]);
        assert_eq!(g.coverage, [1.0, 0.0]);
        assert_eq!(g.uv[0], [0.25, 0.75]);
        assert_eq!(g.depth[0], 3.5);
        assert!(
            g.depth[1].is_infinite(),
            "nothing drawn reads as infinitely far"
        );
        assert_eq!(g.mesh, [2, 0]);
        assert_eq!(g.steps, [17, 0]);
    }
}
