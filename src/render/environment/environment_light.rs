//! The environment maps on the GPU: the source image (uploaded with its mip chain, then dropped
//! unless the background shows it), the irradiance map, the prefiltered specular levels and the
//! BRDF table, all built in one submission when the renderer is made (`environment_kernels`).

use std::sync::Arc;
use std::time::Instant;

use ash::vk;

use super::environment_kernels::{build_maps, equirect_sampler, upload_source, Maps};
use super::environment_plan::EnvironmentPlan;
use crate::environment::Environment;
use crate::render::shader_interface::{
    BINDING_ENV_BRDF, BINDING_ENV_IRRADIANCE, BINDING_ENV_SOURCE, BINDING_ENV_SPECULAR,
};
use crate::vk::{
    half_floats_to_rgba, read_mip, Bind, Context, Image, ImageView, Sampler, VkResult,
};

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
        let read = Bind::Texture(BINDING_ENV_SOURCE, source.view(), &equirect_sampler);
        let build_gpu_ms = build_maps(ctx, &plan, &maps, read)?;
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
