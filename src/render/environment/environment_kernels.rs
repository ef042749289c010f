//! The kernels that build an environment's maps: the source image uploaded with its mip chain,
//! the map images they write, their descriptor sets, and the one recording that dispatches them
//! (irradiance, each prefiltered specular level, the BRDF table), timed where the queue can.

use std::sync::Arc;

use ash::vk;

use super::environment_plan::{
    EnvironmentPlan, BRDF_SAMPLES, IRRADIANCE_SOURCE_WIDTH, PREFILTER_SAMPLES,
};
use crate::environment::Environment;
use crate::render::compute_pass::ComputePass;
use crate::render::shader_interface::{EnvironmentParams, BINDING_ENV_OUT, BINDING_ENV_SOURCE};
use crate::vk::{
    transition_images, upload_mips, Bind, Context, DescriptorPool, DescriptorSet, Image, ImageDesc,
    ImageTransition, ImageView, Recording, Sampler, TimestampPool, VkResult,
};

const GROUP: u32 = 8;
const MAP_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// Builds `maps` from the source that `read` binds, in one submission waited for; returns the
/// kernels' GPU time in ms when the queue has timestamps.
pub(super) fn build_maps(
    ctx: &Arc<Context>,
    plan: &EnvironmentPlan,
    maps: &Maps,
    read: Bind,
) -> VkResult<Option<f64>> {
    let kernels = Kernels::new(ctx)?;
    let outputs = Outputs::new(maps, plan)?;
    let sets = KernelSets::new(ctx, plan, &kernels, read, &outputs)?;
    // Without timestamps on the queue the build is simply not timed on the GPU.
    let timer = TimestampPool::new(ctx, 2, "environment build timestamps").ok();
    let build = MapBuild {
        plan,
        kernels: &kernels,
        sets: &sets,
        maps,
    };
    ctx.one_shot(|rec| build.record(rec, timer.as_ref()))?;
    gpu_ms(timer.as_ref())
}

/// The three compute kernels.
struct Kernels {
    irradiance: ComputePass,
    prefilter: ComputePass,
    brdf: ComputePass,
}

impl Kernels {
    fn new(ctx: &Arc<Context>) -> VkResult<Kernels> {
        let push = std::mem::size_of::<EnvironmentParams>() as u32;
        let source = (
            BINDING_ENV_SOURCE,
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
        );
        let out = (BINDING_ENV_OUT, vk::DescriptorType::STORAGE_IMAGE);
        Ok(Kernels {
            irradiance: ComputePass::plain(
                ctx,
                "environment_irradiance.comp",
                &[source, out],
                push,
                "environment irradiance",
            )?,
            prefilter: ComputePass::plain(
                ctx,
                "environment_prefilter.comp",
                &[source, out],
                push,
                "environment prefilter",
            )?,
            brdf: ComputePass::plain(ctx, "brdf_table.comp", &[out], push, "BRDF table")?,
        })
    }
}

/// The per-level storage views the kernels write.
struct Outputs {
    irradiance: ImageView,
    specular: Vec<ImageView>,
    brdf: ImageView,
}

impl Outputs {
    /// The storage views of every level the kernels write into `maps`.
    fn new(maps: &Maps, plan: &EnvironmentPlan) -> VkResult<Outputs> {
        Ok(Outputs {
            irradiance: maps.irradiance.level_view(0)?,
            specular: (0..plan.specular_levels)
                .map(|l| maps.specular.level_view(l))
                .collect::<VkResult<Vec<_>>>()?,
            brdf: maps.brdf.level_view(0)?,
        })
    }
}

/// The three maps the kernels write.
pub(super) struct Maps {
    pub irradiance: Image,
    pub specular: Image,
    pub brdf: Image,
}

impl Maps {
    /// The maps at the plan's sizes, not yet written.
    pub(super) fn new(ctx: &Arc<Context>, plan: &EnvironmentPlan) -> VkResult<Maps> {
        Ok(Maps {
            irradiance: storage_map(ctx, plan.irradiance_size, 1, "environment irradiance")?,
            specular: storage_map(
                ctx,
                plan.specular_size,
                plan.specular_levels,
                "environment specular",
            )?,
            brdf: storage_map(ctx, plan.brdf_size, 1, "environment BRDF table")?,
        })
    }

    /// All three, for the layout transitions.
    fn all(&self) -> [&Image; 3] {
        [&self.irradiance, &self.specular, &self.brdf]
    }
}

/// A map image of `size` with `levels` mip levels the kernels write and the passes sample.
fn storage_map(ctx: &Arc<Context>, size: [u32; 2], levels: u32, name: &str) -> VkResult<Image> {
    let desc = ImageDesc {
        width: size[0],
        height: size[1],
        format: MAP_FORMAT,
        mip_levels: levels,
        usage: vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_SRC,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    Image::new(ctx, desc, name)
}

/// The sampler of the equirectangular maps: linear, repeating around the up axis, clamped at
/// the poles, over every mip level.
pub(super) fn equirect_sampler(ctx: &Arc<Context>) -> VkResult<Sampler> {
    Sampler::from_info(
        ctx,
        &vk::SamplerCreateInfo::default()
            .mag_filter(vk::Filter::LINEAR)
            .min_filter(vk::Filter::LINEAR)
            .mipmap_mode(vk::SamplerMipmapMode::LINEAR)
            .address_mode_u(vk::SamplerAddressMode::REPEAT)
            .address_mode_v(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .address_mode_w(vk::SamplerAddressMode::CLAMP_TO_EDGE)
            .max_lod(vk::LOD_CLAMP_NONE),
        "environment sampler",
    )
}

/// The kernels' descriptor sets, with the pool they come from.
struct KernelSets {
    irradiance: DescriptorSet,
    /// One per prefiltered level.
    specular: Vec<DescriptorSet>,
    brdf: DescriptorSet,
    _pool: DescriptorPool,
}

impl KernelSets {
    /// The sets of each kernel: the source (`read`) and the level it writes of `outputs`.
    fn new(
        ctx: &Arc<Context>,
        plan: &EnvironmentPlan,
        kernels: &Kernels,
        read: Bind,
        outputs: &Outputs,
    ) -> VkResult<KernelSets> {
        let sets = plan.specular_levels + 2;
        let pool = DescriptorPool::new(ctx, sets, 2 * sets, "environment sets")?;
        let write = |view| Bind::StorageImage(BINDING_ENV_OUT, view);
        let irradiance = pool.allocate(
            kernels.irradiance.layout(),
            &[read, write(&outputs.irradiance)],
        )?;
        let specular = outputs
            .specular
            .iter()
            .map(|v| pool.allocate(kernels.prefilter.layout(), &[read, write(v)]))
            .collect::<VkResult<Vec<_>>>()?;
        let brdf = pool.allocate(kernels.brdf.layout(), &[write(&outputs.brdf)])?;
        Ok(KernelSets {
            irradiance,
            specular,
            brdf,
            _pool: pool,
        })
    }
}

/// What one recording of the build reads.
struct MapBuild<'a> {
    plan: &'a EnvironmentPlan,
    kernels: &'a Kernels,
    sets: &'a KernelSets,
    maps: &'a Maps,
}

impl MapBuild<'_> {
    /// Records the whole build: the maps made writable, the three kernels, the maps made
    /// readable, timed by `timer` when there is one.
    fn record(&self, rec: &Recording, timer: Option<&TimestampPool>) -> VkResult<()> {
        if let Some(t) = timer {
            t.write(rec, vk::PipelineStageFlags2::ALL_COMMANDS, 0)?;
        }
        let images = self.maps.all();
        transition(
            rec,
            &images,
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::GENERAL,
        );
        self.dispatch_kernels(rec)?;
        if let Some(t) = timer {
            t.write(rec, vk::PipelineStageFlags2::COMPUTE_SHADER, 1)?;
        }
        transition(
            rec,
            &images,
            vk::ImageLayout::GENERAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
        );
        Ok(())
    }

    /// Records the irradiance kernel, the prefilter kernel once per level, then the BRDF table.
    fn dispatch_kernels(&self, rec: &Recording) -> VkResult<()> {
        let plan = self.plan;
        let (iw, ih) = source_level_size(plan);
        let irradiance_level = levels_to(plan.uploaded_size[0], IRRADIANCE_SOURCE_WIDTH);
        let base = EnvironmentParams {
            out_width: plan.irradiance_size[0],
            out_height: plan.irradiance_size[1],
            source_level: irradiance_level,
            source_width: iw,
            source_height: ih,
            samples: 0,
            roughness: 0.0,
            base_lod: 0.0,
        };
        dispatch(rec, &self.kernels.irradiance, &self.sets.irradiance, base)?;
        let last = (plan.specular_levels - 1) as f32;
        for (level, set) in self.sets.specular.iter().enumerate() {
            let (w, h) = self.maps.specular.level_extent(level as u32);
            let params = EnvironmentParams {
                out_width: w,
                out_height: h,
                source_level: 0,
                source_width: plan.uploaded_size[0],
                source_height: plan.uploaded_size[1],
                samples: PREFILTER_SAMPLES,
                roughness: level as f32 / last,
                base_lod: (plan.uploaded_size[0] as f32 / w as f32).log2().max(0.0),
            };
            dispatch(rec, &self.kernels.prefilter, set, params)?;
        }
        let params = EnvironmentParams {
            out_width: plan.brdf_size[0],
            out_height: plan.brdf_size[1],
            samples: BRDF_SAMPLES,
            ..base
        };
        dispatch(rec, &self.kernels.brdf, &self.sets.brdf, params)
    }
}

/// The GPU time between `timer`'s two stamps, in ms; `None` without a timer.
fn gpu_ms(timer: Option<&TimestampPool>) -> VkResult<Option<f64>> {
    match timer {
        Some(t) => {
            let ticks = t.read_ticks(2)?;
            Ok(Some(t.ticks_to_ms(ticks[0], ticks[1])))
        }
        None => Ok(None),
    }
}

fn dispatch(
    rec: &Recording,
    pass: &ComputePass,
    set: &DescriptorSet,
    params: EnvironmentParams,
) -> VkResult<()> {
    let groups = [
        params.out_width.div_ceil(GROUP),
        params.out_height.div_ceil(GROUP),
        1,
    ];
    pass.dispatch(rec, set, bytemuck::bytes_of(&params), groups)
}

fn transition(rec: &Recording, images: &[&Image], old: vk::ImageLayout, new: vk::ImageLayout) {
    let all: Vec<ImageTransition> = images
        .iter()
        .map(|&image| ImageTransition {
            image,
            aspect: vk::ImageAspectFlags::COLOR,
            base_mip: 0,
            mip_count: image.desc().mip_levels,
            old,
            new,
            src: (
                vk::PipelineStageFlags2::COMPUTE_SHADER,
                vk::AccessFlags2::SHADER_WRITE,
            ),
            dst: (
                vk::PipelineStageFlags2::ALL_COMMANDS,
                vk::AccessFlags2::SHADER_READ,
            ),
        })
        .collect();
    transition_images(rec, &all);
}

/// Halvings from `width` until it is at most `target`.
fn levels_to(mut width: u32, target: u32) -> u32 {
    let mut levels = 0;
    while width > target {
        width = (width / 2).max(1);
        levels += 1;
    }
    levels
}

/// The size of the uploaded level the irradiance kernel sums.
fn source_level_size(plan: &EnvironmentPlan) -> (u32, u32) {
    let k = levels_to(plan.uploaded_size[0], IRRADIANCE_SOURCE_WIDTH);
    (
        (plan.uploaded_size[0] >> k).max(1),
        (plan.uploaded_size[1] >> k).max(1),
    )
}

/// The environment as an RGBA32F image with its whole mip chain, box-filtered down to the
/// plan's uploaded size first.
pub(super) fn upload_source(
    ctx: &Arc<Context>,
    env: &Environment,
    plan: &EnvironmentPlan,
) -> VkResult<Image> {
    let mut level = env.clone();
    while level.width > plan.uploaded_size[0] {
        level = level.halved();
    }
    let mut levels = vec![level];
    while levels.last().is_some_and(|l| l.width > 1 || l.height > 1) {
        let next = levels.last().map(Environment::halved);
        levels.extend(next);
    }
    let bytes: Vec<Vec<f32>> = levels
        .iter()
        .map(|l| {
            l.texels
                .iter()
                .flat_map(|t| [t[0], t[1], t[2], 1.0])
                .collect()
        })
        .collect();
    let desc = ImageDesc {
        width: plan.uploaded_size[0],
        height: plan.uploaded_size[1],
        format: vk::Format::R32G32B32A32_SFLOAT,
        mip_levels: levels.len() as u32,
        usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    let image = Image::new(ctx, desc, &format!("environment {}", env.name))?;
    let slices: Vec<&[u8]> = bytes.iter().map(|b| bytemuck::cast_slice(b)).collect();
    upload_mips(
        ctx,
        &image,
        &slices,
        vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
    )?;
    Ok(image)
}
