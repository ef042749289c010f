//! Live edits of a terrain's elevation on the GPU: brush strokes (`brush.comp`) written into the
//! height image's level 0, then only the pyramid nodes that read a changed texel rebuilt
//! (`PyramidPass::record_regions` over `terrain::coarse_span`), level by level. A full rebuild
//! is kept beside it to compare with, texel for texel and in GPU time.

use std::sync::Arc;

use ash::vk;

use crate::heightfield::{Address, Heightfield};
use crate::render::compute_pass::ComputePass;
use crate::render::kit::gpu_heightfield::{GpuHeightfield, HeightFormat};
use crate::render::maps::pyramid_pass::{regions_above, PyramidJob, PyramidPass, Region};
use crate::render::shader_interface::{
    BrushParams, BINDING_BRUSH_HEIGHTS, BRUSH_CRATER, BRUSH_FLATTEN, BRUSH_LOWER, BRUSH_RAISE,
};
use crate::terrain::{BrushKind, Stroke, StrokeError, StrokeTarget, TexelRect};
use crate::vk::{
    memory_barrier, read_mip, transition_images, Bind, Context, DescriptorPool, DescriptorSet,
    ImageTransition, ImageView, TimestampPool, VkError, VkResult,
};

const GROUP: u32 = 8;

/// Why strokes could not be applied.
#[derive(Debug, thiserror::Error)]
pub enum EditError {
    /// A stroke is invalid (a non-finite value, a bad radius, missing the map, or a `paint`
    /// stroke, which edits layer weights, not elevation); none of the batch was applied.
    #[error(transparent)]
    Stroke(#[from] StrokeError),
    /// Recording or submitting the brush and pyramid rebuild failed.
    #[error(transparent)]
    Vulkan(#[from] VkError),
}

/// What one batch of strokes rebuilt.
#[derive(Debug, Clone, PartialEq)]
pub struct EditReport {
    /// Per level (0: the elevation itself), the texels written.
    pub texels_per_level: Vec<u64>,
    /// GPU time of the strokes and the partial rebuild.
    pub gpu_ms: f64,
}

/// An elevation on the GPU with its max pyramid, edited by strokes.
pub struct ElevationEditor {
    ctx: Arc<Context>,
    heights: GpuHeightfield,
    pyramid: PyramidPass,
    job: PyramidJob,
    brush: ComputePass,
    _pool: DescriptorPool,
    _level0: ImageView,
    set: DescriptorSet,
    timestamps: TimestampPool,
}

impl ElevationEditor {
    /// Uploads `elevation` and builds its pyramid.
    pub fn new(
        ctx: &Arc<Context>,
        elevation: &Heightfield,
        format: HeightFormat,
        address: Address,
    ) -> VkResult<ElevationEditor> {
        let heights = GpuHeightfield::upload(ctx, elevation, format, address)?;
        let pyramid = PyramidPass::new(ctx, format.shader_suffix())?;
        let job = pyramid.prepare(&heights)?;
        let brush = ComputePass::plain(
            ctx,
            &format!("brush.comp:{}", format.shader_suffix()),
            &[(BINDING_BRUSH_HEIGHTS, vk::DescriptorType::STORAGE_IMAGE)],
            std::mem::size_of::<BrushParams>() as u32,
            "brush",
        )?;
        let level0 = heights.image.level_view(0)?;
        let pool = DescriptorPool::new(ctx, 1, 1, "brush set")?;
        let set = pool.allocate(
            brush.layout(),
            &[Bind::StorageImage(BINDING_BRUSH_HEIGHTS, &level0)],
        )?;
        let editor = ElevationEditor {
            ctx: ctx.clone(),
            heights,
            pyramid,
            job,
            brush,
            _pool: pool,
            _level0: level0,
            set,
            timestamps: TimestampPool::new(ctx, 2, "edit timestamps")?,
        };
        editor
            .ctx
            .one_shot(|rec| editor.pyramid.record(rec, &editor.heights, &editor.job))?;
        Ok(editor)
    }

    /// The elevation and its pyramid (in `SHADER_READ_ONLY_OPTIMAL` between calls).
    pub fn heights(&self) -> &GpuHeightfield {
        &self.heights
    }

    /// Applies `strokes` in order and rebuilds the pyramid nodes they touched. Every stroke is
    /// checked first; a bad one applies none.
    pub fn apply(&mut self, strokes: &[Stroke]) -> Result<EditReport, EditError> {
        let (w, h) = (
            self.heights.image.desc().width,
            self.heights.image.desc().height,
        );
        for (k, s) in strokes.iter().enumerate() {
            s.check(k, w, h)?;
            if s.paints() {
                return Err(StrokeError::from(StrokeTarget::PaintOnElevation { index: k }).into());
            }
        }
        let rects: Vec<TexelRect> = strokes.iter().filter_map(|s| s.rect(w, h)).collect();
        let regions = self.dirty_regions(&rects);
        let mut texels_per_level = vec![rects.iter().map(TexelRect::texels).sum()];
        texels_per_level.extend(regions.iter().map(|level| {
            level
                .iter()
                .map(|r| u64::from(r[2]) * u64::from(r[3]))
                .sum::<u64>()
        }));
        self.record(|rec, editor| {
            for (stroke, rect) in strokes.iter().zip(&rects) {
                let push = brush_push(stroke, rect);
                let groups = [
                    rect.width().div_ceil(GROUP),
                    rect.height().div_ceil(GROUP),
                    1,
                ];
                editor
                    .brush
                    .dispatch(rec, &editor.set, bytemuck::bytes_of(&push), groups)?;
                // Strokes may overlap: each reads what the one before wrote.
                let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
                memory_barrier(
                    rec,
                    (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE),
                    (
                        compute,
                        vk::AccessFlags2::SHADER_STORAGE_READ
                            | vk::AccessFlags2::SHADER_STORAGE_WRITE,
                    ),
                );
            }
            editor.pyramid.record_regions(
                rec,
                &editor.heights.image,
                editor.heights.address,
                &editor.job,
                &regions,
            )
        })
        .map(|gpu_ms| EditReport {
            texels_per_level,
            gpu_ms,
        })
        .map_err(EditError::from)
    }

    /// Rebuilds every level above the elevation; its GPU time in ms.
    pub fn rebuild_all(&mut self) -> VkResult<f64> {
        self.record(|rec, editor| {
            editor.pyramid.record_image(
                rec,
                &editor.heights.image,
                editor.heights.address,
                &editor.job,
            )
        })
    }

    /// Every level, the elevation first.
    pub fn read_levels(&self) -> VkResult<Vec<Vec<f32>>> {
        (0..self.heights.levels())
            .map(|l| {
                read_mip(
                    &self.ctx,
                    &self.heights.image,
                    l,
                    vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                )
                .map(|bytes| self.heights.format.decode(&bytes))
            })
            .collect()
    }

    /// Per level above the elevation, the regions that read a texel of `rects`.
    fn dirty_regions(&self, rects: &[TexelRect]) -> Vec<Vec<Region>> {
        let wrap = self.heights.address == Address::Repeat;
        regions_above(&self.heights.image, rects, wrap)
    }

    /// Records `work` between timestamps, with the image in `GENERAL` during it; the GPU ms.
    fn record(
        &mut self,
        work: impl FnOnce(&crate::vk::Recording, &ElevationEditor) -> VkResult<()>,
    ) -> VkResult<f64> {
        let all = vk::PipelineStageFlags2::ALL_COMMANDS;
        let levels = self.heights.levels();
        let editor = &*self;
        // The last call's timestamps were read; the queries must be reset before they are reused.
        // SAFETY: the pool is written only by this function's one-shots, which have returned, so
        // their work has finished.
        unsafe { editor.timestamps.reset() };
        editor.ctx.one_shot(|rec| {
            editor.timestamps.write(rec, all, 0)?;
            transition_images(
                rec,
                &[ImageTransition {
                    image: &editor.heights.image,
                    aspect: vk::ImageAspectFlags::COLOR,
                    base_mip: 0,
                    mip_count: levels,
                    old: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
                    new: vk::ImageLayout::GENERAL,
                    src: (
                        vk::PipelineStageFlags2::FRAGMENT_SHADER
                            | vk::PipelineStageFlags2::COMPUTE_SHADER
                            | vk::PipelineStageFlags2::COPY,
                        vk::AccessFlags2::SHADER_SAMPLED_READ | vk::AccessFlags2::TRANSFER_READ,
                    ),
                    dst: (
                        vk::PipelineStageFlags2::COMPUTE_SHADER,
                        vk::AccessFlags2::SHADER_STORAGE_READ
                            | vk::AccessFlags2::SHADER_STORAGE_WRITE,
                    ),
                }],
            );
            work(rec, editor)?;
            editor.timestamps.write(rec, all, 1)
        })?;
        let ticks = self.timestamps.read_ticks(2)?;
        Ok(self.timestamps.ticks_to_ms(ticks[0], ticks[1]))
    }
}

/// `brush.comp`'s push constants for `stroke` over `rect`.
fn brush_push(stroke: &Stroke, rect: &TexelRect) -> BrushParams {
    let kind = match stroke.kind {
        BrushKind::Raise => BRUSH_RAISE,
        BrushKind::Lower => BRUSH_LOWER,
        BrushKind::Flatten => BRUSH_FLATTEN,
        BrushKind::Crater => BRUSH_CRATER,
        // Refused by `apply` before anything is recorded.
        BrushKind::Paint => BRUSH_CRATER + 1,
    };
    BrushParams {
        stroke: [stroke.x, stroke.y, stroke.radius, stroke.strength],
        shape: [stroke.target, kind as f32, 0.0, 0.0],
        region: [rect.x0, rect.y0, rect.width(), rect.height()],
    }
}
