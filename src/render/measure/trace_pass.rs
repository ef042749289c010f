//! The trace pass: parallel rays over a grid, traced on the GPU by one method's compute variant,
//! with the hits and per-ray iteration counts read back. Feeds `relief trace` and `relief bench`.

use std::sync::Arc;

use ash::vk;

use super::trace_sweeps::{SweepTimers, TimedSweeps};
use crate::heightfield::{Address, Heightfield, MapData, MaxPyramid};
use crate::method::{Budget, Method};
use crate::render::compute_pass::ComputePass;
use crate::render::heights::height_resources::HeightResources;
use crate::render::kit::gpu_heightfield::HeightFormat;
use crate::render::kit::hard_shadow::hard_shadow_texels;
use crate::render::kit::shadow_mode_value::shadow_mode_value;
use crate::render::shader_interface::{
    TraceParams, BINDING_TRACE_FETCHES, BINDING_TRACE_HITS, BINDING_TRACE_STEPS,
    BINDING_TRACE_VISIBLE, SPEC_BUDGET_EXTENT_LIMIT, SPEC_BUDGET_LEAF_EXACT, SPEC_BUDGET_MAX_STEPS,
    SPEC_BUDGET_REFINE_STEPS, SPEC_COUNT_FETCHES, SPEC_HARD_SHADOW_TEXELS, SPEC_SHADOW_MODE,
    SPEC_SHADOW_REACH, SPEC_SHADOW_STEPS,
};
use crate::scene::ShadowMode;
use crate::vk::{
    Bind, Buffer, Context, DescriptorPool, DescriptorSet, MemoryLocation, Readback, Recording,
    SpecConstants, VkError, VkResult,
};

/// Side of the trace pass's square workgroups (`local_size_x` and `_y` in trace.comp).
pub const TRACE_GROUP_SIDE: u32 = 8;

/// One sweep of parallel rays.
#[derive(Debug, Clone, Copy)]
pub struct TraceRequest<'a> {
    /// The method whose compute variant traces the rays.
    pub method: Method,
    /// Ray direction, dz > 0 (docs/conventions.md).
    pub dir: [f32; 3],
    /// Depth of height 0 below the top plane, in uv units (one unit is the map's width).
    pub depth_scale: f32,
    /// Columns and rows of the ray grid; ray (c, r) enters at ((c+0.5)/cols, (r+0.5)/rows).
    pub grid: (u32, u32),
    /// Iteration caps and leaf settings, as specialization constants.
    pub budget: Budget,
    /// What lies outside the height map: repeated or clamped.
    pub address: Address,
    /// How the heights are stored on the GPU.
    pub format: HeightFormat,
    /// The method's precomputed map, when it reads one (`Method::info().needs`).
    pub map: Option<&'a MapData>,
    /// A light to shadow each hit toward, if any.
    pub shadow: Option<ShadowTrace>,
}

/// The light `relief trace --shadows` shades each hit with.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadowTrace {
    /// How the visible fraction is computed.
    pub mode: ShadowMode,
    /// `SHADOW_STEPS`: samples or the pyramid walk's cap (`ShadowMode::default_steps`).
    pub steps: u32,
    /// Unit direction toward the light's centre in (u, v, up): the conventions' light direction with
    /// the depth axis flipped.
    pub toward: [f32; 3],
    /// Angular radius, radians.
    pub radius: f32,
    /// Horizon mode's light vector scale (`ShadowSettings::horizon_reach`).
    pub horizon_reach: f32,
}

impl ShadowTrace {
    /// A directional light at `elevation_deg` and `azimuth_deg` (docs/conventions.md) of angular
    /// radius `radius_deg`, shadowed by `mode` with its default steps.
    pub fn directional(
        mode: ShadowMode,
        elevation_deg: f64,
        azimuth_deg: f64,
        radius_deg: f64,
    ) -> Self {
        let (e, a) = (elevation_deg.to_radians(), azimuth_deg.to_radians());
        ShadowTrace {
            mode,
            steps: mode.default_steps(),
            toward: [
                (e.cos() * a.cos()) as f32,
                (e.cos() * a.sin()) as f32,
                e.sin() as f32,
            ],
            radius: radius_deg.to_radians() as f32,
            horizon_reach: 1.0,
        }
    }
}

/// What the GPU traced: per ray `u0 v0 dx dy dz u_hit v_hit z_hit`, `(steps, capped)` and the
/// light's visible fraction at the hit (all 1 without a `shadow`).
#[derive(Debug, Clone)]
pub struct TraceOutput {
    /// One per ray, row by row (ray (c, r) at `r * cols + c`): entry point `u0 v0`, direction
    /// `dx dy dz`, and the hit `u v` and its depth `z` below the top plane, in uv units.
    pub hits: Vec<[f32; 8]>,
    /// One per ray, same order: iterations taken, and 1 if the method's cap stopped it (else 0).
    pub steps: Vec<[u32; 2]>,
    /// One per ray, same order: the light's visible fraction at the hit, 0 to 1.
    pub visible: Vec<f32>,
    /// One per ray, same order, from [`trace_counting_fetches`] only (else empty): the texel
    /// fetches of the method's trace, and of the shadow walk after it.
    pub fetches: Vec<[u32; 2]>,
    /// GPU time of each timed dispatch, in order.
    pub frame_ms: Vec<f64>,
    /// Compute shader invocations of each timed frame, as the device counts them (pipeline
    /// statistics); empty where it cannot.
    pub compute_invocations: Vec<u64>,
}

/// Where the timed dispatches write (device-local, so the timing has no bus writes in it) and the
/// host-visible buffers their results are copied to after the closing timestamp.
struct TraceTargets {
    hits: Buffer,
    steps: Buffer,
    visible: Buffer,
    fetches: Buffer,
    hits_back: Readback,
    steps_back: Readback,
    visible_back: Readback,
    fetches_back: Readback,
}

impl TraceTargets {
    /// Targets for `rays` rays; the fetch counts' are a one-entry stand-in unless `counting`.
    fn new(ctx: &Arc<Context>, rays: u64, counting: bool) -> VkResult<TraceTargets> {
        let usage = vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC;
        let gpu = MemoryLocation::GpuOnly;
        let counted = if counting { rays } else { 1 };
        Ok(TraceTargets {
            fetches: Buffer::new(ctx, counted * 8, usage, gpu, "trace fetches")?,
            fetches_back: Readback::new(ctx, counted * 8, "trace fetches readback")?,
            hits: Buffer::new(ctx, rays * 32, usage, gpu, "trace hits")?,
            steps: Buffer::new(ctx, rays * 8, usage, gpu, "trace steps")?,
            visible: Buffer::new(ctx, rays * 4, usage, gpu, "trace visibility")?,
            hits_back: Readback::new(ctx, rays * 32, "trace hits readback")?,
            steps_back: Readback::new(ctx, rays * 8, "trace steps readback")?,
            visible_back: Readback::new(ctx, rays * 4, "trace visibility readback")?,
        })
    }

    /// Copies the last dispatch's results to the host-visible buffers (with the host barrier).
    fn record_readback(&self, rec: &Recording) -> VkResult<()> {
        let written = (
            vk::PipelineStageFlags2::COMPUTE_SHADER,
            vk::AccessFlags2::SHADER_STORAGE_WRITE,
        );
        self.hits_back
            .record_copy_from_buffer(rec, &self.hits, written)?;
        self.steps_back
            .record_copy_from_buffer(rec, &self.steps, written)?;
        self.visible_back
            .record_copy_from_buffer(rec, &self.visible, written)?;
        self.fetches_back
            .record_copy_from_buffer(rec, &self.fetches, written)
    }
}

/// Traces `req` over `hf` on the GPU once.
pub fn trace_on_gpu(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    req: &TraceRequest,
) -> VkResult<TraceOutput> {
    trace_repeated(ctx, hf, req, 0, 1)
}

/// [`trace_on_gpu`] with every texel fetch counted ([`TraceOutput::fetches`]). Counting costs
/// time, so the timed passes never count.
pub fn trace_counting_fetches(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    req: &TraceRequest,
) -> VkResult<TraceOutput> {
    trace_with(ctx, Heights::Field(hf), req, 0, 1, 1, true)
}

/// Traces `req` `warmup + frames` times in one submission, a full barrier between dispatches,
/// timing the last `frames`; the output holds the last dispatch's hits, copied to the host after
/// the closing timestamp.
pub fn trace_repeated(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    req: &TraceRequest,
    warmup: u32,
    frames: u32,
) -> VkResult<TraceOutput> {
    trace_with(ctx, Heights::Field(hf), req, warmup, frames, 1, false)
}

/// [`trace_repeated`] with `dispatches` dispatches per frame (at least 1), each frame's timed
/// together: the bench's timed pass.
pub(crate) fn trace_timed(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    req: &TraceRequest,
    warmup: u32,
    frames: u32,
    dispatches: u32,
) -> VkResult<TraceOutput> {
    trace_with(
        ctx,
        Heights::Field(hf),
        req,
        warmup,
        frames,
        dispatches.max(1),
        false,
    )
}

/// Traces `req` once through `pyramid` (level 0 the heights) as it is, instead of the pyramid the
/// GPU builds from the heights: a blended terrain's conservative bound, so that its cost in
/// iterations can be set beside the exact pyramid's.
pub fn trace_through_pyramid(
    ctx: &Arc<Context>,
    pyramid: &MaxPyramid,
    req: &TraceRequest,
) -> VkResult<TraceOutput> {
    time_through_pyramid(ctx, pyramid, req, 0, 1)
}

/// [`trace_through_pyramid`] timed as [`trace_repeated`] times a field: `warmup + frames`
/// dispatches in one submission, the last `frames` timed, so the bench can set a blended
/// terrain's GPU time beside the exact pyramid's measured the same way.
pub fn time_through_pyramid(
    ctx: &Arc<Context>,
    pyramid: &MaxPyramid,
    req: &TraceRequest,
    warmup: u32,
    frames: u32,
) -> VkResult<TraceOutput> {
    trace_with(
        ctx,
        Heights::Pyramid(pyramid),
        req,
        warmup,
        frames,
        1,
        false,
    )
}

/// What a trace reads: a height field (its pyramid built on the GPU) or a pyramid built elsewhere.
#[derive(Clone, Copy)]
enum Heights<'a> {
    Field(&'a Heightfield),
    Pyramid(&'a MaxPyramid),
}

impl Heights<'_> {
    /// The height map, its pyramid and `req.map` on the device.
    fn upload(self, ctx: &Arc<Context>, req: &TraceRequest) -> VkResult<HeightResources> {
        Ok(match self {
            Heights::Field(hf) => HeightResources::new(
                ctx,
                hf,
                req.format,
                req.address,
                req.map,
                bytemuck::Zeroable::zeroed(),
            )?,
            Heights::Pyramid(pyramid) => HeightResources::with_pyramid(
                ctx,
                pyramid,
                req.format,
                req.address,
                req.map,
                bytemuck::Zeroable::zeroed(),
            )?,
        })
    }
}

/// The trace shader's specialisation for `req`'s budget and shadow and whether it counts
/// fetches, and the light it traces toward (straight up, unused, without a shadow).
fn trace_constants(req: &TraceRequest, count_fetches: bool) -> (SpecConstants, [f32; 4]) {
    let spec = SpecConstants::default()
        .u32(SPEC_COUNT_FETCHES, u32::from(count_fetches))
        .u32(SPEC_BUDGET_MAX_STEPS, req.budget.max_steps)
        .u32(SPEC_BUDGET_REFINE_STEPS, req.budget.refine_steps)
        .u32(SPEC_BUDGET_LEAF_EXACT, req.budget.leaf.spec_value())
        .u32(SPEC_BUDGET_EXTENT_LIMIT, req.budget.extent_limit);
    match req.shadow {
        None => (spec, [0.0, 0.0, 1.0, 0.0]),
        Some(s) => (
            spec.u32(SPEC_SHADOW_MODE, shadow_mode_value(s.mode))
                .u32(SPEC_SHADOW_STEPS, s.steps)
                .f32(SPEC_SHADOW_REACH, s.horizon_reach)
                .f32(SPEC_HARD_SHADOW_TEXELS, hard_shadow_texels(req.method)),
            [s.toward[0], s.toward[1], s.toward[2], s.radius],
        ),
    }
}

/// Traces `req`'s rays through `heights`: `warmup + frames` sweeps of `dispatches` dispatches
/// each in one submission, the last `frames` timed, with the fetches counted when
/// `count_fetches`.
fn trace_with(
    ctx: &Arc<Context>,
    heights: Heights,
    req: &TraceRequest,
    warmup: u32,
    frames: u32,
    dispatches: u32,
    count_fetches: bool,
) -> VkResult<TraceOutput> {
    if frames == 0 {
        return Err(VkError::Invalid("a trace of zero frames".into()));
    }
    let (cols, rows) = req.grid;
    if cols == 0 || rows == 0 {
        return Err(VkError::Invalid(format!("ray grid {cols}x{rows}")));
    }
    let count = cols as u64 * rows as u64;
    let res = heights.upload(ctx, req)?;
    let targets = TraceTargets::new(ctx, count, count_fetches)?;
    let (spec, light) = trace_constants(req, count_fetches);
    let params = TraceParams {
        dir: [req.dir[0], req.dir[1], req.dir[2], req.depth_scale],
        grid: [cols, rows, 0, 0],
        light,
    };
    let pass = trace_kernel(ctx, req, &res, &spec)?;
    let pool = DescriptorPool::new(ctx, 1, 4, "trace sets")?;
    let set = trace_set(&pool, &pass, &res, &targets)?;
    let timers = SweepTimers::new(ctx, frames)?;
    let sweep = TimedSweeps {
        pass: &pass,
        set: &set,
        params,
        timers: &timers,
        counts: (warmup, frames, dispatches),
    };
    ctx.one_shot(|rec| {
        res.record_pyramid(rec)?;
        sweep.record(rec)?;
        targets.record_readback(rec)
    })?;
    let frame_ms = timers.frame_ms(frames)?;
    let compute_invocations = timers.compute_invocations(frames)?;
    Ok(TraceOutput {
        hits: bytemuck::pod_collect_to_vec(targets.hits_back.bytes()?),
        steps: bytemuck::pod_collect_to_vec(targets.steps_back.bytes()?),
        visible: bytemuck::pod_collect_to_vec(targets.visible_back.bytes()?),
        fetches: if count_fetches {
            bytemuck::pod_collect_to_vec(targets.fetches_back.bytes()?)
        } else {
            Vec::new()
        },
        frame_ms,
        compute_invocations,
    })
}

/// The trace kernel of `req`'s method, specialised by `spec`, over `res`'s bindings and the
/// trace's four storage buffers.
fn trace_kernel(
    ctx: &Arc<Context>,
    req: &TraceRequest,
    res: &HeightResources,
    spec: &SpecConstants,
) -> VkResult<ComputePass> {
    let key = req.method.shader_key("trace.comp");
    let mut bindings = res.layout_bindings();
    bindings.extend(
        [
            BINDING_TRACE_HITS,
            BINDING_TRACE_STEPS,
            BINDING_TRACE_VISIBLE,
            BINDING_TRACE_FETCHES,
        ]
        .map(|b| (b, vk::DescriptorType::STORAGE_BUFFER)),
    );
    let push = std::mem::size_of::<TraceParams>() as u32;
    ComputePass::new(ctx, &key, &bindings, push, spec, &key)
}

/// The kernel's set: `res`'s heights and `targets`' buffers.
fn trace_set(
    pool: &DescriptorPool,
    pass: &ComputePass,
    res: &HeightResources,
    targets: &TraceTargets,
) -> VkResult<DescriptorSet> {
    let mut binds = res.binds();
    binds.extend([
        Bind::Storage(BINDING_TRACE_HITS, &targets.hits),
        Bind::Storage(BINDING_TRACE_STEPS, &targets.steps),
        Bind::Storage(BINDING_TRACE_VISIBLE, &targets.visible),
        Bind::Storage(BINDING_TRACE_FETCHES, &targets.fetches),
    ]);
    pool.allocate(pass.layout(), &binds)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vk::ContextOptions;

    fn device() -> Option<Arc<Context>> {
        match Context::new(&ContextOptions::default()) {
            Ok(ctx) => Some(ctx),
            Err(e @ (VkError::NoDevice | VkError::Loader(_))) if std::env::var("CI").is_err() => {
                eprintln!("SKIPPED: no Vulkan device: {e}");
                None
            }
            Err(e) => panic!("cannot create a Vulkan device: {e}"),
        }
    }

    #[test]
    fn timed_dispatches_write_device_local_memory() {
        let Some(ctx) = device() else {
            return;
        };
        let targets = TraceTargets::new(&ctx, 64, true).expect("trace targets");
        for written in [
            &targets.hits,
            &targets.steps,
            &targets.visible,
            &targets.fetches,
        ] {
            assert_eq!(
                written.location(),
                MemoryLocation::GpuOnly,
                "{}",
                written.name()
            );
        }
        for back in [
            &targets.hits_back,
            &targets.steps_back,
            &targets.visible_back,
            &targets.fetches_back,
        ] {
            assert_eq!(back.buffer().location(), MemoryLocation::GpuToCpu);
        }
    }
}
