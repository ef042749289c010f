//! A terrain's blended height pyramid on the GPU (`blended_pyramid.comp`, paper 001 1.7.4): the
//! layers' heights and weights uploaded as two four-channel images, each given its max pyramid
//! (`pyramid.comp`'s rgba variants, the rule of `MaxPyramid::build_bilinear_bound`), then every
//! level of one height image written from the same level of both: level 0 the blended surface,
//! levels 1 up the conservative bound of `terrain::blended_pyramid`. The result is a height map
//! with its pyramid like any other, so every method reads blended terrain unchanged.

use std::sync::Arc;

use ash::vk;

use super::gpu_heightfield::HeightFormat;
use super::pyramid_pass::PyramidPass;
use crate::heightfield::{mip_level_count, Address, Heightfield};
use crate::shaders;
use crate::terrain::{least_sum_slack, BlendMode, LayerStack};
use crate::vk::{
    compute_pipeline, memory_barrier, read_mip, transition_images, upload_mips, Bind, Context,
    DescriptorLayout, DescriptorPool, Image, ImageDesc, ImageTransition, ImageView, Sampler,
    SpecConstants, TimestampPool, VkError, VkResult,
};

const GROUP: u32 = 8;

/// The blend pass's push constants: mode, level, 16-bit output (round bounds up), unused.
fn flags(mode: BlendMode, level: u32, unorm: bool) -> [u32; 4] {
    let mode = match mode {
        BlendMode::Alpha => 0,
        BlendMode::Height => 1,
        BlendMode::HeightIntersect => 2,
    };
    [mode, level, u32::from(unorm), 0]
}

/// The four-channel format a stack's layers are stored in next to height format `format`, and
/// `pyramid.comp`'s variant for it.
fn layer_format(format: HeightFormat) -> (vk::Format, &'static str) {
    match format {
        HeightFormat::R16Unorm => (vk::Format::R16G16B16A16_UNORM, "rgba16"),
        HeightFormat::R32Float => (vk::Format::R32G32B32A32_SFLOAT, "rgba32f"),
    }
}

/// Uploads `maps` (up to four, one size) as the channels of one image with a full mip chain, in
/// `GENERAL`, ready for its pyramid.
fn channel_image(
    ctx: &Arc<Context>,
    maps: &[Heightfield],
    format: HeightFormat,
    name: &str,
) -> VkResult<Image> {
    let (w, h) = (maps[0].width(), maps[0].height());
    let (vk_format, _) = layer_format(format);
    let texels = w as usize * h as usize;
    let value = |k: usize, t: usize| maps.get(k).map_or(0.0, |m| m.data()[t]);
    let bytes: Vec<u8> = match format {
        HeightFormat::R16Unorm => (0..texels)
            .flat_map(|t| (0..4).map(move |k| (t, k)))
            .flat_map(|(t, k)| {
                ((value(k, t).clamp(0.0, 1.0) * 65535.0).round() as u16).to_ne_bytes()
            })
            .collect(),
        HeightFormat::R32Float => (0..texels)
            .flat_map(|t| (0..4).map(move |k| (t, k)))
            .flat_map(|(t, k)| value(k, t).to_ne_bytes())
            .collect(),
    };
    let image = Image::new(
        ctx,
        ImageDesc {
            width: w,
            height: h,
            format: vk_format,
            mip_levels: mip_level_count(w, h),
            usage: vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_DST,
            aspect: vk::ImageAspectFlags::COLOR,
        },
        name,
    )?;
    upload_mips(ctx, &image, &[&bytes], vk::ImageLayout::GENERAL)?;
    Ok(image)
}

/// Uploads `terrain::least_sum_slack` of `stack` as the weights are stored (16-bit ones rounded
/// first, so the sums are the GPU's), rounded up in 16 bits so that no least sum comes out larger
/// than it is; in `GENERAL`, ready for its pyramid.
fn slack_image(ctx: &Arc<Context>, stack: &LayerStack, format: HeightFormat) -> VkResult<Image> {
    let stored = match format {
        HeightFormat::R16Unorm => stack.quantized_unorm16(),
        HeightFormat::R32Float => stack.clone(),
    };
    let slack = least_sum_slack(&stored);
    let bytes = format.encode_up(slack.data());
    let image = Image::new(
        ctx,
        ImageDesc {
            width: slack.width(),
            height: slack.height(),
            format: format.vk(),
            mip_levels: mip_level_count(slack.width(), slack.height()),
            usage: vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_DST,
            aspect: vk::ImageAspectFlags::COLOR,
        },
        "terrain weight-sum slack",
    )?;
    upload_mips(ctx, &image, &[&bytes], vk::ImageLayout::GENERAL)?;
    Ok(image)
}

/// Builds the blended pyramid of `stack` in `mode` on the GPU and reads every level back (level 0
/// first) with the build's GPU time in ms: the layers' and weights' pyramids and the blend.
/// `address` is the terrain's addressing (the pyramids' level 1 wraps or clamps its margin).
pub fn build_blended_pyramid_on_gpu(
    ctx: &Arc<Context>,
    stack: &LayerStack,
    mode: BlendMode,
    format: HeightFormat,
    address: Address,
) -> VkResult<(Vec<Vec<f32>>, f64)> {
    let (layer_vk, suffix) = layer_format(format);
    let storage = vk::FormatFeatureFlags::STORAGE_IMAGE | vk::FormatFeatureFlags::SAMPLED_IMAGE;
    let unorm = format == HeightFormat::R16Unorm;
    if !ctx.format_features(layer_vk).contains(storage)
        || !ctx.format_features(format.vk()).contains(storage)
        || (unorm && !ctx.info().storage_r16)
    {
        return Err(VkError::Unsupported(format!(
            "{format:?} terrain layers ({layer_vk:?} and {:?} storage images)",
            format.vk()
        )));
    }
    let heights = channel_image(ctx, stack.heights(), format, "terrain layer heights")?;
    let weights = channel_image(ctx, stack.weights(), format, "terrain layer weights")?;
    let slack = slack_image(ctx, stack, format)?;
    let levels = heights.desc().mip_levels;
    let blended = Image::new(
        ctx,
        ImageDesc {
            format: format.vk(),
            usage: vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_SRC,
            ..*heights.desc()
        },
        "blended terrain heights",
    )?;
    let pyramid = PyramidPass::new(ctx, suffix)?;
    let jobs = [
        pyramid.prepare_image(&heights)?,
        pyramid.prepare_image(&weights)?,
    ];
    let slack_pyramid = PyramidPass::new(ctx, format.shader_suffix())?;
    let slack_job = slack_pyramid.prepare_image(&slack)?;
    let key = format!("blended_pyramid.comp:{}", format.shader_suffix());
    let spirv = shaders::spirv(&key).ok_or_else(|| VkError::Invalid(format!("no shader {key}")))?;
    let layout = DescriptorLayout::new(
        ctx,
        &[
            (0, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
            (1, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
            (2, vk::DescriptorType::STORAGE_IMAGE),
            (3, vk::DescriptorType::COMBINED_IMAGE_SAMPLER),
        ],
        vk::ShaderStageFlags::COMPUTE,
        "blended pyramid layout",
    )?;
    let pipeline = compute_pipeline(
        ctx,
        spirv,
        &[layout.raw()],
        16,
        &SpecConstants::default(),
        "blended pyramid",
    )?;
    let texels = Sampler::new(
        ctx,
        vk::Filter::NEAREST,
        vk::SamplerAddressMode::CLAMP_TO_EDGE,
        "terrain layer texels",
    )?;
    let views = (0..levels)
        .map(|l| blended.level_view(l))
        .collect::<VkResult<Vec<ImageView>>>()?;
    let pool = DescriptorPool::new(ctx, levels, 3 * levels, "blended pyramid sets")?;
    let sets = views
        .iter()
        .map(|view| {
            pool.allocate(
                &layout,
                &[
                    Bind::Texture(0, heights.view(), texels.raw()),
                    Bind::Texture(1, weights.view(), texels.raw()),
                    Bind::StorageImage(2, view.raw()),
                    Bind::Texture(3, slack.view(), texels.raw()),
                ],
            )
        })
        .collect::<VkResult<Vec<_>>>()?;
    let timestamps = TimestampPool::new(ctx, 2, "blended pyramid timestamps")?;
    let all = vk::PipelineStageFlags2::ALL_COMMANDS;
    let whole = |old, new, src, dst| ImageTransition {
        image: blended.raw(),
        aspect: vk::ImageAspectFlags::COLOR,
        base_mip: 0,
        mip_count: levels,
        old,
        new,
        src,
        dst,
    };
    let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
    ctx.one_shot(|rec| {
        timestamps.write(rec, all, 0)?;
        pyramid.record_image(rec, &heights, address, &jobs[0])?;
        pyramid.record_image(rec, &weights, address, &jobs[1])?;
        slack_pyramid.record_image(rec, &slack, address, &slack_job)?;
        transition_images(
            rec,
            &[whole(
                vk::ImageLayout::UNDEFINED,
                vk::ImageLayout::GENERAL,
                (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
                (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE),
            )],
        );
        for (level, &set) in sets.iter().enumerate() {
            let (w, h) = blended.level_extent(level as u32);
            pipeline.bind(rec, Some(set));
            pipeline.push(rec, bytemuck::bytes_of(&flags(mode, level as u32, unorm)))?;
            rec.dispatch([w.div_ceil(GROUP), h.div_ceil(GROUP), 1]);
        }
        memory_barrier(
            rec,
            (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE),
            (compute, vk::AccessFlags2::SHADER_STORAGE_READ),
        );
        transition_images(
            rec,
            &[whole(
                vk::ImageLayout::GENERAL,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE),
                (
                    vk::PipelineStageFlags2::FRAGMENT_SHADER
                        | compute
                        | vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::SHADER_SAMPLED_READ | vk::AccessFlags2::TRANSFER_READ,
                ),
            )],
        );
        timestamps.write(rec, all, 1)?;
        Ok(())
    })?;
    let ticks = timestamps.read_ticks(2)?;
    let read = (0..levels)
        .map(|l| {
            read_mip(ctx, &blended, l, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL)
                .map(|bytes| format.decode(&bytes))
        })
        .collect::<VkResult<Vec<_>>>()?;
    Ok((read, timestamps.ticks_to_ms(ticks[0], ticks[1])))
}
