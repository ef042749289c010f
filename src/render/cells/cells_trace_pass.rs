//! Rays through a cell complex on the GPU (`shaders/passes/cells_trace.comp`): the CPU march of
//! `cells::trace` over the arrays of `cells::PackedComplex`, one invocation per ray, timed with
//! timestamps. What the renderer's cell pass will run per fragment, and the GPU rays per second
//! Apaza and Andujar's Table 2 reports.

use std::sync::Arc;

use ash::vk;

use super::complex_buffers::ComplexBuffers;
use crate::cells::{MarchSettings, PackedComplex};
use crate::render::maps::map_search::{warm_up, SearchPipeline, TimedSubmissions, SHADER_WROTE};
use crate::render::shader_interface::{CellsTraceParams, BINDING_CELLS_HITS, BINDING_CELLS_RAYS};
use crate::vk::{Bind, Buffer, Context, MemoryLocation, Readback, VkResult};

/// Invocations per workgroup (`local_size_x`).
const GROUP: u32 = 64;

/// One ray: origin and unit direction, as the shader reads it.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct GpuRay {
    origin: [f32; 4],
    dir: [f32; 4],
}

/// Where each ray hit (`None`: it missed) with its samples, and the GPU ms of the march.
pub struct CellsTrace {
    /// One per ray, in order: the hit's `t` along the ray (`origin + t * dir`, so in the
    /// mesh's units for a unit `dir`) and the map samples the march took; `None` on a miss.
    pub hits: Vec<Option<(f64, u32)>>,
    /// GPU time of the march, ms.
    pub gpu_ms: f64,
}

/// Marches `rays` (origin, direction) through `complex` on the GPU.
pub fn march_cells_on_gpu(
    ctx: &Arc<Context>,
    complex: &PackedComplex,
    rays: &[([f64; 3], [f64; 3])],
    settings: MarchSettings,
) -> VkResult<CellsTrace> {
    let push = std::mem::size_of::<CellsTraceParams>() as u32;
    let search = SearchPipeline::new(ctx, "cells_trace.comp", push, 5, "cells trace")?;
    let arrays = ComplexBuffers::upload(ctx, complex, "cells trace")?;
    let storage = vk::BufferUsageFlags::STORAGE_BUFFER;
    let gpu_rays: Vec<GpuRay> = rays
        .iter()
        .map(|(o, d)| GpuRay {
            origin: [o[0] as f32, o[1] as f32, o[2] as f32, 0.0],
            dir: [d[0] as f32, d[1] as f32, d[2] as f32, 0.0],
        })
        .collect();
    let ray_buffer = Buffer::with_data(
        ctx,
        &ComplexBuffers::nonempty(bytemuck::cast_slice(&gpu_rays)),
        storage,
        "cell rays",
    )?;
    let hit_bytes = (rays.len().max(1) * 8) as u64;
    let hits = Buffer::new(
        ctx,
        hit_bytes,
        storage | vk::BufferUsageFlags::TRANSFER_SRC,
        MemoryLocation::GpuOnly,
        "cell hits",
    )?;
    let mut binds = arrays.binds().to_vec();
    binds.push(Bind::Storage(BINDING_CELLS_RAYS, &ray_buffer));
    binds.push(Bind::Storage(BINDING_CELLS_HITS, &hits));
    // SAFETY: every submission that bound the set was a one-shot (warm-ups and timed
    // submissions), and one-shots return only once their work has finished.
    unsafe { search.set.rewrite(&binds) }?;
    let params = CellsTraceParams {
        origin_size: [
            complex.origin[0],
            complex.origin[1],
            complex.origin[2],
            complex.cell_size,
        ],
        n: complex.n,
        resolution: complex.resolution,
        ray_count: rays.len() as u32,
        refinements: settings.refinements,
        samples_per_texel: settings.samples_per_texel as f32,
    };
    let idle = CellsTraceParams {
        ray_count: 0,
        ..params
    };
    warm_up(
        ctx,
        search.pass.pipeline(),
        &search.set,
        bytemuck::bytes_of(&idle),
    )?;
    let mut timed = TimedSubmissions::new(ctx, 1, "cells trace")?;
    timed.submit(ctx, |rec| {
        let groups = [(rays.len() as u32).div_ceil(GROUP).max(1), 1, 1];
        search
            .pass
            .dispatch(rec, &search.set, bytemuck::bytes_of(&params), groups)
    })?;
    let back = Readback::new(ctx, hit_bytes, "cell hits readback")?;
    ctx.one_shot(|rec| back.record_copy_from_buffer(rec, &hits, SHADER_WROTE))?;
    let gpu_ms = timed.total_ms()?;
    let values: Vec<f32> = bytemuck::pod_collect_to_vec(back.bytes()?);
    let hits = values
        .chunks_exact(2)
        .take(rays.len())
        .map(|h| (h[0] >= 0.0).then_some((f64::from(h[0]), h[1] as u32)))
        .collect();
    Ok(CellsTrace { hits, gpu_ms })
}
