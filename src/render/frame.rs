//! One frame, offscreen: upload the height field, build its pyramid, draw the scene into colour
//! and depth targets, read the colour back. Each pass sits between GPU timestamps.

use std::borrow::Cow;
use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use serde::Serialize;

use super::frame_uniforms::FrameUniforms;
use super::gpu_heightfield::HeightFormat;
use super::height_resources::HeightResources;
use super::map_builder::{build_method_map_with, MapBuilder};
use super::plan::{HeightKey, HeightPlan, Plan, PlanError};
use super::surface_pass::{SurfacePass, COLOR_FORMAT, DEPTH_FORMAT};
use crate::heightfield::Address;
use crate::heightfield::{Heightfield, HeightfieldError, LoadOptions};
use crate::method::MapKind;
use crate::scene::Scene;
use crate::vk::{
    read_mip, transition_images, Context, Image, ImageDesc, ImageTransition, TimestampPool,
    VkError, VkResult,
};

/// What to render.
#[derive(Debug, Clone, Copy)]
pub struct RenderOptions {
    pub width: u32,
    pub height: u32,
    pub height_format: HeightFormat,
    pub address: Address,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 960,
            height: 540,
            height_format: HeightFormat::R16Unorm,
            address: Address::Repeat,
        }
    }
}

/// GPU time of one pass.
#[derive(Debug, Clone, Serialize)]
pub struct PassTiming {
    pub pass: &'static str,
    pub gpu_ms: f64,
}

/// A map the frame built: the pyramid and the conservative cone map on the GPU, the other
/// precomputed maps on the CPU.
#[derive(Debug, Clone, Serialize)]
pub struct BuiltMap {
    pub kind: &'static str,
    /// The height map it belongs to.
    pub source: String,
    pub size: [u32; 2],
    /// GPU ms for maps built on the GPU, CPU wall ms for those built on the CPU.
    pub ms: f64,
    /// "gpu" or "cpu".
    pub on: &'static str,
}

/// A rendered image (sRGB RGBA8, rows top to bottom), how long each pass took, and the plan it
/// followed.
#[derive(Debug, Clone)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
    pub timings: Vec<PassTiming>,
    /// CPU wall time of uploading height maps and precomputed maps, in ms.
    pub upload_ms: f64,
    pub plan: Plan,
    pub maps: Vec<BuiltMap>,
}

/// Why a frame could not be rendered.
#[derive(Debug, thiserror::Error)]
pub enum RenderError {
    #[error(transparent)]
    Plan(#[from] PlanError),
    #[error(transparent)]
    Height(#[from] HeightfieldError),
    #[error(transparent)]
    Vulkan(#[from] VkError),
}

const CLEAR: [f32; 4] = [0.015, 0.02, 0.03, 1.0];

fn target(ctx: &Arc<Context>, opts: &RenderOptions, depth: bool) -> VkResult<Image> {
    let (format, usage, aspect, name) = if depth {
        (
            DEPTH_FORMAT,
            vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT,
            vk::ImageAspectFlags::DEPTH,
            "depth target",
        )
    } else {
        (
            COLOR_FORMAT,
            vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC,
            vk::ImageAspectFlags::COLOR,
            "colour target",
        )
    };
    let desc = ImageDesc {
        width: opts.width,
        height: opts.height,
        format,
        mip_levels: 1,
        usage,
        aspect,
    };
    Image::new(ctx, desc, name)
}

/// The heights of one planned height map, as stored on the GPU. The frame's own map is borrowed
/// when it is stored as it is (R32F), not copied.
fn planned_heights<'a>(
    ctx: &Arc<Context>,
    scene: &Scene,
    plan: &HeightPlan,
    frame_heights: Option<&'a Heightfield>,
    format: HeightFormat,
) -> Result<Cow<'a, Heightfield>, RenderError> {
    let hf = match plan.key {
        HeightKey::Frame => Cow::Borrowed(
            frame_heights
                .ok_or_else(|| VkError::Invalid("the plan reads a frame height map".into()))?,
        ),
        HeightKey::Image {
            image,
            channel,
            invert,
            ..
        } => {
            let opts = LoadOptions { channel, invert };
            Cow::Owned(Heightfield::from_dynamic_image(
                &scene.images[image].pixels,
                &opts,
                &plan.source,
            )?)
        }
    };
    hf.check_max_dimension(ctx.info().max_image_dimension_2d, &plan.source)?;
    Ok(match format {
        HeightFormat::R16Unorm => Cow::Owned(hf.quantized_unorm16()),
        HeightFormat::R32Float => hf,
    })
}

/// Renders `scene`. Relief materials without a height texture of their own read `frame_heights`.
pub fn render(
    ctx: &Arc<Context>,
    scene: &Scene,
    frame_heights: Option<&Heightfield>,
    opts: &RenderOptions,
) -> Result<Frame, RenderError> {
    let plan = Plan::derive(scene, frame_heights)?;
    let aspect = opts.width as f32 / opts.height as f32;
    let uniforms = FrameUniforms::for_scene(scene, &plan.lights, aspect);
    let started = Instant::now();
    let mut heights = Vec::with_capacity(plan.heights.len());
    let mut maps = Vec::new();
    for hp in &plan.heights {
        let stored = planned_heights(ctx, scene, hp, frame_heights, opts.height_format)?;
        let address = match hp.key {
            HeightKey::Frame => opts.address,
            HeightKey::Image { address, .. } => address,
        };
        let map = match hp.map_method {
            Some(method) => build_method_map_with(method, &stored, address, MapBuilder::Gpu(ctx))?,
            None => None,
        };
        if let (Some(built), Some(kind)) = (&map, hp.map) {
            maps.push(BuiltMap {
                kind: kind.name(),
                source: hp.source.clone(),
                size: [built.data.width, built.data.height],
                ms: built.ms,
                on: built.on,
            });
        }
        heights.push(HeightResources::with_pyramid(
            ctx,
            &stored,
            opts.height_format,
            address,
            map.as_ref().map(|built| &built.data),
            uniforms,
            hp.pyramid,
        )?);
    }
    let upload_ms = started.elapsed().as_secs_f64() * 1e3;
    let surface = SurfacePass::new(ctx, scene, &plan, &heights, &uniforms)?;
    let color = target(ctx, opts, false)?;
    let depth = target(ctx, opts, true)?;
    let stamps = heights.len() as u32 + 2;
    let timestamps = TimestampPool::new(ctx, stamps, "frame timestamps")?;
    let device = ctx.device();
    let all = vk::PipelineStageFlags2::ALL_COMMANDS;
    ctx.one_shot(|cmd| {
        timestamps.write(cmd, all, 0)?;
        for (k, h) in heights.iter().enumerate() {
            h.record_pyramid(cmd);
            timestamps.write(cmd, all, k as u32 + 1)?;
        }
        begin_targets(device, cmd, &color, &depth, opts);
        surface.record_draws(device, cmd);
        // SAFETY: rendering was begun by begin_targets.
        unsafe { device.cmd_end_rendering(cmd) };
        timestamps.write(cmd, all, stamps - 1)?;
        transition_images(device, cmd, &[color_to_transfer(&color)]);
        Ok(())
    })?;
    let ticks = timestamps.read_ticks(stamps)?;
    let last = stamps as usize - 1;
    for (k, hp) in plan.heights.iter().enumerate().filter(|(_, hp)| hp.pyramid) {
        maps.push(BuiltMap {
            kind: MapKind::MaxPyramid.name(),
            source: hp.source.clone(),
            size: [hp.size.0, hp.size.1],
            ms: timestamps.ticks_to_ms(ticks[k], ticks[k + 1]),
            on: "gpu",
        });
    }
    let mut timings = Vec::new();
    if plan.heights.iter().any(|h| h.pyramid) {
        timings.push(PassTiming {
            pass: "pyramid",
            gpu_ms: timestamps.ticks_to_ms(ticks[0], ticks[last - 1]),
        });
    }
    timings.push(PassTiming {
        pass: "surface",
        gpu_ms: timestamps.ticks_to_ms(ticks[last - 1], ticks[last]),
    });
    let rgba = read_mip(ctx, &color, 0, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)?;
    Ok(Frame {
        width: opts.width,
        height: opts.height,
        rgba,
        timings,
        upload_ms,
        plan,
        maps,
    })
}

fn color_to_transfer(color: &Image) -> ImageTransition {
    ImageTransition {
        image: color.raw(),
        aspect: vk::ImageAspectFlags::COLOR,
        base_mip: 0,
        mip_count: 1,
        old: vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
        new: vk::ImageLayout::TRANSFER_SRC_OPTIMAL,
        src: (
            vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
            vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
        ),
        dst: (
            vk::PipelineStageFlags2::COPY,
            vk::AccessFlags2::TRANSFER_READ,
        ),
    }
}

fn begin_targets(
    device: &ash::Device,
    cmd: vk::CommandBuffer,
    color: &Image,
    depth: &Image,
    opts: &RenderOptions,
) {
    let to_attachment = |image: &Image, aspect, layout, stage, access| ImageTransition {
        image: image.raw(),
        aspect,
        base_mip: 0,
        mip_count: 1,
        old: vk::ImageLayout::UNDEFINED,
        new: layout,
        src: (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE),
        dst: (stage, access),
    };
    transition_images(
        device,
        cmd,
        &[
            to_attachment(
                color,
                vk::ImageAspectFlags::COLOR,
                vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT,
                vk::AccessFlags2::COLOR_ATTACHMENT_WRITE,
            ),
            to_attachment(
                depth,
                vk::ImageAspectFlags::DEPTH,
                vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL,
                vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
                    | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS,
                vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE
                    | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ,
            ),
        ],
    );
    let color_attachment = [vk::RenderingAttachmentInfo::default()
        .image_view(color.view())
        .image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::STORE)
        .clear_value(vk::ClearValue {
            color: vk::ClearColorValue { float32: CLEAR },
        })];
    let depth_attachment = vk::RenderingAttachmentInfo::default()
        .image_view(depth.view())
        .image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)
        .load_op(vk::AttachmentLoadOp::CLEAR)
        .store_op(vk::AttachmentStoreOp::DONT_CARE)
        .clear_value(vk::ClearValue {
            depth_stencil: vk::ClearDepthStencilValue {
                depth: 1.0,
                stencil: 0,
            },
        });
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent: vk::Extent2D {
            width: opts.width,
            height: opts.height,
        },
    };
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&color_attachment)
        .depth_attachment(&depth_attachment);
    let viewport = vk::Viewport {
        x: 0.0,
        y: 0.0,
        width: opts.width as f32,
        height: opts.height as f32,
        min_depth: 0.0,
        max_depth: 1.0,
    };
    // SAFETY: `cmd` is recording; the attachments are in the layouts named above.
    unsafe {
        device.cmd_begin_rendering(cmd, &info);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
}
