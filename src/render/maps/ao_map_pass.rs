//! The texture-space AO map built on the GPU: one value per height texel, the ambient occlusion at
//! its centre on the bilinear surface, cosine-weighted about the texel normal (docs/conventions.md,
//! "Normal and AO"; `heightfield::ambient_occlusion` is the exact CPU reference).
//!
//! Two builders, chosen by [`AoMode`]:
//! - `horizon-N[-rotated]`: Drobot's fast horizon queries on the max pyramid
//!   (`shaders/passes/ao_horizon.comp`), one dispatch; needs the height image's pyramid built.
//! - `exact-horizon`: line sweeps with convex hulls (`shaders/passes/ao_sweep.comp`), one dispatch
//!   per azimuth ([`SWEEP_DIRECTIONS`] of them, see `ao_sweep`) plus a resolve; reads level 0 only.
//!
//! Use from the renderer (the height field's `GpuHeightfield`, pyramid built, is `gpu`):
//!
//! ```no_run
//! # use relief::render::{AoMapPass, GpuHeightfield};
//! # fn f(ctx: &std::sync::Arc<relief::vk::Context>, gpu: &GpuHeightfield) -> relief::vk::VkResult<()> {
//! let pass = AoMapPass::new(ctx, "horizon-8".parse().expect("an AO mode"))?; // once per mode
//! let job = pass.prepare(gpu, 0.1)?; // the map, its set and scratch, for this field and depth
//! ctx.one_shot(|rec| pass.record(rec, &job))?; // or inside any other recording
//! let map = job.into_map(); // once that submission has completed
//! // Bind map.image.view() with map.sampler as a combined image sampler; read .r at the uv.
//! # Ok(()) }
//! ```
//!
//! The map's image ends in `SHADER_READ_ONLY_OPTIMAL`, visible to fragment and compute shaders.
//!
//! Local rebuilds (horizon modes): a map prepared with a bounded reach
//! ([`AoMapPass::prepare_reaching`]) depends on the heights within
//! [`AoJob::influence_texels`] of each texel only, so after the heights change in a rectangle,
//! [`AoMapPass::record_region`] over [`AoJob::influence_region`] of it gives the map a full
//! rebuild would, bit for bit, recomputing only the texels that can see the change.
//!
//! Invariants: a flat field gives exactly 1.0 in every mode; every value is in [0, 1].
//!
//! Accuracy and cost (mean absolute error against the reference at 256 azimuths; lavapipe on two
//! busy cores, 128x128, depth 0.1): `horizon-8` 0.007-0.008 in tens of ms; `exact-horizon`
//! 0.0002-0.0006 in 2-6 s, linear in texels x azimuths, in one submission. The sweep's scratch is
//! `HULL_CAPACITY + 2` x 16 bytes per line (about `(W + H) x 12` lines for the steepest azimuth under
//! clamp) plus 8 bytes per texel.

use std::sync::Arc;

use ash::vk;

use super::ao_influence::{
    clip_region, influence_radius, influence_region, HORIZON_FIRST_DISTANCE, HORIZON_GROWTH,
    HORIZON_LEVEL_BIAS,
};
use super::ao_sweep::{
    crossings, sweep_directions, sweep_lines, Crossing, SweepDirection, CHUNK_STEPS, HULL_CAPACITY,
    MAX_CROSSINGS, STATE_SLOTS,
};
use super::pyramid_pass::PyramidPass;
use crate::heightfield::{Address, Heightfield};
use crate::render::compute_pass::ComputePass;
use crate::render::kit::gpu_heightfield::{sampler_address_mode, GpuHeightfield, HeightFormat};
use crate::render::shader_interface::{
    AoHorizonParams, AoSweepParams, BINDING_AO_ACCUM, BINDING_AO_CROSSINGS, BINDING_AO_FIELD,
    BINDING_AO_HEIGHTS, BINDING_AO_HULLS, BINDING_AO_MAP, MODE_RESOLVE, MODE_SWEEP, MODE_UNPACK,
};
use crate::scene::AoMode;
use crate::vk::{
    memory_barrier, read_mip, transition_images, Bind, Buffer, Context, DescriptorPool,
    DescriptorSet, Image, ImageDesc, ImageTransition, MemoryLocation, Recording, Sampler,
    TimestampPool, VkError, VkResult,
};

/// Azimuths the exact-horizon sweep targets (fewer when a map's lattice offers fewer steps).
pub const SWEEP_DIRECTIONS: u32 = 64;

/// The format of the AO map's image.
pub const AO_MAP_FORMAT: vk::Format = vk::Format::R32_SFLOAT;

const HORIZON_GROUP: u32 = 8;
const SWEEP_GROUP: u32 = 64;

/// A built AO map: `R32_SFLOAT`, one texel per height texel, in `SHADER_READ_ONLY_OPTIMAL`, with a
/// sampler that filters linearly where the device can (else nearest) under the height field's
/// addressing. Bind it as a combined image sampler and read it at the surface's uv.
pub struct AoMap {
    /// Ambient visibility per height texel: 1 unoccluded, 0 fully occluded.
    pub image: Image,
    /// Linear where the format allows it, else nearest; addressed as the height field.
    pub sampler: Sampler,
    /// How it was computed.
    pub mode: AoMode,
    /// The height field's addressing, which the horizons and the sampler follow.
    pub address: Address,
}

/// One build's resources: the map being written, its descriptor set and the sweep's scratch.
/// Keep it alive until the submission that recorded it has completed.
pub struct AoJob {
    map: AoMap,
    _pool: DescriptorPool,
    set: DescriptorSet,
    // The sweep's scratch (none for the horizon pass).
    scratch: Option<SweepScratch>,
    depth_scale: f32,
    /// How far the horizons look, in uv (the whole map unless a reach was asked for).
    reach_uv: f32,
    /// The reach asked for, in texels of the longer side; `None`: the whole map.
    reach_texels: Option<f32>,
    /// Mip levels of the height image the job reads (the pyramid's, or 1 without one).
    height_levels: u32,
}

impl AoJob {
    /// The map (valid to sample once the recording has executed).
    pub fn map(&self) -> &AoMap {
        &self.map
    }

    /// The map alone, dropping the scratch; call after the submission has completed.
    pub fn into_map(self) -> AoMap {
        self.map
    }

    /// The bounded reach the job was prepared with (texels of the longer side), if any.
    pub fn reach_texels(&self) -> Option<f32> {
        self.reach_texels
    }

    /// A radius R in level-0 texels (per axis) such that a texel's AO depends on the heights
    /// within R of it only; `None` when the reach is unbounded (`ao_influence` derives it).
    pub fn influence_texels(&self) -> Option<u32> {
        self.reach_texels?;
        let d = self.map.image.desc();
        Some(influence_radius(
            self.reach_uv,
            (d.width, d.height),
            self.height_levels,
        ))
    }

    /// The texels of the map whose AO a change of the heights in `changed` (x0, y0, width,
    /// height, level-0 texels) can alter (`ao_influence::influence_region`); `None` when the
    /// reach is unbounded (every texel may see the change: rebuild the whole map), an empty
    /// rectangle when `changed` covers no texel of the map.
    pub fn influence_region(&self, changed: [u32; 4]) -> Option<[u32; 4]> {
        let radius = self.influence_texels()?;
        let d = self.map.image.desc();
        let wrap = self.map.address == Address::Repeat;
        Some(influence_region(changed, (d.width, d.height), radius, wrap))
    }
}

/// The pipeline of one AO mode and its set layout.
pub struct AoMapPass {
    ctx: Arc<Context>,
    mode: AoMode,
    pass: ComputePass,
}

impl AoMapPass {
    /// Creates the pipeline for `mode` only. Errors for `AoMode::None`, which builds no map.
    pub fn new(ctx: &Arc<Context>, mode: AoMode) -> VkResult<AoMapPass> {
        let (key, push) = match mode {
            AoMode::None => {
                return Err(VkError::Invalid("AO mode none builds no AO map".into()));
            }
            AoMode::Horizon { .. } => ("ao_horizon.comp", std::mem::size_of::<AoHorizonParams>()),
            AoMode::ExactHorizon => ("ao_sweep.comp", std::mem::size_of::<AoSweepParams>()),
        };
        let name = format!("ao map {mode}");
        let pass = ComputePass::plain(ctx, key, &layout_bindings(mode), push as u32, &name)?;
        Ok(AoMapPass {
            ctx: ctx.clone(),
            mode,
            pass,
        })
    }

    /// The mode this pass builds.
    pub fn mode(&self) -> AoMode {
        self.mode
    }

    /// Allocates the AO map of `hf` (same size, same addressing), its set and scratch.
    /// `depth_scale` must be finite and above 0.
    pub fn prepare(&self, hf: &GpuHeightfield, depth_scale: f32) -> VkResult<AoJob> {
        self.prepare_reaching(hf, depth_scale, None)
    }

    /// [`AoMapPass::prepare`] with the horizons looking at most `reach_texels` texels of the
    /// longer side away (finite, at least 1; the whole map when larger or `None`). A bounded reach
    /// loses the occlusion of farther, higher terrain but makes each texel depend on the heights
    /// near it only, so a local change can be rebuilt locally ([`AoMapPass::record_region`]).
    /// Horizon modes only: the exact sweep follows every line across the whole map.
    pub fn prepare_reaching(
        &self,
        hf: &GpuHeightfield,
        depth_scale: f32,
        reach_texels: Option<f32>,
    ) -> VkResult<AoJob> {
        if !(depth_scale.is_finite() && depth_scale > 0.0) {
            return Err(VkError::Invalid(format!(
                "AO map depth scale {depth_scale}: must be finite and above 0"
            )));
        }
        if let Some(reach) = reach_texels {
            if !(reach.is_finite() && reach >= 1.0) {
                return Err(VkError::Invalid(format!(
                    "AO reach {reach} texels: must be finite and at least 1"
                )));
            }
            if self.mode == AoMode::ExactHorizon {
                return Err(VkError::Invalid(
                    "AO mode exact-horizon has no bounded reach: its sweeps cross the whole map \
                     (use a horizon-N mode)"
                        .into(),
                ));
            }
        }
        let ctx = &self.ctx;
        let map = new_map(ctx, hf, self.mode)?;
        let pool = DescriptorPool::new(ctx, 1, 4, &format!("ao map {} sets", self.mode))?;
        let mut binds = vec![
            Bind::Texture(BINDING_AO_HEIGHTS, hf.image.view(), &hf.point),
            Bind::StorageImage(BINDING_AO_MAP, map.image.view()),
        ];
        let scratch = if self.mode == AoMode::ExactHorizon {
            Some(sweep_scratch(ctx, hf)?)
        } else {
            None
        };
        if let Some(scratch) = &scratch {
            binds.push(Bind::Storage(BINDING_AO_HULLS, &scratch.hulls));
            binds.push(Bind::Storage(BINDING_AO_ACCUM, &scratch.accum));
            binds.push(Bind::Storage(BINDING_AO_FIELD, &scratch.field));
            binds.push(Bind::Storage(BINDING_AO_CROSSINGS, &scratch.crossings));
        }
        let set = pool.allocate(self.pass.layout(), &binds)?;
        let d = hf.image.desc();
        let reach_uv = match reach_texels {
            Some(reach) => whole_reach_uv(hf.address).min(reach / d.width.max(d.height) as f32),
            None => whole_reach_uv(hf.address),
        };
        Ok(AoJob {
            map,
            _pool: pool,
            set,
            scratch,
            depth_scale,
            reach_uv,
            reach_texels,
            height_levels: hf.levels(),
        })
    }

    /// Records the build of `job`'s map from the height field it was prepared for, which must
    /// outlive the submission. The height image must be in `SHADER_READ_ONLY_OPTIMAL` (for horizon
    /// modes with its pyramid built; without one they read level 0 only, less accurately) and its
    /// writes visible to compute shaders; the map ends in `SHADER_READ_ONLY_OPTIMAL`.
    pub fn record(&self, rec: &Recording, job: &AoJob) -> VkResult<()> {
        self.check_job(job)?;
        let image = &job.map.image;
        transition_map(rec, image, MapStep::Write);
        self.pass.pipeline().bind(rec, Some(&job.set));
        match (self.mode, &job.scratch) {
            (
                AoMode::Horizon {
                    directions,
                    rotated,
                },
                _,
            ) => {
                let d = image.desc();
                self.record_horizon(rec, job, (directions, rotated), [0, 0, d.width, d.height])?
            }
            (AoMode::ExactHorizon, Some(scratch)) => self.record_sweep(rec, job, scratch)?,
            _ => return Err(VkError::Invalid("AO job prepared for another mode".into())),
        }
        transition_map(rec, image, MapStep::Read);
        Ok(())
    }

    /// Records the rebuild of `region` (x0, y0, width, height; clipped to the map, nothing
    /// recorded when empty) of `job`'s map, already built by a recording that executes before
    /// this one, keeping its other texels. As [`AoMapPass::record`], the heights must be in
    /// `SHADER_READ_ONLY_OPTIMAL` with their writes (and their pyramid's) visible to compute
    /// shaders. Horizon modes only; pass [`AoJob::influence_region`] of a changed rectangle to
    /// get what a full rebuild would give.
    pub fn record_region(&self, rec: &Recording, job: &AoJob, region: [u32; 4]) -> VkResult<()> {
        self.check_job(job)?;
        let AoMode::Horizon {
            directions,
            rotated,
        } = self.mode
        else {
            return Err(VkError::Invalid(format!(
                "AO mode {} rebuilds whole maps only (its sweeps cross the map): record the \
                 whole map instead of a region",
                self.mode
            )));
        };
        let d = job.map.image.desc();
        let Some(region) = clip_region(region, d.width, d.height) else {
            return Ok(());
        };
        let image = &job.map.image;
        transition_map(rec, image, MapStep::Rewrite);
        self.pass.pipeline().bind(rec, Some(&job.set));
        self.record_horizon(rec, job, (directions, rotated), region)?;
        transition_map(rec, image, MapStep::Read);
        Ok(())
    }

    fn check_job(&self, job: &AoJob) -> VkResult<()> {
        if job.map.mode != self.mode {
            return Err(VkError::Invalid(format!(
                "AO job prepared for {} recorded by the {} pass",
                job.map.mode, self.mode
            )));
        }
        Ok(())
    }

    /// One dispatch over `region` (x0, y0, width, height; non-empty, within the map).
    fn record_horizon(
        &self,
        rec: &Recording,
        job: &AoJob,
        (directions, rotated): (u32, bool),
        region: [u32; 4],
    ) -> VkResult<()> {
        let d = job.map.image.desc();
        let params = AoHorizonParams {
            size: [d.width as i32, d.height as i32],
            repeat_address: u32::from(job.map.address == Address::Repeat),
            directions,
            rotated: u32::from(rotated),
            depth_scale: job.depth_scale,
            first_distance: HORIZON_FIRST_DISTANCE,
            growth: HORIZON_GROWTH,
            reach_uv: job.reach_uv,
            level_bias: HORIZON_LEVEL_BIAS,
            origin: [region[0] as i32, region[1] as i32],
            end: [
                (region[0] + region[2]) as i32,
                (region[1] + region[3]) as i32,
            ],
        };
        self.pass
            .pipeline()
            .push(rec, bytemuck::bytes_of(&params))?;
        rec.dispatch([
            region[2].div_ceil(HORIZON_GROUP),
            region[3].div_ceil(HORIZON_GROUP),
            1,
        ]);
        Ok(())
    }

    fn record_sweep(&self, rec: &Recording, job: &AoJob, scratch: &SweepScratch) -> VkResult<()> {
        let depth_scale = job.depth_scale;
        let accum = &scratch.accum;
        let (w, h) = (job.map.image.desc().width, job.map.image.desc().height);
        let rw = vk::AccessFlags2::SHADER_STORAGE_READ | vk::AccessFlags2::SHADER_STORAGE_WRITE;
        let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
        let repeat = job.map.address == Address::Repeat;
        // Per-texel passes: a group per 64 texels of a row, a row of groups per map row.
        let texel_groups = [w.div_ceil(SWEEP_GROUP), h, 1];
        let sweep = self.pass.pipeline();
        let mut whole_map = sweep_params(&scratch.directions[0], w, h, repeat, depth_scale);
        whole_map.mode = MODE_UNPACK;
        sweep.push(rec, bytemuck::bytes_of(&whole_map))?;
        rec.dispatch(texel_groups);
        rec.fill_buffer(accum, 0, accum.size(), 0)?;
        memory_barrier(
            rec,
            (
                vk::PipelineStageFlags2::CLEAR,
                vk::AccessFlags2::TRANSFER_WRITE,
            ),
            (compute, rw),
        );
        memory_barrier(rec, (compute, rw), (compute, rw));
        for (k, dir) in scratch.directions.iter().enumerate() {
            let mut params = sweep_params(dir, w, h, repeat, depth_scale);
            params.crossing_base = (k * MAX_CROSSINGS) as u32;
            // Each dispatch walks CHUNK_STEPS steps of every line and saves where it stopped.
            let chunks = sweep_lines(params.walk, w, h, repeat).chunks();
            for chunk in 0..chunks {
                params.chunk = chunk;
                sweep.push(rec, bytemuck::bytes_of(&params))?;
                rec.dispatch([params.lines.div_ceil(SWEEP_GROUP), 1, 1]);
                // The next chunk resumes from the hull stacks, the next direction reuses them,
                // and both add to the same sums.
                memory_barrier(rec, (compute, rw), (compute, rw));
            }
        }
        whole_map.mode = MODE_RESOLVE;
        sweep.push(rec, bytemuck::bytes_of(&whole_map))?;
        rec.dispatch(texel_groups);
        Ok(())
    }

    /// Uploads `hf` (as `R32_SFLOAT`, so the GPU sees the same heights as the CPU reference),
    /// builds its pyramid where the mode reads one, builds the AO map and reads it back,
    /// row-major; with the AO build's GPU time in ms (timestamps around it alone).
    pub fn build(
        &self,
        hf: &Heightfield,
        depth_scale: f64,
        address: Address,
    ) -> VkResult<(Vec<f32>, f64)> {
        let ctx = &self.ctx;
        let format = HeightFormat::R32Float;
        let gpu = if self.mode == AoMode::ExactHorizon {
            GpuHeightfield::upload_without_pyramid(ctx, hf, format, address)?
        } else {
            let gpu = GpuHeightfield::upload(ctx, hf, format, address)?;
            let pyramid = PyramidPass::new(ctx, format.shader_suffix())?;
            let job = pyramid.prepare(&gpu)?;
            ctx.one_shot(|rec| pyramid.record(rec, &gpu, &job))?;
            gpu
        };
        let job = self.prepare(&gpu, depth_scale as f32)?;
        let timestamps = TimestampPool::new(ctx, 2, "ao map timestamps")?;
        let all = vk::PipelineStageFlags2::ALL_COMMANDS;
        ctx.one_shot(|rec| {
            timestamps.write(rec, all, 0)?;
            self.record(rec, &job)?;
            timestamps.write(rec, all, 1)?;
            Ok(())
        })?;
        let ticks = timestamps.read_ticks(2)?;
        let map = job.into_map();
        let layout = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
        let bytes = read_mip(ctx, &map.image, 0, layout)?;
        let values = bytemuck::pod_collect_to_vec(&bytes);
        Ok((values, timestamps.ticks_to_ms(ticks[0], ticks[1])))
    }
}

/// The horizon's reach covering the whole profile that can matter: a repeating profile comes back
/// a tile on, seen lower; a clamped one ends at the far corner, beyond which the extension only
/// recedes.
fn whole_reach_uv(address: Address) -> f32 {
    if address == Address::Repeat {
        1.0
    } else {
        std::f32::consts::SQRT_2
    }
}

/// The set layout of `mode`'s shader: heights and the map (ao.glsl), plus the sweep's buffers
/// (hulls, sums, unpacked heights, crossings).
fn layout_bindings(mode: AoMode) -> Vec<(u32, vk::DescriptorType)> {
    let mut bindings = vec![
        (
            BINDING_AO_HEIGHTS,
            vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
        ),
        (BINDING_AO_MAP, vk::DescriptorType::STORAGE_IMAGE),
    ];
    if mode == AoMode::ExactHorizon {
        let scratch = [
            BINDING_AO_HULLS,
            BINDING_AO_ACCUM,
            BINDING_AO_FIELD,
            BINDING_AO_CROSSINGS,
        ];
        bindings.extend(scratch.map(|b| (b, vk::DescriptorType::STORAGE_BUFFER)));
    }
    bindings
}

/// The push constants of one swept azimuth (the walk goes against the horizon's direction).
fn sweep_params(
    dir: &SweepDirection,
    w: u32,
    h: u32,
    repeat: bool,
    depth_scale: f32,
) -> AoSweepParams {
    let walk = [-dir.step[0], -dir.step[1]];
    let lines = sweep_lines(walk, w, h, repeat);
    let crossing_count = crossings(walk).len() as u32;
    let step_u = f64::from(dir.step[0]) / f64::from(w);
    let step_v = f64::from(dir.step[1]) / f64::from(h);
    AoSweepParams {
        size: [w as i32, h as i32],
        walk,
        euclid: lines.euclid,
        c_min: lines.c_min,
        lines: lines.lines,
        repeat_address: u32::from(repeat),
        period: lines.period,
        g_a: lines.g_a,
        mode: MODE_SWEEP,
        depth_scale,
        step_uv: step_u.hypot(step_v) as f32,
        dir: [dir.angle.cos() as f32, dir.angle.sin() as f32],
        weight: dir.weight as f32,
        crossing_base: 0,
        crossing_count,
        segments: lines.segments,
        segment_steps: lines.segment_steps,
        warm_steps: lines.warm_steps,
        chunk: 0,
        chunk_steps: CHUNK_STEPS,
    }
}

/// The sweep's azimuths and buffers: hull stacks for the most lines any azimuth has, one sum per
/// texel, level 0 of the heights unpacked, and each azimuth's crossings ([`MAX_CROSSINGS`] slots).
struct SweepScratch {
    directions: Vec<SweepDirection>,
    hulls: Buffer,
    accum: Buffer,
    field: Buffer,
    crossings: Buffer,
}

fn sweep_scratch(ctx: &Arc<Context>, hf: &GpuHeightfield) -> VkResult<SweepScratch> {
    let (w, h) = (hf.image.desc().width, hf.image.desc().height);
    let repeat = hf.address == Address::Repeat;
    let directions = sweep_directions(SWEEP_DIRECTIONS, w, h);
    let most_lines = directions
        .iter()
        .map(|d| sweep_lines([-d.step[0], -d.step[1]], w, h, repeat).lines)
        .max()
        .unwrap_or(1);
    let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_DST;
    let hulls = Buffer::new(
        ctx,
        u64::from(most_lines) * (HULL_CAPACITY + STATE_SLOTS) * 16,
        usage,
        MemoryLocation::GpuOnly,
        "ao sweep hulls",
    )?;
    let per_texel = |name| {
        Buffer::new(
            ctx,
            u64::from(w) * u64::from(h) * 4,
            usage,
            MemoryLocation::GpuOnly,
            name,
        )
    };
    let mut table = vec![Crossing::default(); directions.len() * MAX_CROSSINGS];
    for (slots, dir) in table.chunks_mut(MAX_CROSSINGS).zip(&directions) {
        let list = crossings([-dir.step[0], -dir.step[1]]);
        slots[..list.len()].copy_from_slice(&list);
    }
    let crossings = Buffer::with_data(
        ctx,
        bytemuck::cast_slice(&table),
        vk::BufferUsageFlags::STORAGE_BUFFER,
        "ao sweep crossings",
    )?;
    Ok(SweepScratch {
        directions,
        crossings,
        hulls,
        accum: per_texel("ao sweep sums")?,
        field: per_texel("ao sweep heights")?,
    })
}

/// The map's image and sampler, checking the device can store and sample the format.
fn new_map(ctx: &Arc<Context>, hf: &GpuHeightfield, mode: AoMode) -> VkResult<AoMap> {
    let features = ctx.format_features(AO_MAP_FORMAT);
    let needed = vk::FormatFeatureFlags::STORAGE_IMAGE
        | vk::FormatFeatureFlags::SAMPLED_IMAGE
        | vk::FormatFeatureFlags::TRANSFER_SRC;
    if !features.contains(needed) {
        return Err(VkError::Unsupported(
            "R32_SFLOAT AO maps (storage and sampling)".into(),
        ));
    }
    let d = hf.image.desc();
    let desc = ImageDesc {
        width: d.width,
        height: d.height,
        format: AO_MAP_FORMAT,
        mip_levels: 1,
        usage: vk::ImageUsageFlags::STORAGE
            | vk::ImageUsageFlags::SAMPLED
            | vk::ImageUsageFlags::TRANSFER_SRC,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    let image = Image::new(ctx, desc, &format!("ao map {mode}"))?;
    let filter = if features.contains(vk::FormatFeatureFlags::SAMPLED_IMAGE_FILTER_LINEAR) {
        vk::Filter::LINEAR
    } else {
        vk::Filter::NEAREST
    };
    let sampler = Sampler::new(
        ctx,
        filter,
        sampler_address_mode(hf.address),
        "ao map sampler",
    )?;
    Ok(AoMap {
        image,
        sampler,
        mode,
        address: hf.address,
    })
}

/// Where a recording moves the map.
#[derive(Clone, Copy)]
enum MapStep {
    /// To `GENERAL` for a full build: the old contents are discarded.
    Write,
    /// From `SHADER_READ_ONLY_OPTIMAL` to `GENERAL` for a partial rebuild: the texels outside the
    /// region must survive, and earlier samplers and copies must finish before the writes.
    Rewrite,
    /// From `GENERAL` to `SHADER_READ_ONLY_OPTIMAL` for the shaders and copies that read it.
    Read,
}

/// Moves the map for `step`, ordering the accesses before it against those after.
fn transition_map(rec: &Recording, image: &Image, step: MapStep) {
    let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
    let write = vk::AccessFlags2::SHADER_STORAGE_WRITE;
    let readers = (
        vk::PipelineStageFlags2::FRAGMENT_SHADER | compute | vk::PipelineStageFlags2::COPY,
        vk::AccessFlags2::SHADER_SAMPLED_READ | vk::AccessFlags2::TRANSFER_READ,
    );
    let (old, new, src, dst) = match step {
        MapStep::Write => (
            vk::ImageLayout::UNDEFINED,
            vk::ImageLayout::GENERAL,
            (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
            (compute, write),
        ),
        MapStep::Rewrite => (
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            vk::ImageLayout::GENERAL,
            readers,
            (compute, write),
        ),
        MapStep::Read => (
            vk::ImageLayout::GENERAL,
            vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            (compute, write),
            readers,
        ),
    };
    transition_images(rec, &[ImageTransition::color(image, (old, new), src, dst)]);
}
