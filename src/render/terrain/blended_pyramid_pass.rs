//! A terrain's blended height pyramid on the GPU (`blended_pyramid.comp`, Drobot 1.7.4): the
//! layers' heights and weights uploaded as two four-channel images, each given its max pyramid
//! (`pyramid.comp`'s rgba variants, the rule of `MaxPyramid::build_bilinear_bound`), then every
//! level of one height image written from the same level of both: level 0 the blended surface,
//! levels 1 up the conservative bound of `terrain::blended_pyramid`. The result is a height map
//! with its pyramid like any other, so every method reads blended terrain unchanged.
//!
//! A [`BlendedPyramid`] keeps its images, so that painted weights rebuild only what they
//! changed: the weights' level-0 texels are re-staged, their pyramid and the least-sum slack's
//! rebuilt over `regions_above` them, and the blend re-run over the same regions.

use std::sync::Arc;

use ash::vk;

use crate::heightfield::{mip_level_count, Address, Heightfield};
use crate::render::compute_pass::ComputePass;
use crate::render::kit::gpu_heightfield::HeightFormat;
use crate::render::maps::pyramid_pass::{regions_above, PyramidJob, PyramidPass, Region};
use crate::render::shader_interface::{
    BlendParams, BINDING_BLEND_LAYER_HEIGHTS, BINDING_BLEND_LAYER_WEIGHTS, BINDING_BLEND_OUT,
    BINDING_BLEND_SLACK, BLEND_ALPHA, BLEND_HEIGHT, BLEND_HEIGHT_INTERSECT,
};
use crate::terrain::{least_sum_slack, BlendMode, LayerStack, TexelRect};
use crate::vk::{
    memory_barrier, read_mip, transition_images, upload_mips, Bind, Context, DescriptorPool,
    DescriptorSet, Image, ImageDesc, ImageTransition, ImageView, Recording, RegionTexels, Sampler,
    StagedRegions, TimestampPool, VkError, VkResult,
};

const GROUP: u32 = 8;

/// The blend pass's push constants: mode, level, 16-bit output (round bounds up), unused; the
/// region written.
fn blend_push(mode: BlendMode, level: u32, unorm: bool, region: Region) -> BlendParams {
    let mode = match mode {
        BlendMode::Alpha => BLEND_ALPHA,
        BlendMode::Height => BLEND_HEIGHT,
        BlendMode::HeightIntersect => BLEND_HEIGHT_INTERSECT,
    };
    BlendParams {
        flags: [mode, level, u32::from(unorm), 0],
        region,
    }
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
    let value = |t: usize| std::array::from_fn(|k| maps.get(k).map_or(0.0, |m| m.data()[t]));
    let bytes = encode_channels(format, (0..texels).map(value));
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

/// Four channels per texel as `layer_format(format)` stores them.
fn encode_channels(format: HeightFormat, texels: impl Iterator<Item = [f32; 4]>) -> Vec<u8> {
    match format {
        HeightFormat::R16Unorm => texels
            .flat_map(|c| c.map(|v| (v.clamp(0.0, 1.0) * 65535.0).round() as u16))
            .flat_map(u16::to_ne_bytes)
            .collect(),
        HeightFormat::R32Float => texels.flatten().flat_map(f32::to_ne_bytes).collect(),
    }
}

/// The weights a texel's image holds after storing `w` in `format`, and its least-sum slack
/// (`terrain::least_sum_slack` of the stored weights, bytes rounded up in 16 bits), encoded.
fn encode_weights(format: HeightFormat, texels: &[[f32; 4]]) -> (Vec<u8>, Vec<u8>) {
    let stored: Vec<[f32; 4]> = match format {
        HeightFormat::R16Unorm => texels
            .iter()
            .map(|w| w.map(|v| f32::from((v.clamp(0.0, 1.0) * 65535.0).round() as u16) / 65535.0))
            .collect(),
        HeightFormat::R32Float => texels.to_vec(),
    };
    let slack: Vec<f32> = stored
        .iter()
        .map(|w| 1.0 - (((w[0] + w[1]) + w[2]) + w[3]).min(1.0))
        .collect();
    (
        encode_channels(format, stored.into_iter()),
        format.encode_up(&slack),
    )
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

/// A terrain's blended pyramid with the images it is built from, kept so that painted weights
/// can be re-blended where they changed.
pub struct BlendedPyramid {
    ctx: Arc<Context>,
    mode: BlendMode,
    format: HeightFormat,
    address: Address,
    layers: usize,
    heights: Image,
    weights: Image,
    slack: Image,
    blended: Image,
    pyramid: PyramidPass,
    jobs: [PyramidJob; 2],
    slack_pyramid: PyramidPass,
    slack_job: PyramidJob,
    pass: ComputePass,
    _views: Vec<ImageView>,
    _pool: DescriptorPool,
    sets: Vec<DescriptorSet>,
    _texels: Sampler,
}

impl BlendedPyramid {
    /// Uploads `stack`'s heights, weights and least-sum slack and prepares the blend in `mode`;
    /// nothing is built until [`BlendedPyramid::record_build`] runs. `address` is the terrain's
    /// addressing (the pyramids' level 1 wraps or clamps its margin).
    pub fn new(
        ctx: &Arc<Context>,
        stack: &LayerStack,
        mode: BlendMode,
        format: HeightFormat,
        address: Address,
    ) -> VkResult<BlendedPyramid> {
        let (layer_vk, suffix) = layer_format(format);
        check_storage(ctx, layer_vk, format)?;
        let heights = channel_image(ctx, stack.heights(), format, "terrain layer heights")?;
        let weights = channel_image(ctx, stack.weights(), format, "terrain layer weights")?;
        let slack = slack_image(ctx, stack, format)?;
        let levels = heights.desc().mip_levels;
        let blended = blended_image(ctx, &heights, format)?;
        let pyramid = PyramidPass::new(ctx, suffix)?;
        let jobs = [
            pyramid.prepare_image(&heights)?,
            pyramid.prepare_image(&weights)?,
        ];
        let slack_pyramid = PyramidPass::new(ctx, format.shader_suffix())?;
        let slack_job = slack_pyramid.prepare_image(&slack)?;
        let sampled = vk::DescriptorType::COMBINED_IMAGE_SAMPLER;
        let pass = ComputePass::plain(
            ctx,
            &format!("blended_pyramid.comp:{}", format.shader_suffix()),
            &[
                (BINDING_BLEND_LAYER_HEIGHTS, sampled),
                (BINDING_BLEND_LAYER_WEIGHTS, sampled),
                (BINDING_BLEND_OUT, vk::DescriptorType::STORAGE_IMAGE),
                (BINDING_BLEND_SLACK, sampled),
            ],
            std::mem::size_of::<BlendParams>() as u32,
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
                    pass.layout(),
                    &[
                        Bind::Texture(BINDING_BLEND_LAYER_HEIGHTS, heights.view(), &texels),
                        Bind::Texture(BINDING_BLEND_LAYER_WEIGHTS, weights.view(), &texels),
                        Bind::StorageImage(BINDING_BLEND_OUT, view),
                        Bind::Texture(BINDING_BLEND_SLACK, slack.view(), &texels),
                    ],
                )
            })
            .collect::<VkResult<Vec<_>>>()?;
        Ok(BlendedPyramid {
            ctx: ctx.clone(),
            mode,
            format,
            address,
            layers: stack.len(),
            heights,
            weights,
            slack,
            blended,
            pyramid,
            jobs,
            slack_pyramid,
            slack_job,
            pass,
            _views: views,
            _pool: pool,
            sets,
            _texels: texels,
        })
    }

    /// The blended heights with their pyramid (in `SHADER_READ_ONLY_OPTIMAL` once built).
    pub fn blended(&self) -> &Image {
        &self.blended
    }

    /// How many layers it blends.
    pub fn layers(&self) -> usize {
        self.layers
    }

    /// Records the whole build: the layers', weights' and slack's pyramids, then every blended
    /// level. Record it once, first; every image ends in `SHADER_READ_ONLY_OPTIMAL`.
    pub fn record_build(&self, rec: &Recording) -> VkResult<()> {
        self.pyramid
            .record_image(rec, &self.heights, self.address, &self.jobs[0])?;
        self.pyramid
            .record_image(rec, &self.weights, self.address, &self.jobs[1])?;
        self.slack_pyramid
            .record_image(rec, &self.slack, self.address, &self.slack_job)?;
        let whole: Vec<Vec<Region>> = (0..self.blended.desc().mip_levels)
            .map(|l| {
                let (w, h) = self.blended.level_extent(l);
                vec![[0, 0, w, h]]
            })
            .collect();
        self.record_blend(rec, vk::ImageLayout::UNDEFINED, &whole)
    }

    /// Stages new weights for level-0 rectangles `rects` of the stack (`texels[k]` row-major over
    /// `rects[k]`), with their least-sum slack, for [`BlendedPyramid::record_weights`].
    pub fn stage_weights(
        &self,
        rects: &[TexelRect],
        texels: &[Vec<[f32; 4]>],
    ) -> VkResult<[StagedRegions; 2]> {
        let encoded: Vec<(Vec<u8>, Vec<u8>)> = texels
            .iter()
            .map(|t| encode_weights(self.format, t))
            .collect();
        let regions = |slack: bool| -> Vec<RegionTexels> {
            rects
                .iter()
                .zip(&encoded)
                .map(|(r, (w, s))| {
                    let bytes = if slack { s.as_slice() } else { w.as_slice() };
                    (0, [r.x0, r.y0, r.width(), r.height()], bytes)
                })
                .collect()
        };
        Ok([
            StagedRegions::new(&self.ctx, &self.weights, &regions(false))?,
            StagedRegions::new(&self.ctx, &self.slack, &regions(true))?,
        ])
    }

    /// Records the rebuild after new weights in `rects` (staged by `stage_weights`): the copies,
    /// the weights' and slack's pyramid nodes above them, and the blended texels of every level
    /// that read them. Returns those blended regions, level 0 first, for the maps built on top.
    pub fn record_weights(
        &self,
        rec: &Recording,
        staged: &[StagedRegions; 2],
        rects: &[TexelRect],
    ) -> VkResult<Vec<Vec<Region>>> {
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        let rw = vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE;
        let to_general: &dyn Fn(&Image) -> ImageTransition<'_> = &|image| ImageTransition {
            image,
            aspect: vk::ImageAspectFlags::COLOR,
            base_mip: 0,
            mip_count: image.desc().mip_levels,
            old: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            new: vk::ImageLayout::GENERAL,
            src: (
                vk::PipelineStageFlags2::FRAGMENT_SHADER | compute,
                vk::AccessFlags2::SHADER_SAMPLED_READ,
            ),
            dst: (
                vk::PipelineStageFlags2::COPY | compute,
                vk::AccessFlags2::TRANSFER_WRITE | rw,
            ),
        };
        transition_images(rec, &[to_general(&self.weights), to_general(&self.slack)]);
        staged[0].record(rec, &self.weights, vk::ImageLayout::GENERAL)?;
        staged[1].record(rec, &self.slack, vk::ImageLayout::GENERAL)?;
        memory_barrier(
            rec,
            (
                vk::PipelineStageFlags2::COPY,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (compute, rw),
        );
        let wrap = self.address == Address::Repeat;
        let above = regions_above(&self.weights, rects, wrap);
        self.pyramid
            .record_regions(rec, &self.weights, self.address, &self.jobs[1], &above)?;
        self.slack_pyramid.record_regions(
            rec,
            &self.slack,
            self.address,
            &self.slack_job,
            &above,
        )?;
        let mut regions = vec![rects
            .iter()
            .map(|r| [r.x0, r.y0, r.width(), r.height()])
            .collect::<Vec<Region>>()];
        regions.extend(above);
        self.record_blend(rec, vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL, &regions)?;
        Ok(regions)
    }

    /// Blends `regions[l]` of every level `l` (the inputs' pyramids built and readable), the
    /// blended image coming from `old`; it ends in `SHADER_READ_ONLY_OPTIMAL`.
    fn record_blend(
        &self,
        rec: &Recording,
        old: vk::ImageLayout,
        regions: &[Vec<Region>],
    ) -> VkResult<()> {
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        let levels = self.blended.desc().mip_levels;
        let whole = |old, new, src, dst| ImageTransition {
            image: &self.blended,
            aspect: vk::ImageAspectFlags::COLOR,
            base_mip: 0,
            mip_count: levels,
            old,
            new,
            src,
            dst,
        };
        let readers = (
            vk::PipelineStageFlags2::FRAGMENT_SHADER | compute | vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::SHADER_SAMPLED_READ | vk::AccessFlags2::TRANSFER_READ,
        );
        let before = if old == vk::ImageLayout::UNDEFINED {
            (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE)
        } else {
            readers
        };
        transition_images(
            rec,
            &[whole(
                old,
                vk::ImageLayout::GENERAL,
                before,
                (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE),
            )],
        );
        let unorm = self.format == HeightFormat::R16Unorm;
        for (level, (set, level_regions)) in self.sets.iter().zip(regions).enumerate() {
            let pipeline = self.pass.pipeline();
            pipeline.bind(rec, Some(set));
            for &region in level_regions {
                let push = blend_push(self.mode, level as u32, unorm, region);
                pipeline.push(rec, bytemuck::bytes_of(&push))?;
                rec.dispatch([region[2].div_ceil(GROUP), region[3].div_ceil(GROUP), 1]);
            }
        }
        transition_images(
            rec,
            &[whole(
                vk::ImageLayout::GENERAL,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE),
                readers,
            )],
        );
        Ok(())
    }

    /// Every blended level read back, level 0 first.
    pub fn read_levels(&self) -> VkResult<Vec<Vec<f32>>> {
        (0..self.blended.desc().mip_levels)
            .map(|l| {
                read_mip(
                    &self.ctx,
                    &self.blended,
                    l,
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                )
                .map(|bytes| self.format.decode(&bytes))
            })
            .collect()
    }
}

/// Refuses a format whose layer and blended images the device cannot write as storage images.
fn check_storage(ctx: &Context, layer_vk: vk::Format, format: HeightFormat) -> VkResult<()> {
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
    Ok(())
}

/// The blended heights, the same size and levels as the layers' `heights`.
fn blended_image(ctx: &Arc<Context>, heights: &Image, format: HeightFormat) -> VkResult<Image> {
    Image::new(
        ctx,
        ImageDesc {
            format: format.vk(),
            usage: vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_SRC,
            ..*heights.desc()
        },
        "blended terrain heights",
    )
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
    let built = BlendedPyramid::new(ctx, stack, mode, format, address)?;
    let ms = time_on_gpu(ctx, |rec| built.record_build(rec))?;
    Ok((built.read_levels()?, ms))
}

/// Runs `work` in one submission between timestamps; its GPU ms.
pub fn time_on_gpu(
    ctx: &Arc<Context>,
    work: impl FnOnce(&Recording) -> VkResult<()>,
) -> VkResult<f64> {
    let timestamps = TimestampPool::new(ctx, 2, "blended pyramid timestamps")?;
    let all = vk::PipelineStageFlags2::ALL_COMMANDS;
    ctx.one_shot(|rec| {
        timestamps.write(rec, all, 0)?;
        work(rec)?;
        timestamps.write(rec, all, 1)
    })?;
    let ticks = timestamps.read_ticks(2)?;
    Ok(timestamps.ticks_to_ms(ticks[0], ticks[1]))
}
