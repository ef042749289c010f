//! The G-buffer: what the surface pass writes beside the radiance when a frame asks for it, from
//! the very trace that shades each pixel (`shaders/passes/surface.frag`): the shading normal; the
//! hit's uv, its depth along the camera's axis, the mesh drawn and the steps its trace took; the
//! albedo and ambient occlusion it was shaded with; the share of its direct light no shadow
//! blocked; and its motion on screen since the previous frame. Read back as
//! [`GBufferChannels`], written by `relief render --exr-out` as layers beside the beauty.
//!
//! With MSAA the float channels are averaged over a pixel's samples and divided by its coverage
//! (so an edge pixel holds the mean of its covered samples), and the integer channel comes from
//! sample zero, unfiltered, as compositors want depth and ids: Vulkan resolves integer formats
//! with one sample only, and float formats only by averaging.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;

use crate::render::kit::formats::GBUFFER_FORMATS;
use crate::scene::Camera;

use crate::vk::{
    half_floats_to_rgba, transition_images, whole_color_region, ColorTarget, Context, Image,
    ImageDesc, ImageTransition, Readback, Recording, VkResult,
};

/// One attachment of the G-buffer.
struct ChannelSpec {
    format: vk::Format,
    name: &'static str,
    /// Bytes per texel of its read-back.
    bytes: u64,
    /// Integer channels take sample zero; float ones are averaged.
    integer: bool,
}

/// The G-buffer's attachments after the radiance, in location order (1 to 4).
const CHANNELS: [ChannelSpec; 4] = [
    // World-space shading normal (xyz) and coverage (w, 1 where a surface was drawn).
    ChannelSpec {
        format: GBUFFER_FORMATS[0],
        name: "normal",
        bytes: 8,
        integer: false,
    },
    // As bits: uv0 at the hit (x, y: f32 bits), its depth along the camera's axis (z: f32
    // bits), the mesh (w, low 16 bits: scene mesh index + 1, 0 for none) and the trace's steps
    // (w, high 16 bits).
    ChannelSpec {
        format: GBUFFER_FORMATS[1],
        name: "surface",
        bytes: 16,
        integer: true,
    },
    // Albedo, linear (xyz), and the ambient occlusion the ambient light was darkened by (w).
    ChannelSpec {
        format: GBUFFER_FORMATS[2],
        name: "material",
        bytes: 8,
        integer: false,
    },
    // Screen motion since the previous frame in pixels (xy: x right, y down), and the share of
    // the direct light not shadowed (z).
    ChannelSpec {
        format: GBUFFER_FORMATS[3],
        name: "motion and shadow",
        bytes: 8,
        integer: false,
    },
];

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
    /// Linear albedo (base colour times its texture and vertex colour, with terrain layers
    /// mixed in) of the surface shown; zero where nothing was drawn.
    pub albedo: Vec<[f32; 3]>,
    /// The ambient occlusion the ambient light was darkened by (the material's occlusion texture
    /// times the height field's own AO map), 1 for none; zero where nothing was drawn.
    pub ao: Vec<f32>,
    /// The share of the direct light reaching the surface that no shadow blocked: each light
    /// facing it weighs by its luminance, attenuation and cosine; 1 where no light faces it,
    /// zero where nothing was drawn.
    pub shadow: Vec<f32>,
    /// Where the surface point moved on screen since the previous frame, in pixels (x right, y
    /// down): its pixel now less its pixel through the previous frame's camera; zero where
    /// nothing was drawn and in a first frame.
    pub motion: Vec<[f32; 2]>,
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

    /// Decodes the read-back channels of a `width` x `height` frame, in location order (pixels
    /// past the shortest channel are left out).
    pub fn decode(width: u32, height: u32, channels: &[&[u8]]) -> GBufferChannels {
        let channel = |k: usize| channels.get(k).copied().unwrap_or_default();
        let (normal, surface, material, motion) = (channel(0), channel(1), channel(2), channel(3));
        let normal = half_floats_to_rgba(normal);
        let surface: Vec<u32> = bytemuck::pod_collect_to_vec(surface);
        let material = half_floats_to_rgba(material);
        let motion = half_floats_to_rgba(motion);
        let mut out = GBufferChannels {
            width,
            height,
            ..GBufferChannels::default()
        };
        let texels = normal.iter().zip(surface.chunks_exact(4));
        for ((n, s), (m, v)) in texels.zip(material.iter().zip(&motion)) {
            let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
            let unit = if len > 0.0 {
                [n[0] / len, n[1] / len, n[2] / len]
            } else {
                [0.0; 3]
            };
            let coverage = n[3];
            // Averaged over all samples, uncovered ones cleared to zero: back to the mean of
            // the covered ones.
            let covered = |x: f32| if coverage > 0.0 { x / coverage } else { 0.0 };
            let mesh = s[3] & 0xffff;
            out.normal.push(unit);
            out.coverage.push(coverage);
            out.uv.push([f32::from_bits(s[0]), f32::from_bits(s[1])]);
            out.depth.push(if mesh == 0 {
                f32::INFINITY
            } else {
                f32::from_bits(s[2])
            });
            out.mesh.push(mesh);
            out.steps.push(s[3] >> 16);
            out.albedo
                .push([covered(m[0]), covered(m[1]), covered(m[2])]);
            out.ao.push(covered(m[3]));
            out.motion.push([covered(v[0]), covered(v[1])]);
            out.shadow.push(covered(v[2]));
        }
        out
    }
}

/// The G-buffer's images: drawn into with the scene's samples, and with MSAA resolved into
/// single-sample images when rendering ends.
pub struct GBuffer {
    /// One image per channel, in location order.
    drawn: Vec<Image>,
    /// Frames read the channels back (else only the deferred frame's lighting pass reads
    /// them).
    kept: bool,
    /// With MSAA, the resolve target of each; else empty.
    resolved: Vec<Image>,
}

impl GBuffer {
    /// The channels of a `width` x `height` scene drawn with `samples` samples per pixel,
    /// read back by frames when `kept`, read by the lighting pass when `lit` (one sample).
    pub fn new(
        ctx: &Arc<Context>,
        (width, height): (u32, u32),
        samples: u32,
        (kept, lit): (bool, bool),
    ) -> VkResult<GBuffer> {
        let storage = if lit {
            vk::ImageUsageFlags::STORAGE
        } else {
            vk::ImageUsageFlags::empty()
        };
        let desc = |format| ImageDesc {
            width,
            height,
            format,
            mip_levels: 1,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT
                | vk::ImageUsageFlags::TRANSFER_SRC
                | storage,
            aspect: vk::ImageAspectFlags::COLOR,
        };
        let drawn = CHANNELS
            .iter()
            .map(|c| {
                let name = format!("g-buffer {}", c.name);
                Image::new_multisampled(ctx, desc(c.format), samples, &name)
            })
            .collect::<VkResult<Vec<_>>>()?;
        let resolved = if samples > 1 {
            CHANNELS
                .iter()
                .map(|c| {
                    Image::new(
                        ctx,
                        desc(c.format),
                        &format!("g-buffer {} resolved", c.name),
                    )
                })
                .collect::<VkResult<Vec<_>>>()?
        } else {
            Vec::new()
        };
        Ok(GBuffer {
            drawn,
            kept,
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
        self.drawn
            .iter()
            .chain(&self.resolved)
            .map(|image| ImageTransition::color(image, layouts, before, attachment))
            .collect()
    }

    /// The attachments after the radiance, cleared to zero (nothing drawn).
    pub fn targets(&self) -> Vec<ColorTarget<'_>> {
        CHANNELS
            .iter()
            .zip(&self.drawn)
            .enumerate()
            .map(|(k, (c, image))| {
                let mode = if c.integer {
                    vk::ResolveModeFlags::SAMPLE_ZERO
                } else {
                    vk::ResolveModeFlags::AVERAGE
                };
                ColorTarget {
                    image,
                    resolve: self.resolved.get(k).map(|r| (r, mode)),
                    clear: if c.integer {
                        vk::ClearColorValue { uint32: [0; 4] }
                    } else {
                        vk::ClearColorValue { float32: [0.0; 4] }
                    },
                }
            })
            .collect()
    }

    /// Whether frames read the channels back.
    pub fn kept(&self) -> bool {
        self.kept
    }

    /// The albedo and occlusion channel and the motion and shadow one, as drawn (the lighting
    /// pass's inputs and output).
    pub fn material_and_motion(&self) -> (&Image, &Image) {
        (&self.drawn[2], &self.drawn[3])
    }

    /// One read-back buffer per channel, in location order, named after `slot`.
    pub fn readbacks(&self, ctx: &Arc<Context>, slot: &str) -> VkResult<Vec<Readback>> {
        CHANNELS
            .iter()
            .zip(&self.drawn)
            .map(|(c, image)| {
                let d = image.desc();
                let bytes = u64::from(d.width) * u64::from(d.height) * c.bytes;
                Readback::new(ctx, bytes, &format!("{slot} g-buffer {} readback", c.name))
            })
            .collect()
    }

    /// Copies the channels (resolved, with MSAA) into `into`, one buffer per channel in location
    /// order, after the scene's rendering has ended.
    pub fn copy_out(&self, rec: &Recording, into: &[Readback]) -> VkResult<()> {
        let images = if self.resolved.is_empty() {
            &self.drawn
        } else {
            &self.resolved
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
        let transitions: Vec<_> = images
            .iter()
            .map(|image| ImageTransition::color(image, layouts, written, read))
            .collect();
        transition_images(rec, &transitions);
        for (image, buffer) in images.iter().zip(into) {
            let d = image.desc();
            buffer.record_copy_from_image(rec, image, whole_color_region(d.width, d.height))?;
        }
        Ok(())
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
        // Half of the first pixel covered: its averaged material and motion are halved.
        let material: Vec<u16> = [0.5, 0.5, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0]
            .iter()
            .map(|&x| half(x))
            .collect();
        let motion: Vec<u16> = [0.5, 0.0, 0.5, 0.0, 0.0, 0.0, 0.0, 0.0]
            .iter()
            .map(|&x| half(x))
            .collect();
        let mut normal = normal;
        normal[3] = half(0.5);
        let g = GBufferChannels::decode(
            2,
            1,
            &[
                bytemuck::cast_slice(&normal),
                bytemuck::cast_slice(&surface),
                bytemuck::cast_slice(&material),
                bytemuck::cast_slice(&motion),
            ],
        );
        assert_eq!(g.normal, [[0.0, 0.0, 1.0], [0.0; 3]]);
        assert_eq!(g.coverage, [0.5, 0.0]);
        assert_eq!(g.albedo, [[1.0, 1.0, 0.0], [0.0; 3]]);
        assert_eq!(g.ao, [1.0, 0.0]);
        assert_eq!(g.motion, [[1.0, 0.0], [0.0; 2]]);
        assert_eq!(g.shadow, [1.0, 0.0]);
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
