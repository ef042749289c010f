//! One frame, offscreen: upload the height field, build its pyramid, draw the scene into colour
//! and depth targets, read the colour back. Each pass sits between GPU timestamps.

use std::sync::Arc;
use std::time::Instant;

use ash::vk;
use glam::Vec3;
use serde::Serialize;

use super::gpu_heightfield::{Addressing, HeightFormat};
use super::height_resources::HeightResources;
use super::method_map::MapData;
use super::surface_pass::{FrameUniforms, SurfacePass, COLOR_FORMAT, DEPTH_FORMAT};
use crate::heightfield::reference::Address;
use crate::heightfield::Heightfield;
use crate::method::{build_method_map, MapKind};
use crate::scene::{Camera, Light, Scene};
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
    pub address: Addressing,
}

impl Default for RenderOptions {
    fn default() -> Self {
        RenderOptions {
            width: 960,
            height: 540,
            height_format: HeightFormat::R16Unorm,
            address: Addressing::Repeat,
        }
    }
}

/// GPU time of one pass.
#[derive(Debug, Clone, Serialize)]
pub struct PassTiming {
    pub pass: &'static str,
    pub gpu_ms: f64,
}

/// A rendered image (sRGB RGBA8, rows top to bottom) and how long each pass took.
#[derive(Debug, Clone)]
pub struct Frame {
    pub width: u32,
    pub height: u32,
    pub rgba: Vec<u8>,
    pub timings: Vec<PassTiming>,
    /// CPU wall time of the upload of the height field, in ms.
    pub upload_ms: f64,
    /// Keys of the surface pipelines built.
    pub pipelines: Vec<(String, bool)>,
}

const CLEAR: [f32; 4] = [0.015, 0.02, 0.03, 1.0];
const AMBIENT: [f32; 4] = [0.09, 0.1, 0.12, 0.0];

fn uniforms(scene: &Scene, aspect: f32) -> FrameUniforms {
    let camera = scene.camera.unwrap_or_else(|| match scene.bounds() {
        Some((lo, hi)) => Camera::framing(lo, hi),
        None => Camera::look_at(Vec3::new(0.0, 1.0, 3.0), Vec3::ZERO, 0.8, 0.1, 100.0),
    });
    let light = scene
        .lights
        .first()
        .copied()
        .unwrap_or_else(Light::default_light);
    let eye = camera.eye();
    FrameUniforms {
        view_proj: camera.view_projection(aspect).to_cols_array_2d(),
        eye: [eye.x, eye.y, eye.z, 1.0],
        light_dir: [light.direction.x, light.direction.y, light.direction.z, 1.0],
        light_color: [light.color.x, light.color.y, light.color.z, 0.0],
        ambient: AMBIENT,
        // Filled in by HeightResources.
        height_info: [0.0; 4],
    }
}

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

/// The precomputed map the scene's relief methods read, built on the CPU. One kind per frame:
/// materials whose methods need different maps would need a set per material.
fn frame_map(
    scene: &Scene,
    stored: &Heightfield,
    address: Addressing,
) -> VkResult<Option<MapData>> {
    let reference_address = match address {
        Addressing::Repeat => Address::Repeat,
        Addressing::Clamp => Address::Clamp,
    };
    let mut kinds: Vec<_> = scene
        .materials
        .iter()
        .filter_map(|m| m.relief.map(|r| r.method))
        .filter(|m| m.info().needs.iter().any(|k| *k != MapKind::MaxPyramid))
        .collect();
    kinds.dedup();
    match kinds.as_slice() {
        [] => Ok(None),
        [method] => Ok(build_method_map(*method, stored, reference_address).map(|(data, _)| data)),
        many => Err(VkError::Invalid(format!(
            "materials use {} methods with precomputed maps ({}); relief renders one such method per frame",
            many.len(),
            many.iter().map(|m| m.id()).collect::<Vec<_>>().join(", ")
        ))),
    }
}

/// Renders `scene`, displacing its relief materials with `heights`.
pub fn render(
    ctx: &Arc<Context>,
    scene: &Scene,
    heights: &Heightfield,
    opts: &RenderOptions,
) -> VkResult<Frame> {
    let stored = match opts.height_format {
        HeightFormat::R16Unorm => heights.quantized_unorm16(),
        HeightFormat::R32Float => heights.clone(),
    };
    let map = frame_map(scene, &stored, opts.address)?;
    let aspect = opts.width as f32 / opts.height as f32;
    let started = Instant::now();
    let res = HeightResources::new(
        ctx,
        &stored,
        opts.height_format,
        opts.address,
        map.as_ref(),
        uniforms(scene, aspect),
    )?;
    let upload_ms = started.elapsed().as_secs_f64() * 1e3;
    let surface = SurfacePass::new(ctx, scene, &res)?;
    let color = target(ctx, opts, false)?;
    let depth = target(ctx, opts, true)?;
    let timestamps = TimestampPool::new(ctx, 4, "frame timestamps")?;
    let device = ctx.device();
    let all = vk::PipelineStageFlags2::ALL_COMMANDS;
    ctx.one_shot(|cmd| {
        timestamps.write(cmd, all, 0)?;
        res.record_pyramid(cmd);
        timestamps.write(cmd, all, 1)?;
        begin_targets(device, cmd, &color, &depth, opts);
        surface.record_draws(device, cmd);
        // SAFETY: rendering was begun by begin_targets.
        unsafe { device.cmd_end_rendering(cmd) };
        timestamps.write(cmd, all, 2)?;
        transition_images(device, cmd, &[color_to_transfer(&color)]);
        Ok(())
    })?;
    let ticks = timestamps.read_ticks(3)?;
    let timings = vec![
        PassTiming {
            pass: "pyramid",
            gpu_ms: timestamps.ticks_to_ms(ticks[0], ticks[1]),
        },
        PassTiming {
            pass: "surface",
            gpu_ms: timestamps.ticks_to_ms(ticks[1], ticks[2]),
        },
    ];
    let rgba = read_mip(ctx, &color, 0, vk::ImageLayout::TRANSFER_SRC_OPTIMAL)?;
    Ok(Frame {
        width: opts.width,
        height: opts.height,
        rgba,
        timings,
        upload_ms,
        pipelines: surface.pipeline_keys(),
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
