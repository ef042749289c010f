//! The material textures a frame samples: each scene image uploaded once per encoding it is read
//! with (sRGB for colours, UNORM for data) with a full mip chain, one sampler per distinct glTF
//! sampler, and a 1x1 white texture for empty slots. Only images some drawn material reads are
//! uploaded.

use std::collections::HashMap;
use std::sync::Arc;

use ash::vk;

use crate::render::kit::texture_mips::mip_chain;
use crate::scene::{Filter, SamplerDesc, SceneImage, TextureRef, Wrap};
use crate::vk::{upload_mips, Context, Image, ImageDesc, ImageView, Sampler, VkError, VkResult};

/// Uploaded images and samplers, created on first use.
pub struct SceneTextures {
    ctx: Arc<Context>,
    images: HashMap<(usize, bool), Image>,
    samplers: HashMap<SamplerDesc, Sampler>,
    white: Image,
}

impl SceneTextures {
    pub fn new(ctx: &Arc<Context>) -> VkResult<SceneTextures> {
        let white = upload_rgba(ctx, 1, 1, &[255; 4], false, "white texture")?;
        let mut textures = SceneTextures {
            ctx: ctx.clone(),
            images: HashMap::new(),
            samplers: HashMap::new(),
            white,
        };
        textures.sampler(&SamplerDesc::default())?;
        Ok(textures)
    }

    /// The view and sampler for `texture`, uploading its image on first use.
    pub fn bind(
        &mut self,
        images: &[SceneImage],
        texture: &TextureRef,
        srgb: bool,
    ) -> VkResult<(ImageView, Sampler)> {
        let key = (texture.image, srgb);
        if !self.images.contains_key(&key) {
            let source = images.get(texture.image).ok_or_else(|| {
                VkError::Invalid(format!(
                    "texture names image {} of {}",
                    texture.image,
                    images.len()
                ))
            })?;
            let rgba = source.pixels.to_rgba8();
            let name = format!("image {}", source.name);
            let image = upload_rgba(&self.ctx, rgba.width(), rgba.height(), &rgba, srgb, &name)?;
            self.images.insert(key, image);
        }
        let view = self.images[&key].view().clone();
        Ok((view, self.sampler(&texture.sampler)?))
    }

    /// The white texture with the default sampler, for slots without a texture.
    pub fn white(&mut self) -> VkResult<(ImageView, Sampler)> {
        Ok((
            self.white.view().clone(),
            self.sampler(&SamplerDesc::default())?,
        ))
    }

    fn sampler(&mut self, desc: &SamplerDesc) -> VkResult<Sampler> {
        if let Some(s) = self.samplers.get(desc) {
            return Ok(s.clone());
        }
        let filter = |f: Filter| match f {
            Filter::Nearest => vk::Filter::NEAREST,
            Filter::Linear => vk::Filter::LINEAR,
        };
        let wrap = |w: Wrap| match w {
            Wrap::Repeat => vk::SamplerAddressMode::REPEAT,
            Wrap::MirroredRepeat => vk::SamplerAddressMode::MIRRORED_REPEAT,
            Wrap::ClampToEdge => vk::SamplerAddressMode::CLAMP_TO_EDGE,
        };
        let (mipmap_mode, max_lod) = match desc.mipmaps {
            None => (vk::SamplerMipmapMode::NEAREST, 0.0),
            Some(Filter::Nearest) => (vk::SamplerMipmapMode::NEAREST, vk::LOD_CLAMP_NONE),
            Some(Filter::Linear) => (vk::SamplerMipmapMode::LINEAR, vk::LOD_CLAMP_NONE),
        };
        let info = vk::SamplerCreateInfo::default()
            .mag_filter(filter(desc.mag))
            .min_filter(filter(desc.min))
            .mipmap_mode(mipmap_mode)
            .address_mode_u(wrap(desc.wrap_u))
            .address_mode_v(wrap(desc.wrap_v))
            .address_mode_w(vk::SamplerAddressMode::REPEAT)
            .max_lod(max_lod);
        let name = format!("material sampler {}", self.samplers.len());
        let sampler = Sampler::from_info(&self.ctx, &info, &name)?;
        self.samplers.insert(*desc, sampler.clone());
        Ok(sampler)
    }
}

fn upload_rgba(
    ctx: &Arc<Context>,
    width: u32,
    height: u32,
    rgba: &[u8],
    srgb: bool,
    name: &str,
) -> VkResult<Image> {
    let levels = mip_chain(width, height, rgba, srgb);
    let desc = ImageDesc {
        width,
        height,
        format: if srgb {
            vk::Format::R8G8B8A8_SRGB
        } else {
            vk::Format::R8G8B8A8_UNORM
        },
        mip_levels: levels.len() as u32,
        usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    let image = Image::new(ctx, desc, name)?;
    let slices: Vec<&[u8]> = levels.iter().map(Vec::as_slice).collect();
    upload_mips(
        ctx,
        &image,
        &slices,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    )?;
    Ok(image)
}
