//! The timed pass of `relief bench`: a full-screen quad whose every pixel traces one parallel ray
//! with one method (`bench.frag`), drawn `warmup + frames` times in one submission, each timed
//! frame between two timestamps with a full barrier between frames.

use std::sync::Arc;

use ash::vk;

use super::gpu_heightfield::{Addressing, HeightFormat};
use super::height_resources::HeightResources;
use super::method_map::MapData;
use crate::heightfield::Heightfield;
use crate::method::{Budget, Method};
use crate::shaders;
use crate::vk::{
    graphics_pipeline, memory_barrier, transition_images, Context, DescriptorLayout,
    DescriptorPool, GraphicsDesc, Image, ImageDesc, ImageTransition, SpecConstants, TimestampPool,
    VkError, VkResult,
};

/// Output format: z, steps, capped per pixel, in full float so nothing is rounded away.
const HIT_FORMAT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;

/// One timed configuration.
#[derive(Debug, Clone, Copy)]
pub struct BenchRequest<'a> {
    pub method: Method,
    pub dir: [f32; 3],
    pub depth_scale: f32,
    pub resolution: (u32, u32),
    pub budget: Budget,
    pub address: Addressing,
    pub format: HeightFormat,
    pub map: Option<&'a MapData>,
    pub warmup: u32,
    pub frames: u32,
}

/// GPU milliseconds of each timed frame, in order.
#[derive(Debug, Clone)]
pub struct BenchTiming {
    pub frame_ms: Vec<f64>,
}

#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct BenchParams {
    dir: [f32; 4],
}

/// Times `req.frames` full-screen frames of `req.method` over `hf`.
pub fn time_method(
    ctx: &Arc<Context>,
    hf: &Heightfield,
    req: &BenchRequest<'_>,
) -> VkResult<BenchTiming> {
    let (w, h) = req.resolution;
    if req.frames == 0 || w == 0 || h == 0 {
        return Err(VkError::Invalid(format!(
            "bench of {} frames at {w}x{h}",
            req.frames
        )));
    }
    let key = format!("bench.frag:{}", req.method.id());
    let missing = |k: &str| VkError::Invalid(format!("no compiled shader {k}"));
    let fs = shaders::spirv(&key).ok_or_else(|| missing(&key))?;
    let vs = shaders::spirv("fullscreen.vert").ok_or_else(|| missing("fullscreen.vert"))?;
    let res = HeightResources::new(
        ctx,
        hf,
        req.format,
        req.address,
        req.map,
        bytemuck::Zeroable::zeroed(),
    )?;
    let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    let layout = DescriptorLayout::new(ctx, &res.layout_bindings(), stages, "bench layout")?;
    let pool = DescriptorPool::new(ctx, 1, 2, "bench sets")?;
    let set = pool.allocate(&layout, &res.binds())?;
    let spec = SpecConstants::default()
        .u32(0, req.budget.max_steps)
        .u32(1, req.budget.refine_steps);
    let desc = GraphicsDesc {
        vertex: vs,
        fragment: fs,
        fragment_spec: &spec,
        vertex_stride: 0,
        attributes: &[],
        color_format: HIT_FORMAT,
        depth_format: vk::Format::UNDEFINED,
        cull: vk::CullModeFlags::NONE,
        set_layouts: &[layout.raw()],
        push_bytes: std::mem::size_of::<BenchParams>() as u32,
    };
    let pipeline = graphics_pipeline(ctx, &desc, &key)?;
    let target = Image::new(
        ctx,
        ImageDesc {
            width: w,
            height: h,
            format: HIT_FORMAT,
            mip_levels: 1,
            usage: vk::ImageUsageFlags::COLOR_ATTACHMENT,
            aspect: vk::ImageAspectFlags::COLOR,
        },
        "bench target",
    )?;
    let timestamps = TimestampPool::new(ctx, 2 * req.frames, "bench timestamps")?;
    let params = BenchParams {
        dir: [req.dir[0], req.dir[1], req.dir[2], req.depth_scale],
    };
    let device = ctx.device();
    let all = vk::PipelineStageFlags2::ALL_COMMANDS;
    let full = (
        all,
        vk::AccessFlags2::MEMORY_READ | vk::AccessFlags2::MEMORY_WRITE,
    );
    ctx.one_shot(|cmd| {
        res.record_pyramid(cmd);
        transition_images(device, cmd, &[to_attachment(&target)]);
        for frame in 0..req.warmup + req.frames {
            let timed = frame.checked_sub(req.warmup);
            if let Some(k) = timed {
                timestamps.write(cmd, all, 2 * k)?;
            }
            draw(device, cmd, &target, (w, h), |cmd| {
                pipeline.bind(cmd, Some(set));
                pipeline.push(cmd, bytemuck::bytes_of(&params));
            });
            if let Some(k) = timed {
                timestamps.write(cmd, all, 2 * k + 1)?;
            }
            memory_barrier(device, cmd, full, full);
        }
        Ok(())
    })?;
    let ticks = timestamps.read_ticks(2 * req.frames)?;
    let frame_ms = ticks
        .chunks_exact(2)
        .map(|t| timestamps.ticks_to_ms(t[0], t[1]))
        .collect();
    Ok(BenchTiming { frame_ms })
}

fn to_attachment(target: &Image) -> ImageTransition {
    ImageTransition {
        image: target.raw(),
        aspect: vk::ImageAspectFlags::COLOR,
        base_mip: 0,
        mip_count: 1,
        old: vk::ImageLayout::UNDEFINED,
        new: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        src: (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
        dst: (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        ),
    }
}

fn draw(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    target: &Image,
    (w, h): (u32, u32),
    bind: impl Fn(vk::CommandBuffer),
) {
    let attachment = [vk::RenderingAttachmentInfo::default()
        .image_view(target.view())
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::DONT_CARE)
        .store_op(vk::AttachmentStoreOp::STORE)];
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent: vk::Extent2D {
            width: w,
            height: h,
        },
    };
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&attachment);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: w as f32,
        height: h as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: `cmd` is recording; the target is in COLOR_ATTACHMENT_OPTIMAL.
    unsafe {
        device.cmd_begin_rendering(cmd, &info);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
    bind(cmd);
    // SAFETY: a pipeline and its set are bound; the vertex shader makes its own triangle.
    unsafe {
        device.cmd_draw(cmd, 3, 1, 0, 0);
        device.cmd_end_rendering(cmd);
    }
}
