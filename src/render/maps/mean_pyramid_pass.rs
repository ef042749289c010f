//! The averaged (mean) height pyramid of Ki and Oh section 2.5, for LOD surface variants: an image
//! of its own with the heights in level 0 and, per coarser level, the mean of the finer texels each
//! texel covers (`shaders/passes/mean_pyramid.comp`, one dispatch per level with a barrier
//! between). Built on the GPU in the first frame, beside the max pyramid, only when a material's
//! LOD reads it (the plan says so); its views and sets live as long as the image.

use std::sync::Arc;

use ash::vk;

use crate::heightfield::{mip_level_count, Heightfield};
use crate::render::compute_pass::ComputePass;
use crate::render::kit::gpu_heightfield::HeightFormat;
use crate::render::shader_interface::{BINDING_PYRAMID_COARSE, BINDING_PYRAMID_FINE};
use crate::vk::{
    memory_barrier, transition_images, upload_mips, Bind, Context, DescriptorPool, DescriptorSet,
    Image, ImageDesc, ImageTransition, ImageView, Recording, VkResult,
};

const GROUP: u32 = 8;

/// The averaged pyramid's image and everything its build records.
pub struct MeanPyramid {
    image: Image,
    pass: ComputePass,
    sets: Vec<DescriptorSet>,
    _views: Vec<ImageView>,
    _pool: DescriptorPool,
}

impl MeanPyramid {
    /// Uploads `hf` as level 0 of a full mip chain stored as `format` and prepares the build.
    pub fn new(ctx: &Arc<Context>, hf: &Heightfield, format: HeightFormat) -> VkResult<Self> {
        let desc = ImageDesc {
            width: hf.width(),
            height: hf.height(),
            format: format.vk(),
            mip_levels: mip_level_count(hf.width(), hf.height()),
            usage: vk::ImageUsageFlags::STORAGE
                | vk::ImageUsageFlags::SAMPLED
                | vk::ImageUsageFlags::TRANSFER_DST
                | vk::ImageUsageFlags::TRANSFER_SRC,
            aspect: vk::ImageAspectFlags::COLOR,
        };
        let image = Image::new(ctx, desc, "averaged height pyramid")?;
        upload_mips(
            ctx,
            &image,
            &[&format.encode(hf.data())],
            vk::ImageLayout::GENERAL,
        )?;
        let pass = ComputePass::plain(
            ctx,
            &format!("mean_pyramid.comp:{}", format.shader_suffix()),
            &[
                (BINDING_PYRAMID_FINE, vk::DescriptorType::STORAGE_IMAGE),
                (BINDING_PYRAMID_COARSE, vk::DescriptorType::STORAGE_IMAGE),
            ],
            0,
            "averaged pyramid",
        )?;
        let views = (0..desc.mip_levels)
            .map(|l| image.level_view(l))
            .collect::<VkResult<Vec<_>>>()?;
        let dispatches = desc.mip_levels.saturating_sub(1).max(1);
        let pool = DescriptorPool::new(ctx, dispatches, 2 * dispatches, "averaged pyramid sets")?;
        let sets = views
            .windows(2)
            .map(|pair| {
                let binds = [
                    Bind::StorageImage(BINDING_PYRAMID_FINE, &pair[0]),
                    Bind::StorageImage(BINDING_PYRAMID_COARSE, &pair[1]),
                ];
                pool.allocate(pass.layout(), &binds)
            })
            .collect::<VkResult<Vec<_>>>()?;
        Ok(MeanPyramid {
            image,
            pass,
            sets,
            _views: views,
            _pool: pool,
        })
    }

    /// The view of every level, for sampling once built.
    pub fn view(&self) -> &ImageView {
        self.image.view()
    }

    /// Records the build; the image ends in `SHADER_READ_ONLY_OPTIMAL`. Record it once.
    pub fn record(&self, rec: &Recording) -> VkResult<()> {
        let write = (
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        let read = (
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_READ,
        );
        for (k, set) in self.sets.iter().enumerate() {
            let (w, h) = self.image.level_extent(k as u32 + 1);
            self.pass
                .dispatch(rec, set, &[], [w.div_ceil(GROUP), h.div_ceil(GROUP), 1])?;
            memory_barrier(rec, write, read);
        }
        transition_images(
            rec,
            &[ImageTransition {
                image: &self.image,
                aspect: vk::ImageAspectFlags::COLOR,
                base_mip: 0,
                mip_count: self.image.desc().mip_levels,
                old: vk::ImageLayout::GENERAL,
                new: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                src: (
                    vk::PipelineStageFlags2::COMPUTE_SHADER | vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::SHADER_STORAGE_WRITE | vk::AccessFlags2::TRANSFER_WRITE,
                ),
                dst: (
                    vk::PipelineStageFlags2::FRAGMENT_SHADER | vk::PipelineStageFlags2::COPY,
                    vk::AccessFlags2::SHADER_SAMPLED_READ | vk::AccessFlags2::TRANSFER_READ,
                ),
            }],
        );
        Ok(())
    }
}

/// Uploads `hf`, builds its averaged pyramid on the GPU and reads every level back (level 0
/// first). For the CPU-equals-GPU test.
pub fn build_mean_pyramid_on_gpu(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    format: HeightFormat,
) -> VkResult<Vec<Vec<f32>>> {
    let mean = MeanPyramid::new(ctx, hf, format)?;
    ctx.one_shot(|rec| mean.record(rec))?;
    (0..mean.image.desc().mip_levels)
        .map(|l| {
            let layout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
            crate::vk::read_mip(ctx, &mean.image, l, layout).map(|b| format.decode(&b))
        })
        .collect()
}
