//! Moving pixels between host and GPU: mip-chain uploads through one staging buffer, and readback
//! of one mip level into host memory (through a [`Readback`], which records the host-read
//! barrier). Images end in the layout the caller names.

use std::sync::Arc;

use ash::vk;
use gpu_allocator::MemoryLocation;

use super::buffer::Buffer;
use super::commands::{transition_images, ImageTransition};
use super::context::Context;
use super::error::{VkError, VkResult};
use super::image::{Image, ImageDesc};
use super::readback::Readback;
use super::recording::Recording;

/// Bytes per texel of the formats relief moves between host and GPU.
pub fn texel_size(format: vk::Format) -> VkResult<usize> {
    Ok(match format {
        vk::Format::R8_UNORM => 1,
        vk::Format::R16_UNORM | vk::Format::R16_SFLOAT => 2,
        vk::Format::R32_SFLOAT
        | vk::Format::D32_SFLOAT
        | vk::Format::R8G8B8A8_UNORM
        | vk::Format::R8G8B8A8_SRGB
        | vk::Format::B8G8R8A8_UNORM
        | vk::Format::B8G8R8A8_SRGB => 4,
        vk::Format::R16G16B16A16_SFLOAT
        | vk::Format::R16G16B16A16_UNORM
        | vk::Format::R32G32_SFLOAT => 8,
        vk::Format::R32G32B32A32_SFLOAT | vk::Format::R32G32B32A32_UINT => 16,
        other => {
            return Err(VkError::Invalid(format!(
                "no host transfer for format {other:?}"
            )))
        }
    })
}

fn all_mips(image: &Image, old: vk::ImageLayout, new: vk::ImageLayout) -> ImageTransition<'_> {
    ImageTransition {
        image,
        aspect: image.desc().aspect,
        base_mip: 0,
        mip_count: image.desc().mip_levels,
        old,
        new,
        src: (
            vk::PipelineStageFlags2::ALL_COMMANDS,
            vk::AccessFlags2::MEMORY_WRITE,
        ),
        dst: (
            vk::PipelineStageFlags2::ALL_COMMANDS,
            vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE,
        ),
    }
}

/// Uploads `levels[k]` (tightly packed rows) into mip `k` and leaves the whole image in `final_layout`.
pub fn upload_mips(
    ctx: &Arc<Context>,
    image: &Image,
    levels: &[&[u8]],
    final_layout: vk::ImageLayout,
) -> VkResult<()> {
    upload_layers(ctx, image, &[levels.to_vec()], final_layout)
}

/// Uploads `layers[l][k]` (tightly packed rows) into mip `k` of array layer `l` and leaves the
/// whole image in `final_layout`.
pub fn upload_layers(
    ctx: &Arc<Context>,
    image: &Image,
    layers: &[Vec<&[u8]>],
    final_layout: vk::ImageLayout,
) -> VkResult<()> {
    if layers.len() != image.layer_count() as usize {
        return Err(VkError::Invalid(format!(
            "{} layers for {:?}, which has {}",
            layers.len(),
            image.name(),
            image.layer_count()
        )));
    }
    let texel = texel_size(image.desc().format)?;
    let mut offsets = Vec::new();
    for (l, levels) in layers.iter().enumerate() {
        for (k, bytes) in levels.iter().enumerate() {
            let (w, h) = image.level_extent(k as u32);
            if bytes.len() != w as usize * h as usize * texel {
                return Err(VkError::Invalid(format!(
                    "mip {k} of layer {l} of {:?}: {} bytes for {w}x{h}",
                    image.name(),
                    bytes.len()
                )));
            }
            offsets.push((l as u32, k as u32));
        }
    }
    let (staging, starts) = stage(
        ctx,
        layers.iter().flatten().copied(),
        &format!("{} staging", image.name()),
    )?;
    let regions: Vec<_> = offsets
        .iter()
        .zip(starts)
        .map(|(&(layer, level), offset)| {
            let (w, h) = image.level_extent(level);
            vk::BufferImageCopy::default()
                .buffer_offset(offset as u64)
                .image_subresource(subresource(image, level).base_array_layer(layer))
                .image_extent(vk::Extent3D {
                    width: w,
                    height: h,
                    depth: 1,
                })
        })
        .collect();
    ctx.one_shot(|rec| {
        let dst = vk::ImageLayout::TRANSFER_DST_OPTIMAL;
        transition_images(rec, &[all_mips(image, vk::ImageLayout::UNDEFINED, dst)]);
        // SAFETY: regions lie within the staging buffer and the image's levels.
        unsafe {
            rec.device().cmd_copy_buffer_to_image(
                rec.raw(),
                staging.raw(),
                image.raw(),
                dst,
                &regions,
            )
        };
        transition_images(rec, &[all_mips(image, dst, final_layout)]);
        Ok(())
    })
}

/// One host-visible staging buffer holding `chunks` one after another, each 16-byte aligned,
/// and where each starts.
fn stage<'a>(
    ctx: &Arc<Context>,
    chunks: impl Iterator<Item = &'a [u8]> + Clone,
    name: &str,
) -> VkResult<(Buffer, Vec<usize>)> {
    let mut starts = Vec::new();
    let mut total = 0usize;
    for bytes in chunks.clone() {
        starts.push(total);
        total = (total + bytes.len()).next_multiple_of(16);
    }
    let mut staging = Buffer::new(
        ctx,
        total.max(16) as u64,
        vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::CpuToGpu,
        name,
    )?;
    for (bytes, &start) in chunks.zip(&starts) {
        // SAFETY: the staging buffer was just made: no submission can read it yet.
        unsafe { staging.write(start, bytes)? };
    }
    Ok((staging, starts))
}

fn subresource(image: &Image, level: u32) -> vk::ImageSubresourceLayers {
    vk::ImageSubresourceLayers::default()
        .aspect_mask(image.desc().aspect)
        .mip_level(level)
        .layer_count(1)
}

/// Reads mip `level` back as tightly packed rows. The image must be in `layout`, and stays in it.
pub fn read_mip(
    ctx: &Arc<Context>,
    image: &Image,
    level: u32,
    layout: vk::ImageLayout,
) -> VkResult<Vec<u8>> {
    let texel = texel_size(image.desc().format)?;
    let (w, h) = image.level_extent(level);
    let size = (w as usize * h as usize * texel) as u64;
    let readback = Readback::new(ctx, size, &format!("{} readback", image.name()))?;
    let src = vk::ImageLayout::TRANSFER_SRC_OPTIMAL;
    ctx.one_shot(|rec| {
        transition_images(rec, &[all_mips(image, layout, src)]);
        let region = vk::BufferImageCopy::default()
            .image_subresource(subresource(image, level))
            .image_extent(vk::Extent3D {
                width: w,
                height: h,
                depth: 1,
            });
        readback.record_copy_from_image(rec, image, region)?;
        transition_images(rec, &[all_mips(image, src, layout)]);
        Ok(())
    })?;
    Ok(readback.bytes()?.to_vec())
}

/// Texels for rectangles of an image's levels, staged in host-visible memory, to be copied in
/// a command buffer of the caller's: the partial updates of a map that lives across frames.
/// Keep it alive until that command buffer has completed.
pub struct StagedRegions {
    staging: Buffer,
    copies: Vec<vk::BufferImageCopy>,
    /// What the regions were checked against: an image recorded into must match it.
    staged_for: ImageDesc,
}

/// One rectangle of a level: its level, `[x0, y0, width, height]`, and its texels, tightly
/// packed rows in the image's format.
pub type RegionTexels<'a> = (u32, [u32; 4], &'a [u8]);

impl StagedRegions {
    /// Stages `regions` of `image`, checking each lies within its level and holds its bytes.
    pub fn new(
        ctx: &Arc<Context>,
        image: &Image,
        regions: &[RegionTexels],
    ) -> VkResult<StagedRegions> {
        let texel = texel_size(image.desc().format)?;
        for &(level, [x, y, w, h], bytes) in regions {
            let (lw, lh) = image.level_extent(level);
            let fits = level < image.desc().mip_levels
                && x.checked_add(w).is_some_and(|e| e <= lw)
                && y.checked_add(h).is_some_and(|e| e <= lh);
            if !fits || bytes.len() != w as usize * h as usize * texel {
                return Err(VkError::Invalid(format!(
                    "region {x},{y} {w}x{h} of mip {level} of {:?} ({lw}x{lh}): {} bytes",
                    image.name(),
                    bytes.len()
                )));
            }
        }
        let (staging, starts) = stage(
            ctx,
            regions.iter().map(|r| r.2),
            &format!("{} region staging", image.name()),
        )?;
        let mut copies = Vec::with_capacity(regions.len());
        for (&(level, [x, y, w, h], _), &offset) in regions.iter().zip(&starts) {
            copies.push(
                vk::BufferImageCopy::default()
                    .buffer_offset(offset as u64)
                    .image_subresource(subresource(image, level))
                    .image_offset(vk::Offset3D {
                        x: x as i32,
                        y: y as i32,
                        z: 0,
                    })
                    .image_extent(vk::Extent3D {
                        width: w,
                        height: h,
                        depth: 1,
                    }),
            );
        }
        Ok(StagedRegions {
            staging,
            copies,
            staged_for: *image.desc(),
        })
    }

    /// Records the copies into `image` (the one staged for, or one of the same size, format and
    /// mip count), which must be in `layout` (`GENERAL` or `TRANSFER_DST_OPTIMAL`) with earlier
    /// accesses made available to transfers. Another image or layout is an error.
    pub fn record(&self, rec: &Recording, image: &Image, layout: vk::ImageLayout) -> VkResult<()> {
        if !same_shape(image.desc(), &self.staged_for) {
            return Err(VkError::Invalid(format!(
                "regions staged for a {:?} image recorded into {:?}, a {:?} one",
                shape(&self.staged_for),
                image.name(),
                shape(image.desc())
            )));
        }
        if layout != vk::ImageLayout::GENERAL && layout != vk::ImageLayout::TRANSFER_DST_OPTIMAL {
            return Err(VkError::Invalid(format!(
                "staged regions copied into {:?} in {layout:?}",
                image.name()
            )));
        }
        if self.copies.is_empty() {
            return Ok(());
        }
        // SAFETY: the copies were checked against the levels of an image of this shape and lie
        // in the staging buffer.
        unsafe {
            rec.device().cmd_copy_buffer_to_image(
                rec.raw(),
                self.staging.raw(),
                image.raw(),
                layout,
                &self.copies,
            )
        };
        Ok(())
    }
}

/// Size, format and mip count: what decides whether a region fits an image.
fn shape(desc: &ImageDesc) -> (u32, u32, vk::Format, u32) {
    (desc.width, desc.height, desc.format, desc.mip_levels)
}

fn same_shape(a: &ImageDesc, b: &ImageDesc) -> bool {
    shape(a) == shape(b)
}

/// Records copies of the same rectangles (`(level, [x0, y0, width, height])`) from `src` to `dst`,
/// in the layouts named. The images must have one format and size and hold every rectangle in
/// both; otherwise nothing is recorded and the error says why.
pub fn record_copy_regions(
    rec: &Recording,
    (src, src_layout): (&Image, vk::ImageLayout),
    (dst, dst_layout): (&Image, vk::ImageLayout),
    regions: &[(u32, [u32; 4])],
) -> VkResult<()> {
    let (s, d) = (src.desc(), dst.desc());
    if (s.width, s.height, s.format) != (d.width, d.height, d.format) {
        return Err(VkError::Invalid(format!(
            "region copies from {:?} ({:?}) to {:?} ({:?}): sizes or formats differ",
            src.name(),
            shape(s),
            dst.name(),
            shape(d)
        )));
    }
    let levels = s.mip_levels.min(d.mip_levels);
    for &(level, [x, y, w, h]) in regions {
        let (lw, lh) = src.level_extent(level);
        let fits = level < levels
            && x.checked_add(w).is_some_and(|e| e <= lw)
            && y.checked_add(h).is_some_and(|e| e <= lh);
        if !fits {
            return Err(VkError::Invalid(format!(
                "region {x},{y} {w}x{h} of mip {level} copied from {:?} to {:?} ({lw}x{lh})",
                src.name(),
                dst.name()
            )));
        }
    }
    if regions.is_empty() {
        return Ok(());
    }
    let copies: Vec<vk::ImageCopy> = regions
        .iter()
        .map(|&(level, [x, y, w, h])| {
            let offset = vk::Offset3D {
                x: x as i32,
                y: y as i32,
                z: 0,
            };
            vk::ImageCopy::default()
                .src_subresource(subresource(src, level))
                .dst_subresource(subresource(dst, level))
                .src_offset(offset)
                .dst_offset(offset)
                .extent(vk::Extent3D {
                    width: w,
                    height: h,
                    depth: 1,
                })
        })
        .collect();
    // SAFETY: the images have one format and size and their levels hold the rectangles
    // (checked above).
    unsafe {
        rec.device().cmd_copy_image(
            rec.raw(),
            src.raw(),
            src_layout,
            dst.raw(),
            dst_layout,
            &copies,
        )
    };
    Ok(())
}

/// RGBA half-float texels (little-endian, as the host reads them) as f32.
pub fn half_floats_to_rgba(bytes: &[u8]) -> Vec<[f32; 4]> {
    let halves: Vec<u16> = bytemuck::pod_collect_to_vec(bytes);
    halves
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]].map(half_to_f32))
        .collect()
}

/// An IEEE half float's value.
fn half_to_f32(h: u16) -> f32 {
    let sign = if h & 0x8000 != 0 { -1.0 } else { 1.0 };
    let exponent = i32::from((h >> 10) & 0x1f);
    let mantissa = f32::from(h & 0x3ff);
    sign * match exponent {
        0 => mantissa * 2f32.powi(-24),
        31 if mantissa == 0.0 => f32::INFINITY,
        31 => f32::NAN,
        e => (1.0 + mantissa / 1024.0) * 2f32.powi(e - 15),
    }
}

#[cfg(test)]
mod half_tests {
    use super::half_to_f32;

    #[test]
    fn half_floats_decode() {
        assert_eq!(half_to_f32(0x3c00), 1.0);
        assert_eq!(half_to_f32(0xc000), -2.0);
        assert_eq!(half_to_f32(0x7bff), 65504.0);
        assert_eq!(half_to_f32(0x0001), 2f32.powi(-24));
        assert_eq!(half_to_f32(0x7c00), f32::INFINITY);
        assert!(half_to_f32(0x7e00).is_nan());
        assert_eq!(half_to_f32(0x3555), 0.333_251_95);
    }
}
