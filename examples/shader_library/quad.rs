//! A relief quad drawn by a pipeline of the example's own, written in raw `ash`: its shaders
//! (`quad.vert`, `quad.frag`) include nothing but relief's shader library, and the height image
//! they read is built on the CPU by the library's map builder. relief's `vk` layer lends the
//! device, images and one-shot submission; no `Renderer`, scene or pass of relief's is involved.

use std::sync::Arc;

use anyhow::Context as _;
use glam::{Mat4, Vec3};
use relief::heightfield::{Heightfield, MaxPyramid};
use relief::method::Method;
use relief::shader_library::{self, DEFAULT_SPEC_ID_BASE};
use relief::vk::raw as vk;
use relief::vk::{
    read_mip, transition_images, upload_mips, Context, Image, ImageDesc, ImageTransition, Sampler,
};

/// The SPIR-V relief's build compiled from `quad.vert` and `quad.frag` against the shader
/// library's files alone; an engine compiles them with its own toolchain, its include path on
/// the folder `shader_library::write_to` fills.
const VERTEX: &[u8] = include_bytes!(concat!(
    env!("OUT_DIR"),
    "/shader_library_example/quad.vert.spv"
));
const FRAGMENT: &[u8] = include_bytes!(concat!(
    env!("OUT_DIR"),
    "/shader_library_example/quad.frag.spv"
));
/// `quad.frag` compiled with `RELIEF_REVERSE_Z`, for an engine whose depth is reversed.
const FRAGMENT_REVERSE_Z: &[u8] = include_bytes!(concat!(
    env!("OUT_DIR"),
    "/shader_library_example/quad_reverse_z.frag.spv"
));

/// The camera's clip planes.
pub const NEAR: f32 = 0.05;
pub const FAR: f32 = 50.0;

/// The quad (side `2 * half` in the XZ plane, the map once across it) and the camera.
pub struct QuadView {
    pub eye: Vec3,
    pub target: Vec3,
    pub yfov: f32,
    pub half: f32,
    /// In uv units, as relief's materials give it.
    pub depth_scale: f32,
    pub width: u32,
    pub height: u32,
    /// Depth reversed, as many engines keep it: 1 at the near plane, 0 at the far one.
    pub reverse_z: bool,
}

impl QuadView {
    pub fn view_projection(&self) -> Mat4 {
        let aspect = self.width as f32 / self.height as f32;
        let (near, far) = if self.reverse_z {
            (FAR, NEAR)
        } else {
            (NEAR, FAR)
        };
        let projection = Mat4::perspective_rh(self.yfov, aspect, near, far);
        // Vulkan's framebuffer y points down.
        Mat4::from_scale(Vec3::new(1.0, -1.0, 1.0))
            * projection
            * Mat4::look_at_rh(self.eye, self.target, Vec3::Y)
    }
}

/// What the pass wrote: sRGB RGBA8 pixels, per pixel (u, v, steps, view depth) of the hit
/// (zero where the quad is not), and the depth attachment (the displaced depth, in the view's
/// convention).
pub struct QuadImages {
    pub rgba: Vec<u8>,
    pub hits: Vec<[f32; 4]>,
    pub depth: Vec<f32>,
}

/// The push constants of both shaders.
#[repr(C)]
#[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct Push {
    view_proj: [f32; 16],
    eye: [f32; 4],
    forward: [f32; 4],
    quad: [f32; 4],
    height_info: [f32; 4],
}

const COLOR: vk::Format = vk::Format::R8G8B8A8_SRGB;
const HIT: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
const DEPTH: vk::Format = vk::Format::D32_SFLOAT;

/// Draws the quad displaced by `heights` (repeat addressing) with QDM.
pub fn draw_quad(
    ctx: &Arc<Context>,
    heights: &Heightfield,
    view: &QuadView,
) -> anyhow::Result<QuadImages> {
    let (height_image, levels) = upload_heights(ctx, heights)?;
    let repeat = vk::SamplerAddressMode::REPEAT;
    let nearest = Sampler::new(ctx, vk::Filter::NEAREST, repeat, "library nearest")?;
    let bilinear = Sampler::new(ctx, vk::Filter::LINEAR, repeat, "library bilinear")?;

    let target = |format, aspect, usage, name| {
        let desc = ImageDesc {
            width: view.width,
            height: view.height,
            format,
            mip_levels: 1,
            usage,
            aspect,
        };
        Image::new(ctx, desc, name)
    };
    let attach = vk::ImageUsageFlags::COLOR_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    let color = target(COLOR, vk::ImageAspectFlags::COLOR, attach, "library colour")?;
    let hits = target(HIT, vk::ImageAspectFlags::COLOR, attach, "library hits")?;
    let depth_usage =
        vk::ImageUsageFlags::DEPTH_STENCIL_ATTACHMENT | vk::ImageUsageFlags::TRANSFER_SRC;
    let depth = target(
        DEPTH,
        vk::ImageAspectFlags::DEPTH,
        depth_usage,
        "library depth",
    )?;

    let pass = RawPass::new(ctx, view.reverse_z)?;
    pass.bind_heights(height_image.view().raw(), nearest.raw(), bilinear.raw());
    let forward = (view.target - view.eye).normalize();
    let push = Push {
        view_proj: view.view_projection().to_cols_array(),
        eye: view.eye.extend(1.0).into(),
        forward: forward.extend(0.0).into(),
        quad: [view.half, view.depth_scale, 0.0, 0.0],
        height_info: [
            heights.width() as f32,
            heights.height() as f32,
            levels as f32,
            1.0,
        ],
    };
    let color_out = vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL;
    ctx.one_shot(|rec| {
        transition_images(
            rec,
            &[
                into_attachment(&color, color_out),
                into_attachment(&hits, color_out),
                into_attachment(&depth, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL),
            ],
        );
        let far = if view.reverse_z { 0.0 } else { 1.0 };
        begin_rendering(rec.raw(), ctx.device(), [&color, &hits], &depth, far);
        pass.draw(rec.raw(), &push);
        rec.end_rendering();
        Ok(())
    })?;
    let rgba = read_mip(ctx, &color, 0, color_out)?;
    let hit_bytes = read_mip(ctx, &hits, 0, color_out)?;
    let hits = bytemuck::pod_collect_to_vec::<u8, [f32; 4]>(&hit_bytes);
    let depth_bytes = read_mip(ctx, &depth, 0, vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL)?;
    let depth = bytemuck::pod_collect_to_vec::<u8, f32>(&depth_bytes);
    Ok(QuadImages { rgba, hits, depth })
}

/// Begins dynamic rendering into the two colour targets (cleared to zero) and the depth
/// attachment, cleared to the far plane's depth `far` and kept.
fn begin_rendering(
    cmd: vk::CommandBuffer,
    device: &ash::Device,
    colors: [&Image; 2],
    depth: &Image,
    far: f32,
) {
    let extent = vk::Extent2D {
        width: colors[0].desc().width,
        height: colors[0].desc().height,
    };
    let attachment = |image: &Image, clear| {
        vk::RenderingAttachmentInfo::default()
            .image_view(image.view().raw())
            .load_op(vk::AttachmentLoadOp::CLEAR)
            .store_op(vk::AttachmentStoreOp::STORE)
            .clear_value(clear)
    };
    let cleared = vk::ClearValue {
        color: vk::ClearColorValue { float32: [0.0; 4] },
    };
    let colors = colors.map(|image| {
        attachment(image, cleared).image_layout(vk::ImageLayout::COLOR_ATTACHMENT_OPTIMAL)
    });
    let far = vk::ClearValue {
        depth_stencil: vk::ClearDepthStencilValue {
            depth: far,
            stencil: 0,
        },
    };
    let depth = attachment(depth, far).image_layout(vk::ImageLayout::DEPTH_ATTACHMENT_OPTIMAL);
    let area = vk::Rect2D {
        offset: vk::Offset2D::default(),
        extent,
    };
    let info = vk::RenderingInfo::default()
        .render_area(area)
        .layer_count(1)
        .color_attachments(&colors)
        .depth_attachment(&depth);
    let viewport = vk::Viewport {
        width: extent.width as f32,
        height: extent.height as f32,
        max_depth: 1.0,
        ..Default::default()
    };
    // SAFETY: `cmd` is recording; the attachments are alive and in the layouts named.
    unsafe {
        device.cmd_begin_rendering(cmd, &info);
        device.cmd_set_viewport(cmd, 0, &[viewport]);
        device.cmd_set_scissor(cmd, 0, &[area]);
    }
}

/// The height image the library's contract asks for: level 0 the heights, levels 1.. the max
/// pyramid that bounds the bilinear surface; and its level count.
fn upload_heights(ctx: &Arc<Context>, heights: &Heightfield) -> anyhow::Result<(Image, u32)> {
    let pyramid = MaxPyramid::build_bilinear_bound(heights, true);
    let desc = ImageDesc {
        width: heights.width(),
        height: heights.height(),
        format: vk::Format::R32_SFLOAT,
        mip_levels: pyramid.level_count(),
        usage: vk::ImageUsageFlags::SAMPLED | vk::ImageUsageFlags::TRANSFER_DST,
        aspect: vk::ImageAspectFlags::COLOR,
    };
    let image = Image::new(ctx, desc, "library heights")?;
    let levels: Vec<&[u8]> = pyramid
        .levels()
        .iter()
        .map(|l| bytemuck::cast_slice(&l.data))
        .collect();
    let read = vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL;
    upload_mips(ctx, &image, &levels, read)?;
    Ok((image, pyramid.level_count()))
}

/// `image`, contents dropped, into attachment `layout` before the pass writes it.
fn into_attachment(image: &Image, layout: vk::ImageLayout) -> ImageTransition<'_> {
    let none = (vk::PipelineStageFlags2::NONE, vk::AccessFlags2::NONE);
    let fragments = vk::PipelineStageFlags2::EARLY_FRAGMENT_TESTS
        | vk::PipelineStageFlags2::LATE_FRAGMENT_TESTS
        | vk::PipelineStageFlags2::COLOR_ATTACHMENT_OUTPUT;
    let access = vk::AccessFlags2::COLOR_ATTACHMENT_WRITE
        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_READ
        | vk::AccessFlags2::DEPTH_STENCIL_ATTACHMENT_WRITE;
    ImageTransition {
        aspect: image.desc().aspect,
        dst: (fragments, access),
        ..ImageTransition::color(image, (vk::ImageLayout::UNDEFINED, layout), none, none)
    }
}

/// The example's own Vulkan objects: shader modules, layouts, the pipeline and its descriptor
/// set, destroyed once, when the pass goes (after the one-shot that used them has finished).
struct RawPass {
    device: ash::Device,
    modules: [vk::ShaderModule; 2],
    set_layout: vk::DescriptorSetLayout,
    layout: vk::PipelineLayout,
    pipeline: vk::Pipeline,
    pool: vk::DescriptorPool,
    set: vk::DescriptorSet,
}

impl RawPass {
    fn new(ctx: &Context, reverse_z: bool) -> anyhow::Result<RawPass> {
        let device = ctx.device().clone();
        let module = |spirv: &[u8]| -> anyhow::Result<vk::ShaderModule> {
            let words = ash::util::read_spv(&mut std::io::Cursor::new(spirv))?;
            // SAFETY: valid SPIR-V from the build; the module is destroyed in Drop.
            Ok(unsafe {
                device
                    .create_shader_module(&vk::ShaderModuleCreateInfo::default().code(&words), None)
            }?)
        };
        let mut pass = RawPass {
            modules: [vk::ShaderModule::null(); 2],
            device: device.clone(),
            set_layout: vk::DescriptorSetLayout::null(),
            layout: vk::PipelineLayout::null(),
            pipeline: vk::Pipeline::null(),
            pool: vk::DescriptorPool::null(),
            set: vk::DescriptorSet::null(),
        };
        let sampled = |binding| {
            vk::DescriptorSetLayoutBinding::default()
                .binding(binding)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .descriptor_count(1)
                .stage_flags(vk::ShaderStageFlags::FRAGMENT)
        };
        let bindings = [sampled(0), sampled(1)];
        pass.modules = [module(VERTEX)?, vk::ShaderModule::null()];
        pass.modules[1] = module(if reverse_z {
            FRAGMENT_REVERSE_Z
        } else {
            FRAGMENT
        })?;
        // SAFETY (this block): valid create infos on a live device; each handle is stored in the
        // pass as soon as it exists, so Drop destroys exactly what was made.
        unsafe {
            pass.set_layout = device.create_descriptor_set_layout(
                &vk::DescriptorSetLayoutCreateInfo::default().bindings(&bindings),
                None,
            )?;
            let range = [vk::PushConstantRange::default()
                .stage_flags(vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT)
                .size(std::mem::size_of::<Push>() as u32)];
            let set_layouts = [pass.set_layout];
            pass.layout = device.create_pipeline_layout(
                &vk::PipelineLayoutCreateInfo::default()
                    .set_layouts(&set_layouts)
                    .push_constant_ranges(&range),
                None,
            )?;
            pass.pipeline = pass.create_pipeline(reverse_z)?;
            let sizes = [vk::DescriptorPoolSize {
                ty: vk::DescriptorType::COMBINED_IMAGE_SAMPLER,
                descriptor_count: 2,
            }];
            pass.pool = device.create_descriptor_pool(
                &vk::DescriptorPoolCreateInfo::default()
                    .max_sets(1)
                    .pool_sizes(&sizes),
                None,
            )?;
            let alloc = vk::DescriptorSetAllocateInfo::default()
                .descriptor_pool(pass.pool)
                .set_layouts(&set_layouts);
            pass.set = device.allocate_descriptor_sets(&alloc)?[0];
        }
        Ok(pass)
    }

    /// QDM with relief's own budget for it, and the cone walk for the sun's self-shadow.
    fn create_pipeline(&self, reverse_z: bool) -> anyhow::Result<vk::Pipeline> {
        let mut constants: Vec<(u32, u32)> =
            shader_library::budget_constants(Method::QDM, DEFAULT_SPEC_ID_BASE).to_vec();
        let shadow_mode = shader_library::spec_constants()
            .find(|c| c.name == "SPEC_SHADOW_MODE")
            .context("shadow mode id")?;
        constants.push((DEFAULT_SPEC_ID_BASE + shadow_mode.offset, 4)); // SHADOW_MODE_CONE
        let entries: Vec<vk::SpecializationMapEntry> = (0..constants.len() as u32)
            .map(|k| vk::SpecializationMapEntry {
                constant_id: constants[k as usize].0,
                offset: 4 * k,
                size: 4,
            })
            .collect();
        let values: Vec<u32> = constants.iter().map(|&(_, v)| v).collect();
        let spec = vk::SpecializationInfo::default()
            .map_entries(&entries)
            .data(bytemuck::cast_slice(&values));
        let stages = [
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::VERTEX)
                .module(self.modules[0])
                .name(c"main"),
            vk::PipelineShaderStageCreateInfo::default()
                .stage(vk::ShaderStageFlags::FRAGMENT)
                .module(self.modules[1])
                .name(c"main")
                .specialization_info(&spec),
        ];
        let vertex_input = vk::PipelineVertexInputStateCreateInfo::default();
        let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
            .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
        let viewport = vk::PipelineViewportStateCreateInfo::default()
            .viewport_count(1)
            .scissor_count(1);
        let raster = vk::PipelineRasterizationStateCreateInfo::default()
            .polygon_mode(vk::PolygonMode::FILL)
            .cull_mode(vk::CullModeFlags::NONE)
            .line_width(1.0);
        let multisample = vk::PipelineMultisampleStateCreateInfo::default()
            .rasterization_samples(vk::SampleCountFlags::TYPE_1);
        let depth = vk::PipelineDepthStencilStateCreateInfo::default()
            .depth_test_enable(true)
            .depth_write_enable(true)
            .depth_compare_op(if reverse_z {
                vk::CompareOp::GREATER_OR_EQUAL
            } else {
                vk::CompareOp::LESS_OR_EQUAL
            });
        let blend = [vk::PipelineColorBlendAttachmentState::default()
            .color_write_mask(vk::ColorComponentFlags::RGBA); 2];
        let blending = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend);
        let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
        let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
        let formats = [COLOR, HIT];
        let mut rendering = vk::PipelineRenderingCreateInfo::default()
            .color_attachment_formats(&formats)
            .depth_attachment_format(DEPTH);
        let info = vk::GraphicsPipelineCreateInfo::default()
            .stages(&stages)
            .vertex_input_state(&vertex_input)
            .input_assembly_state(&assembly)
            .viewport_state(&viewport)
            .rasterization_state(&raster)
            .multisample_state(&multisample)
            .depth_stencil_state(&depth)
            .color_blend_state(&blending)
            .dynamic_state(&dynamic)
            .layout(self.layout)
            .push_next(&mut rendering);
        // SAFETY: every state the pipeline reads is above and alive for the call.
        let made = unsafe {
            self.device
                .create_graphics_pipelines(vk::PipelineCache::null(), &[info], None)
        };
        Ok(made.map_err(|(_, e)| e)?[0])
    }

    fn bind_heights(&self, view: vk::ImageView, nearest: vk::Sampler, bilinear: vk::Sampler) {
        let image = |sampler| {
            [vk::DescriptorImageInfo {
                sampler,
                image_view: view,
                image_layout: vk::ImageLayout::SHADER_READ_ONLY_OPTIMAL,
            }]
        };
        let (point, linear) = (image(nearest), image(bilinear));
        let write = |binding, info| {
            vk::WriteDescriptorSet::default()
                .dst_set(self.set)
                .dst_binding(binding)
                .descriptor_type(vk::DescriptorType::COMBINED_IMAGE_SAMPLER)
                .image_info(info)
        };
        // SAFETY: the set is not in use by any submission yet; the view and samplers outlive
        // the one-shot that reads them (the caller holds them).
        unsafe {
            self.device
                .update_descriptor_sets(&[write(0, &point), write(1, &linear)], &[])
        };
    }

    fn draw(&self, cmd: vk::CommandBuffer, push: &Push) {
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        // SAFETY: `cmd` is recording inside dynamic rendering with the formats the pipeline was
        // made for; the set's resources are alive until the submission ends.
        unsafe {
            self.device
                .cmd_bind_pipeline(cmd, vk::PipelineBindPoint::GRAPHICS, self.pipeline);
            self.device.cmd_bind_descriptor_sets(
                cmd,
                vk::PipelineBindPoint::GRAPHICS,
                self.layout,
                0,
                &[self.set],
                &[],
            );
            self.device
                .cmd_push_constants(cmd, self.layout, stages, 0, bytemuck::bytes_of(push));
            self.device.cmd_draw(cmd, 6, 1, 0, 0);
        }
    }
}

impl Drop for RawPass {
    fn drop(&mut self) {
        // SAFETY: the one-shot that used these has finished (one_shot waits); destroying a null
        // handle is a no-op, so a pass half made drops cleanly.
        unsafe {
            self.device.destroy_descriptor_pool(self.pool, None);
            self.device.destroy_pipeline(self.pipeline, None);
            self.device.destroy_pipeline_layout(self.layout, None);
            self.device
                .destroy_descriptor_set_layout(self.set_layout, None);
            for module in self.modules {
                self.device.destroy_shader_module(module, None);
            }
        }
    }
}
