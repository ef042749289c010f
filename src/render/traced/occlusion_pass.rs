//! Occlusion rays through a [`TracedScene`]: one compute dispatch of `traced_occlusion.comp` per
//! batch, each ray a ray query that ends at the first thing it meets, timed with timestamps and
//! read back.

use std::sync::Arc;

use ash::vk;
use glam::Vec3;

use super::traced_scene::TracedScene;
use crate::method::Method;
use crate::render::compute_pass::ComputePass;
use crate::render::kit::render_error::RenderError;
use crate::render::shader_interface::{
    OcclusionParams, BINDING_OCCLUSION_PRISMS, BINDING_OCCLUSION_RAYS, BINDING_OCCLUSION_RESULTS,
    BINDING_OCCLUSION_SCENE, SPEC_BUDGET_EXTENT_LIMIT, SPEC_BUDGET_LEAF_EXACT,
    SPEC_BUDGET_MAX_STEPS, SPEC_BUDGET_REFINE_STEPS,
};
use crate::vk::{
    memory_barrier, Bind, Buffer, Context, DescriptorPool, MemoryLocation, Readback, SpecConstants,
    TimestampPool, VkError,
};

/// `local_size_x` of traced_occlusion.comp.
const GROUP: u32 = 64;

/// One segment to test: `origin + t dir` for `t` in `[t_min, t_max]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OcclusionRay {
    /// Where the ray starts.
    pub origin: Vec3,
    /// Where the segment begins along it.
    pub t_min: f32,
    /// Its direction (any length; `t` is in its units).
    pub dir: Vec3,
    /// Where the segment ends.
    pub t_max: f32,
}

/// What a batch found.
#[derive(Debug, Clone, Default)]
pub struct Occlusion {
    /// Per ray, in order: whether something lies on the segment.
    pub blocked: Vec<bool>,
    /// Relief prisms whose boxes the rays entered and the shader tested.
    pub prisms_tested: u64,
    /// Height-field walk iterations over all those tests.
    pub walk_steps: u64,
    /// Rays one of whose walks ran out of budget (its verdict is then the walk's best guess).
    pub capped: usize,
    /// GPU ms of the dispatches over all the rays (the median of the timed repeats).
    pub gpu_ms: f64,
}

/// The most rays one dispatch takes: the workgroup count every device allows in x (65535).
const MAX_BATCH: usize = 65_535 * GROUP as usize;

/// Tests every ray of `rays` against `scene`, in dispatches of at most 65,535 workgroups of 64 rays.
pub fn trace_occlusion(
    ctx: &Arc<Context>,
    scene: &TracedScene,
    rays: &[OcclusionRay],
) -> Result<Occlusion, RenderError> {
    time_occlusion(ctx, scene, rays, 1)
}

/// [`trace_occlusion`] with each batch dispatched `repeats` times (at least 1) in one submission,
/// each timed; the time is the median repeat's, for the bench.
pub fn time_occlusion(
    ctx: &Arc<Context>,
    scene: &TracedScene,
    rays: &[OcclusionRay],
    repeats: u32,
) -> Result<Occlusion, RenderError> {
    // A ray query's segment must be finite, non-negative and ordered, or the shader's result is
    // undefined; no layer checks it inside the shader.
    if let Some((k, r)) = rays.iter().enumerate().find(|(_, r)| {
        let finite = r.origin.is_finite() && r.dir.is_finite() && r.t_max.is_finite();
        !(finite && r.t_min >= 0.0 && r.t_min <= r.t_max && r.dir != Vec3::ZERO)
    }) {
        return Err(VkError::Invalid(format!(
            "occlusion ray {k}: origin {}, direction {}, t from {} to {}: a segment needs finite values, a direction and 0 <= t_min <= t_max",
            r.origin, r.dir, r.t_min, r.t_max
        ))
        .into());
    }
    let heights = scene.heights();
    let mut bindings = heights.layout_bindings();
    bindings.extend([
        (
            BINDING_OCCLUSION_SCENE,
            vk::DescriptorType::ACCELERATION_STRUCTURE_KHR,
        ),
        (BINDING_OCCLUSION_PRISMS, vk::DescriptorType::STORAGE_BUFFER),
        (BINDING_OCCLUSION_RAYS, vk::DescriptorType::STORAGE_BUFFER),
        (
            BINDING_OCCLUSION_RESULTS,
            vk::DescriptorType::STORAGE_BUFFER,
        ),
    ]);
    let budget = Method::MAXMIP.info().default_budget;
    let spec = SpecConstants::default()
        .u32(SPEC_BUDGET_MAX_STEPS, budget.max_steps)
        .u32(SPEC_BUDGET_REFINE_STEPS, budget.refine_steps)
        .u32(SPEC_BUDGET_LEAF_EXACT, budget.leaf.spec_value())
        .u32(SPEC_BUDGET_EXTENT_LIMIT, budget.extent_limit);
    let push = std::mem::size_of::<OcclusionParams>() as u32;
    let pass = ComputePass::new(
        ctx,
        "traced_occlusion.comp",
        &bindings,
        push,
        &spec,
        "traced occlusion",
    )?;
    let mut all = Occlusion::default();
    for batch in rays.chunks(MAX_BATCH) {
        let part = trace_batch(ctx, scene, &pass, batch, repeats.max(1))?;
        all.blocked.extend(part.blocked);
        all.prisms_tested += part.prisms_tested;
        all.walk_steps += part.walk_steps;
        all.capped += part.capped;
        all.gpu_ms += part.gpu_ms;
    }
    Ok(all)
}

/// `repeats` dispatches over `rays` (at most `MAX_BATCH`), each timed.
fn trace_batch(
    ctx: &Arc<Context>,
    scene: &TracedScene,
    pass: &ComputePass,
    rays: &[OcclusionRay],
    repeats: u32,
) -> Result<Occlusion, RenderError> {
    let count = rays.len() as u32;
    let packed: Vec<[f32; 8]> = rays
        .iter()
        .map(|r| {
            [
                r.origin.x, r.origin.y, r.origin.z, r.t_min, r.dir.x, r.dir.y, r.dir.z, r.t_max,
            ]
        })
        .collect();
    let ray_buffer = Buffer::with_data(
        ctx,
        bytemuck::cast_slice(&packed),
        vk::BufferUsageFlags::STORAGE_BUFFER,
        "occlusion rays",
    )?;
    let bytes = u64::from(count) * 16;
    let results = Buffer::new(
        ctx,
        bytes,
        vk::BufferUsageFlags::STORAGE_BUFFER | vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::GpuOnly,
        "occlusion results",
    )?;
    let results_back = Readback::new(ctx, bytes, "occlusion results readback")?;
    let pool = DescriptorPool::new(ctx, 1, 4, "traced occlusion sets")?;
    let mut binds = scene.heights().binds();
    binds.extend([
        Bind::Structure(BINDING_OCCLUSION_SCENE, scene.top()),
        Bind::Storage(BINDING_OCCLUSION_PRISMS, scene.records()),
        Bind::Storage(BINDING_OCCLUSION_RAYS, &ray_buffer),
        Bind::Storage(BINDING_OCCLUSION_RESULTS, &results),
    ]);
    let set = pool.allocate(pass.layout(), &binds)?;
    let params = OcclusionParams {
        count: [count, 0, 0, 0],
    };
    let timestamps = TimestampPool::new(ctx, 2 * repeats, "traced occlusion timestamps")?;
    let compute = vk::PipelineStageFlags2::COMPUTE_SHADER;
    let written = (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE);
    ctx.one_shot(|rec| {
        for k in 0..repeats {
            if k > 0 {
                // The repeats write the same results: order them as the first.
                memory_barrier(rec, written, written);
            }
            timestamps.write(rec, compute, 2 * k)?;
            pass.dispatch(
                rec,
                &set,
                bytemuck::bytes_of(&params),
                [count.div_ceil(GROUP), 1, 1],
            )?;
            timestamps.write(rec, compute, 2 * k + 1)?;
        }
        results_back.record_copy_from_buffer(
            rec,
            &results,
            (compute, vk::AccessFlags2::SHADER_STORAGE_WRITE),
        )
    })?;
    let ticks = timestamps.read_ticks(2 * repeats)?;
    let mut times: Vec<f64> = ticks
        .chunks_exact(2)
        .map(|t| timestamps.ticks_to_ms(t[0], t[1]))
        .collect();
    times.sort_by(f64::total_cmp);
    let words: Vec<[u32; 4]> = bytemuck::pod_collect_to_vec(results_back.bytes()?);
    Ok(Occlusion {
        blocked: words.iter().map(|w| w[0] != 0).collect(),
        prisms_tested: words.iter().map(|w| u64::from(w[1])).sum(),
        walk_steps: words.iter().map(|w| u64::from(w[2])).sum(),
        capped: words.iter().filter(|w| w[3] != 0).count(),
        gpu_ms: times[times.len() / 2],
    })
}
