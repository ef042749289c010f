//! Set 2 of layered surfaces (`shaders/include/terrain_layers.glsl`): per layered material, its
//! layers' colour and detail as two array images (layer k in array layer k), its splat map, and
//! a parameter block (blend mode, layer count, each layer's tiling and depth). Array layers are
//! one size, so each layer's textures are resized to the largest among them; a texture a layer
//! lacks is filled with what means "nothing here" (white albedo, a flat normal, full roughness).
//!
//! - binding 0, `layer_albedo_height`: sRGB albedo, and in alpha the layer's height times its
//!   depth (alpha is never sRGB-encoded), for the shading weights of the `height` blends;
//! - binding 1, `layer_normal_roughness`: tangent-space normal (OpenGL convention), roughness;
//! - binding 2, `layer_weights`: the splat map, bilinear and clamped like `terrain::SplatMap`;
//! - binding 3: `LayerUniform`.

use std::sync::Arc;

use ash::vk;
use image::{imageops::FilterType, DynamicImage, RgbaImage};

use crate::heightfield::Channel;
use crate::render::kit::texture_mips::mip_chain;
use crate::render::shader_interface::{
    LayerUniform, BINDING_LAYER_ALBEDO_HEIGHT, BINDING_LAYER_NORMAL_ROUGHNESS,
    BINDING_LAYER_PARAMS, BINDING_LAYER_WEIGHTS,
};
use crate::scene::{
    LayerWeights, Layers, LayersError, Material, MaterialLayer, SceneImage, TextureRef,
};
use crate::terrain::BlendMode;
use crate::vk::{
    upload_layers, upload_mips, Bind, Buffer, Context, DescriptorLayout, DescriptorPool,
    DescriptorSet, Image, ImageDesc, Sampler, VkError, VkResult,
};

/// The layout of set 2.
pub fn layer_layout(ctx: &Arc<Context>) -> VkResult<DescriptorLayout> {
    let tex = |b| (b, vk::DescriptorType::COMBINED_IMAGE_SAMPLER);
    let bindings = [
        tex(BINDING_LAYER_ALBEDO_HEIGHT),
        tex(BINDING_LAYER_NORMAL_ROUGHNESS),
        tex(BINDING_LAYER_WEIGHTS),
        (BINDING_LAYER_PARAMS, vk::DescriptorType::UNIFORM_BUFFER),
    ];
    DescriptorLayout::new(
        ctx,
        &bindings,
        vk::ShaderStageFlags::FRAGMENT,
        "layer layout",
    )
}

/// One set per drawn layered material, with what it points at.
pub struct LayerSets {
    _pool: DescriptorPool,
    images: Vec<Image>,
    _buffers: Vec<Buffer>,
    _samplers: [Sampler; 2],
    sets: Vec<Option<DescriptorSet>>,
    /// By material: its splat image's index in `images`.
    splats: Vec<Option<usize>>,
}

impl LayerSets {
    /// Sets for the materials `layered` marks (each has layers, checked by the plan).
    pub fn new(
        ctx: &Arc<Context>,
        layout: &DescriptorLayout,
        materials: &[Material],
        images: &[SceneImage],
        layered: &[bool],
    ) -> VkResult<LayerSets> {
        let count = layered.iter().filter(|l| **l).count().max(1) as u32;
        let pool = DescriptorPool::new(ctx, count, 4 * count, "layer sets")?;
        let tiled = Sampler::new(
            ctx,
            vk::Filter::LINEAR,
            vk::SamplerAddressMode::REPEAT,
            "layer sampler",
        )?;
        let clamped = Sampler::new(
            ctx,
            vk::Filter::LINEAR,
            vk::SamplerAddressMode::CLAMP_TO_EDGE,
            "splat sampler",
        )?;
        let mut sets = vec![None; materials.len()];
        let mut splats = vec![None; materials.len()];
        let (mut owned_images, mut buffers) = (Vec::new(), Vec::new());
        for (index, material) in materials.iter().enumerate() {
            let Some(layers) = material.layers.as_ref().filter(|_| layered[index]) else {
                continue;
            };
            let name = &material.name;
            let colour = layer_array(ctx, layers, images, true, &format!("{name} layer albedo"))?;
            let detail = layer_array(ctx, layers, images, false, &format!("{name} layer normals"))?;
            let splat = layers.splat().ok_or_else(|| {
                VkError::Invalid(format!("material {name:?}: {}", LayersError::Unbaked))
            })?;
            let splat = splat_image(ctx, &images[splat.image], &format!("{name} splat"))?;
            let buffer = Buffer::with_data(
                ctx,
                bytemuck::bytes_of(&uniform(layers)),
                vk::BufferUsageFlags::UNIFORM_BUFFER,
                &format!("{name} layer parameters"),
            )?;
            let binds = [
                Bind::Texture(BINDING_LAYER_ALBEDO_HEIGHT, colour.view(), &tiled),
                Bind::Texture(BINDING_LAYER_NORMAL_ROUGHNESS, detail.view(), &tiled),
                Bind::Texture(BINDING_LAYER_WEIGHTS, splat.view(), &clamped),
                Bind::Uniform(BINDING_LAYER_PARAMS, &buffer),
            ];
            sets[index] = Some(pool.allocate(layout, &binds)?);
            splats[index] = Some(owned_images.len() + 2);
            owned_images.extend([colour, detail, splat]);
            buffers.push(buffer);
        }
        Ok(LayerSets {
            _pool: pool,
            images: owned_images,
            _buffers: buffers,
            _samplers: [tiled, clamped],
            sets,
            splats,
        })
    }

    /// The splat image material `index` is shaded with (16-bit RGBA, `SHADER_READ_ONLY_OPTIMAL`
    /// between frames), if it is a drawn layered material: painting updates it in place.
    pub fn splat_image(&self, index: usize) -> Option<&Image> {
        self.splats
            .get(index)
            .copied()
            .flatten()
            .map(|k| &self.images[k])
    }

    /// The set of material `index`, if it is a drawn layered material.
    pub fn set(&self, index: usize) -> Option<DescriptorSet> {
        self.sets.get(index).cloned().flatten()
    }
}

fn uniform(layers: &Layers) -> LayerUniform {
    let mode = match layers.mode {
        BlendMode::Alpha => 0,
        BlendMode::Height => 1,
        BlendMode::HeightIntersect => 2,
    };
    let per_layer =
        |f: fn(&MaterialLayer) -> f32| std::array::from_fn(|k| layers.layers.get(k).map_or(0.0, f));
    let normals = layers
        .layers
        .iter()
        .enumerate()
        .filter(|(_, l)| l.normal.is_some())
        .fold(0u32, |bits, (k, _)| bits | 1 << k);
    LayerUniform {
        info: [
            mode,
            layers.layers.len() as u32,
            normals,
            u32::from(matches!(layers.weights, LayerWeights::BakedVertexColors(_))),
        ],
        tiling: per_layer(|l| l.tiling),
        depth: per_layer(|l| l.depth),
    }
}

/// The side every array layer is resized to: the largest texture any layer names.
fn array_side(layers: &Layers, images: &[SceneImage]) -> u32 {
    layers
        .layers
        .iter()
        .flat_map(|l| [Some(l.height), l.albedo, l.normal, l.roughness])
        .flatten()
        .map(|t| {
            let p = &images[t.image].pixels;
            p.width().max(p.height())
        })
        .max()
        .unwrap_or(1)
}

/// `texture`'s image at `side` x `side`, RGBA8 (resized with a triangle filter if needed).
fn resized(images: &[SceneImage], texture: &TextureRef, side: u32) -> RgbaImage {
    let pixels: &DynamicImage = &images[texture.image].pixels;
    let rgba = pixels.to_rgba8();
    if rgba.dimensions() == (side, side) {
        rgba
    } else {
        image::imageops::resize(&rgba, side, side, FilterType::Triangle)
    }
}

/// Channel `channel` of a texel as stored in 8 bits.
fn channel_of(p: &image::Rgba<u8>, channel: Channel) -> u8 {
    match channel {
        Channel::R | Channel::Luma => p.0[0],
        Channel::G => p.0[1],
        Channel::B => p.0[2],
        Channel::A => p.0[3],
    }
}

/// Writes channels `channels` of every texel of `rgba` from `source` through `pick`, or `default`
/// without one.
fn fill(
    rgba: &mut [u8],
    source: Option<RgbaImage>,
    channels: std::ops::Range<usize>,
    default: u8,
    pick: impl Fn(&image::Rgba<u8>, usize) -> u8,
) {
    match source {
        Some(image) => {
            for (texel, p) in rgba.chunks_exact_mut(4).zip(image.pixels()) {
                for c in channels.clone() {
                    texel[c] = pick(p, c);
                }
            }
        }
        None => {
            for texel in rgba.chunks_exact_mut(4) {
                texel[channels.clone()].fill(default);
            }
        }
    }
}

/// The colour array (`colour`: albedo and height) or the detail array (normal and roughness).
fn layer_array(
    ctx: &Arc<Context>,
    layers: &Layers,
    images: &[SceneImage],
    colour: bool,
    name: &str,
) -> VkResult<Image> {
    let side = array_side(layers, images);
    let texels = side as usize * side as usize;
    let mut chains = Vec::with_capacity(layers.layers.len());
    for l in &layers.layers {
        let mut rgba = vec![0u8; texels * 4];
        let texture = |t: Option<&TextureRef>| t.map(|t| resized(images, t, side));
        if colour {
            fill(&mut rgba, texture(l.albedo.as_ref()), 0..3, 255, |p, c| {
                p.0[c]
            });
            let (depth, channel) = (l.depth, l.height_channel);
            fill(&mut rgba, texture(Some(&l.height)), 3..4, 0, |p, _| {
                (f32::from(channel_of(p, channel)) * depth).round() as u8
            });
        } else {
            // A flat normal, (0, 0, 1) encoded.
            let flat = [128, 128, 255];
            fill(&mut rgba, texture(l.normal.as_ref()), 0..3, 0, |p, c| {
                p.0[c]
            });
            if l.normal.is_none() {
                rgba.chunks_exact_mut(4)
                    .for_each(|t| t[..3].copy_from_slice(&flat));
            }
            fill(
                &mut rgba,
                texture(l.roughness.as_ref()),
                3..4,
                255,
                |p, _| p.0[0],
            );
        }
        chains.push(mip_chain(side, side, &rgba, colour));
    }
    let desc = ImageDesc {
        width: side,
        height: side,
        format: if colour {
            vk::Format::R8G8B8A8_SRGB
        } else {
            vk::Format::R8G8B8A8_UNORM
        },
        mip_levels: chains[0].len() as u32,
        usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    let image = Image::new_array(ctx, desc, chains.len() as u32, name)?;
    let slices: Vec<Vec<&[u8]>> = chains
        .iter()
        .map(|levels| levels.iter().map(Vec::as_slice).collect())
        .collect();
    upload_layers(
        ctx,
        &image,
        &slices,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    )?;
    Ok(image)
}

/// The splat map as 16-bit unorm RGBA, one level (it is magnified, never minified, on terrain).
fn splat_image(ctx: &Arc<Context>, source: &SceneImage, name: &str) -> VkResult<Image> {
    let rgba = source.pixels.to_rgba16();
    let bytes: Vec<u8> = rgba.as_raw().iter().flat_map(|c| c.to_ne_bytes()).collect();
    let desc = ImageDesc {
        width: rgba.width(),
        height: rgba.height(),
        format: vk::Format::R16G16B16A16_UNORM,
        mip_levels: 1,
        usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    let image = Image::new(ctx, desc, name)?;
    upload_mips(
        ctx,
        &image,
        &[&bytes],
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    )?;
    Ok(image)
}
