//! The environment maps on the GPU and the kernels that build them: the source image (uploaded
//! with its mip chain, then dropped), the irradiance map, the prefiltered specular levels and the
//! BRDF table, all built in one submission when the renderer is made.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use super::environment_plan::{
    EnvironmentPlan, BRDF_SAMPLES, IRRADIANCE_SOURCE_WIDTH, PREFILTER_SAMPLES,
};
use crate::environment::Environment;
use crate::render::compute_pass::ComputePass;
use crate::render::shader_interface::{
    EnvironmentParams, BINDING_ENV_BRDF, BINDING_ENV_IRRADIANCE, BINDING_ENV_OUT,
    BINDING_ENV_SOURCE, BINDING_ENV_SPECULAR,
};
use crate::vk::{
    half_floats_to_rgba, read_mip, transition_images, upload_mips, Bind, Context, DescriptorPool,
    DescriptorSet, Image, ImageDesc, ImageTransition, ImageView, Recording, Sampler, TimestampPool,
    VkResult,
};

const GROUP: u32 = 8;
const MAP_FORMAT: vk::Format = vk::Format::R16G16B16A16_SFLOAT;

/// An environment's light on the GPU, ready for the drawing passes.
pub struct EnvironmentLight {
    irradiance: Image,
    specular: Image,
    brdf: Image,
    /// Linear, repeating around the up axis, clamped at the poles.
    equirect_sampler: Sampler,
    /// Linear, clamped.
    table_sampler: Sampler,
    plan: EnvironmentPlan,
    build_ms: f64,
    /// GPU time of the kernels, when the queue has timestamps.
    build_gpu_ms: Option<f64>,
    /// The uploaded image, kept when the background shows it.
    source: Option<Image>,
}

/// The maps read back (tests): texels as RGBA, rows top to bottom.
#[derive(Debug, Clone)]
pub struct BakedEnvironment {
    /// The irradiance map: its size and texels.
    pub irradiance: ([u32; 2], Vec<[f32; 4]>),
    /// The prefiltered levels, finest (roughness 0) first: each size and texels.
    pub specular: Vec<([u32; 2], Vec<[f32; 4]>)>,
    /// The BRDF table (x: view cosine, y: roughness; r scale, g bias): its size and texels.
    pub brdf: ([u32; 2], Vec<[f32; 4]>),
}

impl EnvironmentLight {
    /// Uploads `env` and builds its maps, waiting for the GPU; `keep_source` keeps the uploaded
    /// image for the background.
    pub fn build(
        ctx: &Arc<Context>,
        env: &Environment,
        keep_source: bool,
    ) -> VkResult<EnvironmentLight> {
        let mut plan = EnvironmentPlan::of(env);
        plan.background = keep_source;
        let started = Instant::now();
        let source = upload_source(ctx, env, &plan)?;
        let maps = Maps::new(ctx, &plan)?;
        let equirect_sampler = equirect_sampler(ctx)?;
        let table_sampler = Sampler::new(
            ctx,
            vk::Filter::LINEAR,
            vk::SamplerAddressMode::CLAMP_TO_EDGE,
            "BRDF table sampler",
        )?;
        let kernels = Kernels::new(ctx)?;
        let outputs = Outputs::new(&maps, &plan)?;
        let read = Bind::Texture(BINDING_ENV_SOURCE, source.view(), &equirect_sampler);
        let sets = KernelSets::new(ctx, &plan, &kernels, read, &outputs)?;
        // Without timestamps on the queue the build is simply not timed on the GPU.
        let timer = TimestampPool::new(ctx, 2, "environment build timestamps").ok();
        let build = MapBuild {
            plan: &plan,
            kernels: &kernels,
            sets: &sets,
            maps: &maps,
        };
        ctx.one_shot(|rec| build.record(rec, timer.as_ref()))?;
        let build_gpu_ms = gpu_ms(timer.as_ref())?;
        Ok(EnvironmentLight {
            irradiance: maps.irradiance,
            specular: maps.specular,
            brdf: maps.brdf,
            equirect_sampler,
            table_sampler,
            plan,
            build_ms: started.elapsed().as_secs_f64() * 1e3,
            build_gpu_ms,
            source: keep_source.then_some(source),
        })
    }

    /// The uploaded environment image at `binding`, if it was kept for the background.
    pub fn background_bind(&self, binding: u32) -> Option<Bind<'_>> {
        let source = self.source.as_ref()?;
        Some(Bind::Texture(
            binding,
            source.view(),
            &self.equirect_sampler,
        ))
    }

    /// What was built.
    pub fn plan(&self) -> &EnvironmentPlan {
        &self.plan
    }

    /// CPU wall time of the upload and the build, in ms (one submission, waited for).
    pub fn build_ms(&self) -> f64 {
        self.build_ms
    }

    /// GPU time of the three kernels, in ms, when the queue has timestamps.
    pub fn build_gpu_ms(&self) -> Option<f64> {
        self.build_gpu_ms
    }

    /// The prefiltered map's last level (roughness 1), as the shaders' level of detail.
    pub fn last_specular_level(&self) -> f32 {
        (self.plan.specular_levels - 1) as f32
    }

    /// The drawing passes' binds of the three maps.
    pub fn binds(&self) -> [Bind<'_>; 3] {
        [
            Bind::Texture(
                BINDING_ENV_IRRADIANCE,
                self.irradiance.view(),
                &self.equirect_sampler,
            ),
            Bind::Texture(
                BINDING_ENV_SPECULAR,
                self.specular.view(),
                &self.equirect_sampler,
            ),
            Bind::Texture(BINDING_ENV_BRDF, self.brdf.view(), &self.table_sampler),
        ]
    }

    /// Reads every map back (tests, checks against `environment::reference`).
    pub fn read_back(&self, ctx: &Arc<Context>) -> VkResult<BakedEnvironment> {
        let layout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let level = |image: &Image, l: u32| -> VkResult<([u32; 2], Vec<[f32; 4]>)> {
            let (w, h) = image.level_extent(l);
            Ok((
                [w, h],
                half_floats_to_rgba(&read_mip(ctx, image, l, layout)?),
            ))
        };
        Ok(BakedEnvironment {
            irradiance: level(&self.irradiance, 0)?,
            specular: (0..self.plan.specular_levels)
                .map(|l| level(&self.specular, l))
                .collect::<VkResult<Vec<_>>>()?,
            brdf: level(&self.brdf, 0)?,
        })
    }
}

/// The drawing passes' binds when there is no environment: `stand_in` at each binding, which
/// no shader then reads.
pub(in crate::render) fn stand_in_binds<'a>(stand_in: &'a (ImageView, Sampler)) -> [Bind<'a>; 3] {
    [
        BINDING_ENV_IRRADIANCE,
        BINDING_ENV_SPECULAR,
        BINDING_ENV_BRDF,
    ]
    .map(|b| Bind::Texture(b, &stand_in.0, &stand_in.1))
}

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
struct Maps {
    irradiance: Image,
    specular: Image,
    brdf: Image,
}

impl Maps {
    /// The maps at the plan's sizes, not yet written.
    fn new(ctx: &Arc<Context>, plan: &EnvironmentPlan) -> VkResult<Maps> {
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
fn equirect_sampler(ctx: &Arc<Context>) -> VkResult<Sampler> {
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
fn upload_source(ctx: &Arc<Context>, env: &Environment, plan: &EnvironmentPlan) -> VkResult<Image> {
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
