//! The precomputed map a method reads besides the height pyramid (cone ratios, quadric
//! coefficients): one float texel per height texel, uploaded once and read by integer texel
//! through binding 3.

use std::sync::Arc;

use ash::vk;

use crate::heightfield::{Address, MapData};
use crate::render::kit::gpu_heightfield::sampler_address_mode;
use crate::vk::{upload_mips, Context, Image, ImageDesc, Sampler, VkError, VkResult};

/// A map on the GPU, with the nearest sampler its binding uses.
pub struct GpuMethodMap {
    /// The map, one level, 32-bit float channels, shader-read-only.
    pub image: Image,
    /// Nearest filtering under the height field's addressing.
    pub sampler: Sampler,
}

impl GpuMethodMap {
    /// Uploads `data` as R32, RG32 or RGBA32 float, ready for sampling.
    pub fn upload(
        ctx: &Arc<Context>,
        data: &MapData,
        address: Address,
        name: &str,
    ) -> VkResult<GpuMethodMap> {
        let format = match data.channels {
            1 => vk::Format::R32_SFLOAT,
            2 => vk::Format::R32G32_SFLOAT,
            4 => vk::Format::R32G32B32A32_SFLOAT,
            n => return Err(VkError::Invalid(format!("map {name:?} with {n} channels"))),
        };
        let expected = data.width as usize * data.height as usize * data.channels as usize;
        if data.texels.len() != expected {
            return Err(VkError::Invalid(format!(
                "map {name:?}: {} floats for {expected}",
                data.texels.len()
            )));
        }
        let desc = ImageDesc {
            width: data.width,
            height: data.height,
            format,
            mip_levels: 1,
            usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
            aspect: vk::ImageAspectFlags::COLOR,
        };
        let image = Image::new(ctx, desc, name)?;
        let bytes: &[u8] = bytemuck::cast_slice(&data.texels);
        upload_mips(
            ctx,
            &image,
            &[bytes],
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        )?;
        let sampler = Sampler::new(
            ctx,
            vk::Filter::NEAREST,
            sampler_address_mode(address),
            &format!("{name} sampler"),
        )?;
        Ok(GpuMethodMap { image, sampler })
    }
}
