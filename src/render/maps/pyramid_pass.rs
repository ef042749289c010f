//! The GPU max-pyramid builder: one compute dispatch per level, each reading the level below
//! through a storage view and writing its own, with a barrier between levels. Same rule as the
//! CPU builder (`MaxPyramid::build_bilinear_bound`), so the two are compared texel for texel in
//! tests.

use std::sync::Arc;

use ash::vk;

use crate::heightfield::Address;
use crate::render::compute_pass::ComputePass;
use crate::render::kit::gpu_heightfield::GpuHeightfield;
use crate::render::shader_interface::{
    PyramidParams, BINDING_PYRAMID_COARSE, BINDING_PYRAMID_FINE,
};
use crate::terrain::{coarse_span, TexelRect};
use crate::vk::{
    memory_barrier, transition_images, Bind, Context, DescriptorPool, DescriptorSet, Image,
    ImageTransition, ImageView, Recording, VkResult,
};

const GROUP: u32 = 8;

/// A rectangle of one level's texels: `[x0, y0, width, height]`.
pub type Region = [u32; 4];

/// Per level above level 0 of `image`, the regions whose nodes read a texel of `rects` (level-0
/// rectangles): what a change there makes stale, from `terrain::coarse_span`. Level 1 reads
/// one texel of margin (its nodes bound the bilinear surface); `wrap` for repeat addressing.
pub fn regions_above(image: &Image, rects: &[TexelRect], wrap: bool) -> Vec<Vec<Region>> {
    let mut current: Vec<Region> = rects
        .iter()
        .map(|r| [r.x0, r.y0, r.width(), r.height()])
        .collect();
    let mut levels = Vec::new();
    for level in 1..image.desc().mip_levels {
        let (fw, fh) = image.level_extent(level - 1);
        let (cw, ch) = image.level_extent(level);
        let margin = u32::from(level == 1);
        let mut next: Vec<Region> = Vec::new();
        for r in &current {
            let xs = coarse_span((r[0], r[0] + r[2] - 1), fw, cw, margin, wrap);
            let ys = coarse_span((r[1], r[1] + r[3] - 1), fh, ch, margin, wrap);
            for &(x0, x1) in &xs {
                for &(y0, y1) in &ys {
                    let region = [x0, y0, x1 - x0 + 1, y1 - y0 + 1];
                    if !next.contains(&region) {
                        next.push(region);
                    }
                }
            }
        }
        levels.push(next.clone());
        current = next;
    }
    levels
}

/// The compute pipeline that builds one pyramid level from the one below.
pub struct PyramidPass {
    ctx: Arc<Context>,
    pass: ComputePass,
}

/// Per-height-field resources of one build: a view per level and a set per dispatch. Keep it
/// alive until the command buffer that uses it has finished.
pub struct PyramidJob {
    _views: Vec<ImageView>,
    _pool: DescriptorPool,
    sets: Vec<DescriptorSet>,
}

impl PyramidPass {
    /// Creates the pipeline for heights stored as `suffix` ("r16" or "r32f").
    pub fn new(ctx: &Arc<Context>, suffix: &str) -> VkResult<PyramidPass> {
        let pass = ComputePass::plain(
            ctx,
            &format!("pyramid.comp:{suffix}"),
            &[
                (BINDING_PYRAMID_FINE, vk::DescriptorType::STORAGE_IMAGE),
                (BINDING_PYRAMID_COARSE, vk::DescriptorType::STORAGE_IMAGE),
            ],
            std::mem::size_of::<PyramidParams>() as u32,
            "pyramid",
        )?;
        Ok(PyramidPass {
            ctx: ctx.clone(),
            pass,
        })
    }

    /// Makes the views and descriptor sets to build `hf`'s pyramid.
    pub fn prepare(&self, hf: &GpuHeightfield) -> VkResult<PyramidJob> {
        self.prepare_image(&hf.image)
    }

    /// [`PyramidPass::prepare`] for any storage image with a full mip chain in this pass's format.
    pub fn prepare_image(&self, image: &Image) -> VkResult<PyramidJob> {
        let levels = image.desc().mip_levels;
        let views = (0..levels)
            .map(|l| image.level_view(l))
            .collect::<VkResult<Vec<_>>>()?;
        let dispatches = levels.saturating_sub(1).max(1);
        let pool = DescriptorPool::new(&self.ctx, dispatches, 2 * dispatches, "pyramid sets")?;
        let sets = views
            .windows(2)
            .map(|pair| {
                pool.allocate(
                    self.pass.layout(),
                    &[
                        Bind::StorageImage(BINDING_PYRAMID_FINE, &pair[0]),
                        Bind::StorageImage(BINDING_PYRAMID_COARSE, &pair[1]),
                    ],
                )
            })
            .collect::<VkResult<Vec<_>>>()?;
        Ok(PyramidJob {
            _views: views,
            _pool: pool,
            sets,
        })
    }

    /// Records the build. The image must be in `GENERAL` with level 0 written; it ends in
    /// `SHADER_READ_ONLY_OPTIMAL`, ready for the surface pass.
    pub fn record(&self, rec: &Recording, hf: &GpuHeightfield, job: &PyramidJob) -> VkResult<()> {
        self.record_image(rec, &hf.image, hf.address, job)
    }

    /// [`PyramidPass::record`] for the image `job` was prepared for, addressed as `address`.
    pub fn record_image(
        &self,
        rec: &Recording,
        image: &Image,
        address: Address,
        job: &PyramidJob,
    ) -> VkResult<()> {
        let whole: Vec<Vec<Region>> = (1..image.desc().mip_levels)
            .map(|l| {
                let (w, h) = image.level_extent(l);
                vec![[0, 0, w, h]]
            })
            .collect();
        self.record_regions(rec, image, address, job, &whole)
    }

    /// Rebuilds only `regions[k]` of level `k + 1` (each `[x0, y0, width, height]`), from the
    /// image's level 0 in `GENERAL` up; the image ends in `SHADER_READ_ONLY_OPTIMAL`. What a
    /// brush stroke touched, from `terrain::coarse_span`.
    pub fn record_regions(
        &self,
        rec: &Recording,
        image: &Image,
        address: Address,
        job: &PyramidJob,
        regions: &[Vec<Region>],
    ) -> VkResult<()> {
        let write = (
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        let read = (
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_READ,
        );
        for (k, (set, level)) in job.sets.iter().zip(regions).enumerate() {
            let pipeline = self.pass.pipeline();
            pipeline.bind(rec, Some(set));
            let widen = u32::from(k == 0);
            let wrap = u32::from(address == Address::Repeat);
            for region in level {
                let push = PyramidParams {
                    flags: [widen, wrap, 0, 0],
                    region: *region,
                };
                pipeline.push(rec, bytemuck::bytes_of(&push))?;
                rec.dispatch([region[2].div_ceil(GROUP), region[3].div_ceil(GROUP), 1]);
            }
            memory_barrier(rec, write, read);
        }
        transition_images(
            rec,
            &[ImageTransition {
                image,
                aspect: vk::ImageAspectFlags::COLOR,
                base_mip: 0,
                mip_count: image.desc().mip_levels,
                old: vk::ImageLayout::GENERAL,
                new: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                src: (
                    vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::TRANSFER_WRITE,
                ),
                dst: (
                    vk::PipelineStageFlags2::FRAGMENT_SHADER
                        | vk::PipelineStageFlags2::COMPUTE_SHADER
                        | vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::SHADER_SAMPLED_READ | vk::AccessFlags2::TRANSFER_READ,
                ),
            }],
        );
        Ok(())
    }
}

/// Uploads `hf`, builds its pyramid on the GPU and reads every level back (level 0 first),
/// with the build's GPU time in ms. Used by `relief maps` and the CPU-equals-GPU tests.
pub fn build_pyramid_on_gpu(
    ctx: &Arc<Context>,
    hf: &crate::heightfield::Heightfield,
    format: crate::render::HeightFormat,
    address: Address,
) -> VkResult<(Vec<Vec<f32>>, f64)> {
    let gpu = GpuHeightfield::upload(ctx, hf, format, address)?;
    let pass = PyramidPass::new(ctx, format.shader_suffix())?;
    let job = pass.prepare(&gpu)?;
    let timestamps = crate::vk::TimestampPool::new(ctx, 2, "pyramid timestamps")?;
    let all = vk::PipelineStageFlags2::ALL_COMMANDS;
    ctx.one_shot(|rec| {
        timestamps.write(rec, all, 0)?;
        pass.record(rec, &gpu, &job)?;
        timestamps.write(rec, all, 1)?;
        Ok(())
    })?;
    let ticks = timestamps.read_ticks(2)?;
    let levels = (0..gpu.levels())
        .map(|l| {
            crate::vk::read_mip(
                ctx,
                &gpu.image,
                l,
                vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            )
            .map(|bytes| format.decode(&bytes))
        })
        .collect::<VkResult<Vec<_>>>()?;
    Ok((levels, timestamps.ticks_to_ms(ticks[0], ticks[1])))
}
