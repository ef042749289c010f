//! The height field on the GPU: one image holding level 0 and the max pyramid in its mip chain,
//! read through a point sampler (nearest texel, nearest mip: the pyramid's boxes) and a linear
//! sampler (the bilinear surface).

use std::sync::Arc;

use ash::vk;

use crate::heightfield::{mip_level_count, Address, Heightfield, MaxPyramid};
use crate::vk::{upload_mips, Context, Image, ImageDesc, Sampler, VkError, VkResult};

/// How heights are stored on the GPU.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum HeightFormat {
    /// 16-bit unsigned normalised: 1/65535 steps, half the memory of R32F.
    R16Unorm,
    /// 32-bit float.
    R32Float,
}

impl HeightFormat {
    /// The Vulkan format.
    pub fn vk(self) -> vk::Format {
        match self {
            HeightFormat::R16Unorm => vk::Format::R16_UNORM,
            HeightFormat::R32Float => vk::Format::R32_SFLOAT,
        }
    }

    /// The key suffix of the pyramid shader variant for this format.
    pub fn shader_suffix(self) -> &'static str {
        match self {
            HeightFormat::R16Unorm => "r16",
            HeightFormat::R32Float => "r32f",
        }
    }

    /// The stored bytes of `hf` at level 0.
    pub fn encode(self, values: &[f32]) -> Vec<u8> {
        match self {
            HeightFormat::R16Unorm => values
                .iter()
                .flat_map(|&h| ((h.clamp(0.0, 1.0) * 65535.0).round() as u16).to_ne_bytes())
                .collect(),
            HeightFormat::R32Float => bytemuck::cast_slice(values).to_vec(),
        }
    }

    /// Like [`HeightFormat::encode`], but a 16-bit value rounds up to the next step: for bounds,
    /// which must not drop below what they bound.
    pub fn encode_up(self, values: &[f32]) -> Vec<u8> {
        match self {
            HeightFormat::R16Unorm => values
                .iter()
                .flat_map(|&h| ((h.clamp(0.0, 1.0) * 65535.0).ceil() as u16).to_ne_bytes())
                .collect(),
            HeightFormat::R32Float => self.encode(values),
        }
    }

    /// Heights back from stored bytes (native-endian texels of this format), 0 to 1.
    pub fn decode(self, bytes: &[u8]) -> Vec<f32> {
        match self {
            HeightFormat::R16Unorm => bytes
                .chunks_exact(2)
                .map(|c| f32::from(u16::from_ne_bytes([c[0], c[1]])) / 65535.0)
                .collect(),
            HeightFormat::R32Float => bytes
                .chunks_exact(4)
                .map(|c| f32::from_ne_bytes([c[0], c[1], c[2], c[3]]))
                .collect(),
        }
    }
}

/// The sampler address mode of `address`: the one place the renderer maps the height field's
/// addressing (docs/conventions.md) to Vulkan, for the height samplers and the method map's.
pub(crate) fn sampler_address_mode(address: Address) -> vk::SamplerAddressMode {
    match address {
        Address::Repeat => vk::SamplerAddressMode::REPEAT,
        Address::Clamp => vk::SamplerAddressMode::CLAMP_TO_EDGE,
    }
}

/// The height image (level 0 uploaded, pyramid levels to be built) and its two samplers.
pub struct GpuHeightfield {
    /// The heights at level 0 and the max pyramid in the levels above (one level when no
    /// pyramid is wanted). Uploaded in `GENERAL` layout when the pyramid pass is to build the
    /// levels, else in `SHADER_READ_ONLY_OPTIMAL`.
    pub image: Image,
    /// Nearest-filtered sampler (`height_point` in the shaders): exact texels and pyramid nodes.
    pub point: Sampler,
    /// Bilinear sampler (`height_linear` in the shaders): the interpolated surface.
    pub linear: Sampler,
    /// How the heights are stored.
    pub format: HeightFormat,
    /// What lies outside the map; both samplers use it.
    pub address: Address,
}

impl GpuHeightfield {
    /// Uploads `hf` as level 0 of a full mip chain, leaving the image in `GENERAL` layout for the
    /// pyramid pass. Checks that the device can store, sample and filter `format`.
    pub fn upload(
        ctx: &Arc<Context>,
        hf: &Heightfield,
        format: HeightFormat,
        address: Address,
    ) -> VkResult<GpuHeightfield> {
        Self::upload_levels(ctx, hf, format, address, true)
    }

    /// Uploads `hf` alone, for methods that read no pyramid: one level, ready for sampling.
    pub fn upload_without_pyramid(
        ctx: &Arc<Context>,
        hf: &Heightfield,
        format: HeightFormat,
        address: Address,
    ) -> VkResult<GpuHeightfield> {
        Self::upload_levels(ctx, hf, format, address, false)
    }

    fn upload_levels(
        ctx: &Arc<Context>,
        hf: &Heightfield,
        format: HeightFormat,
        address: Address,
        pyramid: bool,
    ) -> VkResult<GpuHeightfield> {
        let mut needed = vk::FormatFeatureFlags::SAMPLED_IMAGE
            | vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR
            | vk::FormatFeatureFlags::TRANSFER_DST;
        if pyramid {
            needed |= vk::FormatFeatureFlags::STORAGE_IMAGE;
        }
        if !ctx.format_features(format.vk()).contains(needed)
            || (pyramid && format == HeightFormat::R16Unorm && !ctx.info().storage_r16)
        {
            return Err(VkError::Unsupported(format!(
                "{format:?} height images (storage, sampling and linear filtering)"
            )));
        }
        let desc = ImageDesc {
            width: hf.width(),
            height: hf.height(),
            format: format.vk(),
            mip_levels: if pyramid {
                mip_level_count(hf.width(), hf.height())
            } else {
                1
            },
            usage: if pyramid {
                vk::ImageUsageFlags::STORAGE
                    | vk::ImageUsageFlags::SAMPLED
                    | vk::ImageUsageFlags::TRANSFER_DST
                    | vk::ImageUsageFlags::TRANSFER_SRC
            } else {
                vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST
            },
            aspect: vk::ImageAspectFlags::COLOR,
        };
        let image = Image::new(ctx, desc, "height field")?;
        let level0 = format.encode(hf.data());
        let layout = if pyramid {
            vk::ImageLayout::GENERAL
        } else {
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL
        };
        upload_mips(ctx, &image, &[&level0], layout)?;
        Self::with_samplers(ctx, image, format, address)
    }

    /// `pyramid`'s levels uploaded as they are (level 0 the heights), for traversals through a
    /// pyramid built elsewhere: a blended terrain's conservative bound. In 16 bits the levels
    /// from 1 up round up to a step, so that no node drops below what it bounds.
    pub fn upload_prebuilt(
        ctx: &Arc<Context>,
        pyramid: &MaxPyramid,
        format: HeightFormat,
        address: Address,
    ) -> VkResult<GpuHeightfield> {
        let base = pyramid.level(0);
        let image = Image::new(
            ctx,
            ImageDesc {
                width: base.width,
                height: base.height,
                format: format.vk(),
                mip_levels: pyramid.level_count(),
                usage: vk::ImageUsageFlags::SAMPLED
                    | vk::ImageUsageFlags::TRANSFER_DST
                    | vk::ImageUsageFlags::TRANSFER_SRC,
                aspect: vk::ImageAspectFlags::COLOR,
            },
            "prebuilt height pyramid",
        )?;
        let levels: Vec<Vec<u8>> = pyramid
            .levels()
            .iter()
            .enumerate()
            .map(|(k, level)| match k {
                0 => format.encode(&level.data),
                _ => format.encode_up(&level.data),
            })
            .collect();
        let slices: Vec<&[u8]> = levels.iter().map(Vec::as_slice).collect();
        upload_mips(
            ctx,
            &image,
            &slices,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )?;
        Self::with_samplers(ctx, image, format, address)
    }

    fn with_samplers(
        ctx: &Arc<Context>,
        image: Image,
        format: HeightFormat,
        address: Address,
    ) -> VkResult<GpuHeightfield> {
        Ok(GpuHeightfield {
            image,
            point: Sampler::new(
                ctx,
                vk::Filter::NEAREST,
                sampler_address_mode(address),
                "height point sampler",
            )?,
            linear: Sampler::new(
                ctx,
                vk::Filter::LINEAR,
                sampler_address_mode(address),
                "height linear sampler",
            )?,
            format,
            address,
        })
    }

    /// `height_info` of the shaders' frame uniforms: width, height, mip levels, 1 for repeat.
    pub fn shader_info(&self) -> [f32; 4] {
        let d = self.image.desc();
        let repeat = if self.address == Address::Repeat {
            1.0
        } else {
            0.0
        };
        [d.width as f32, d.height as f32, d.mip_levels as f32, repeat]
    }

    /// Number of mip levels (level 0 plus the pyramid).
    pub fn levels(&self) -> u32 {
        self.image.desc().mip_levels
    }
}
