//! Shader modules, pipeline layouts, and compute and graphics pipelines (dynamic rendering), with
//! specialization constants for the numbers a shader variant is tuned by. Every pipeline goes
//! through the context's pipeline cache.

use std::sync::Arc;

use ash::vk;

use super::context::Context;
use super::counters::Created;
use super::deferred::Doomed;
use super::descriptors::{DescriptorLayout, DescriptorSet};
use super::error::{Named, VkError, VkResult};
use super::recording::Recording;

/// Specialization constants, in constant-id order as pushed.
#[derive(Debug, Clone, Default)]
pub struct SpecConstants {
    entries: Vec<vk::SpecializationMapEntry>,
    data: Vec<u8>,
}

impl SpecConstants {
    /// Sets constant `id` to a 32-bit unsigned value.
    pub fn u32(mut self, id: u32, value: u32) -> Self {
        self.push(id, &value.to_ne_bytes());
        self
    }

    /// Sets constant `id` to a 32-bit float.
    pub fn f32(mut self, id: u32, value: f32) -> Self {
        self.push(id, &value.to_ne_bytes());
        self
    }

    fn push(&mut self, id: u32, bytes: &[u8; 4]) {
        self.entries.push(vk::SpecializationMapEntry {
            constant_id: id,
            offset: self.data.len() as u32,
            size: 4,
        });
        self.data.extend_from_slice(bytes);
    }

    fn info(&self) -> vk::SpecializationInfo<'_> {
        vk::SpecializationInfo::default()
            .map_entries(&self.entries)
            .data(&self.data)
    }
}

/// A pipeline with its layout. Dropping it hands both to the context, which destroys them once
/// the GPU has finished every submission that may use them.
pub struct Pipeline {
    ctx: Arc<Context>,
    raw: vk::Pipeline,
    layout: vk::PipelineLayout,
    bind_point: vk::PipelineBindPoint,
    push_stages: vk::ShaderStageFlags,
    push_bytes: u32,
}

impl Pipeline {
    /// Binds the pipeline and, if given, descriptor set 0.
    pub fn bind(&self, rec: &Recording, set: Option<&DescriptorSet>) {
        // SAFETY: `rec` is recording on this device; the set's layout is the validation layer's
        // to check against the pipeline layout.
        unsafe {
            rec.device()
                .cmd_bind_pipeline(rec.raw(), self.bind_point, self.raw);
        }
        if let Some(set) = set {
            self.bind_set(rec, 0, set);
        }
    }

    /// Binds `set` at index `index` (the pipeline itself must be bound).
    pub fn bind_set(&self, rec: &Recording, index: u32, set: &DescriptorSet) {
        // SAFETY: `rec` is recording on this device; the set was made by a relief pool.
        unsafe {
            rec.device().cmd_bind_descriptor_sets(
                rec.raw(),
                self.bind_point,
                self.layout,
                index,
                &[set.raw()],
                &[],
            )
        };
    }

    /// Pushes `bytes` as push constants visible to every stage of the pipeline; more bytes than
    /// the layout's push range is an error, not undefined behaviour.
    pub fn push(&self, rec: &Recording, bytes: &[u8]) -> VkResult<()> {
        if bytes.len() > self.push_bytes as usize || bytes.len() % 4 != 0 {
            return Err(VkError::Invalid(format!(
                "{} push-constant bytes for a range of {}",
                bytes.len(),
                self.push_bytes
            )));
        }
        // SAFETY: `rec` is recording; the layout declares a push range at least this large for
        // these stages (checked above).
        unsafe {
            rec.device()
                .cmd_push_constants(rec.raw(), self.layout, self.push_stages, 0, bytes)
        };
        Ok(())
    }
}

impl Drop for Pipeline {
    fn drop(&mut self) {
        self.ctx
            .defer(Doomed::Pipeline(self.raw, self.layout, self.bind_point));
    }
}

/// A shader module that lives only while pipelines are being created from it.
struct Module<'a> {
    device: &'a ash::Device,
    raw: vk::ShaderModule,
}

impl<'a> Module<'a> {
    fn new(ctx: &'a Context, spirv: &[u32], name: &str) -> VkResult<Self> {
        let info = vk::ShaderModuleCreateInfo::default().code(spirv);
        // SAFETY: `spirv` is a complete module produced by glslang at build time.
        let raw = unsafe { ctx.device().create_shader_module(&info, None) }
            .named("vkCreateShaderModule")?;
        ctx.set_name(raw, name);
        Ok(Module {
            device: ctx.device(),
            raw,
        })
    }
}

impl Drop for Module<'_> {
    fn drop(&mut self) {
        // SAFETY: pipelines created from the module no longer need it.
        unsafe { self.device.destroy_shader_module(self.raw, None) };
    }
}

fn create_layout(
    ctx: &Context,
    set_layouts: &[&DescriptorLayout],
    push_bytes: u32,
    push_stages: vk::ShaderStageFlags,
    name: &str,
) -> VkResult<vk::PipelineLayout> {
    let set_layouts: Vec<_> = set_layouts.iter().map(|l| l.raw()).collect();
    // The range names exactly the stages the pipeline has, so pushes and layouts agree.
    let ranges = [vk::PushConstantRange {
        stage_flags: push_stages,
        offset: 0,
        size: push_bytes,
    }];
    let ranges: &[_] = if push_bytes > 0 { &ranges } else { &[] };
    let info = vk::PipelineLayoutCreateInfo::default()
        .set_layouts(&set_layouts)
        .push_constant_ranges(ranges);
    // SAFETY: valid device and create info.
    let layout = unsafe { ctx.device().create_pipeline_layout(&info, None) }
        .named("vkCreatePipelineLayout")?;
    ctx.set_name(layout, &format!("{name} layout"));
    Ok(layout)
}

/// Creates a compute pipeline from one SPIR-V module with entry point `main`.
pub fn compute_pipeline(
    ctx: &Arc<Context>,
    spirv: &[u32],
    set_layouts: &[&DescriptorLayout],
    push_bytes: u32,
    spec: &SpecConstants,
    name: &str,
) -> VkResult<Pipeline> {
    let module = Module::new(ctx, spirv, name)?;
    let stages = vk::ShaderStageFlags::COMPUTE;
    let layout = create_layout(ctx, set_layouts, push_bytes, stages, name)?;
    let spec_info = spec.info();
    let stage = vk::PipelineShaderStageCreateInfo::default()
        .stage(vk::ShaderStageFlags::COMPUTE)
        .module(module.raw)
        .name(c"main")
        .specialization_info(&spec_info);
    let info = vk::ComputePipelineCreateInfo::default()
        .stage(stage)
        .layout(layout);
    // SAFETY: module, layout and specialization data outlive the call; the cache is held.
    let created = ctx.with_pipeline_cache(|cache| unsafe {
        ctx.device().create_compute_pipelines(cache, &[info], None)
    });
    finish(
        ctx,
        created,
        (layout, stages, push_bytes),
        vk::PipelineBindPoint::COMPUTE,
        name,
    )
}

fn finish(
    ctx: &Arc<Context>,
    created: Result<Vec<vk::Pipeline>, (Vec<vk::Pipeline>, vk::Result)>,
    (layout, push_stages, push_bytes): (vk::PipelineLayout, vk::ShaderStageFlags, u32),
    bind_point: vk::PipelineBindPoint,
    name: &str,
) -> VkResult<Pipeline> {
    match created {
        Ok(list) => {
            ctx.set_name(list[0], name);
            ctx.count(if bind_point == vk::PipelineBindPoint::GRAPHICS {
                Created::GraphicsPipeline
            } else {
                Created::ComputePipeline
            });
            Ok(Pipeline {
                ctx: ctx.clone(),
                raw: list[0],
                layout,
                bind_point,
                push_stages,
                push_bytes,
            })
        }
        Err((_, result)) => {
            // SAFETY: the layout is unused since no pipeline was created.
            unsafe { ctx.device().destroy_pipeline_layout(layout, None) };
            Err(result).named("vkCreate*Pipelines")
        }
    }
}

/// Everything a graphics pipeline of relief varies in.
pub struct GraphicsDesc<'a> {
    /// The vertex shader's SPIR-V.
    pub vertex: &'a [u32],
    /// The fragment shader's SPIR-V.
    pub fragment: &'a [u32],
    /// Specialization constants of the fragment shader.
    pub fragment_spec: &'a SpecConstants,
    /// 0 for a pass whose vertex shader makes its own vertices.
    pub vertex_stride: u32,
    /// Vertex attributes read from binding 0.
    pub attributes: &'a [vk::VertexInputAttributeDescription],
    /// The first colour attachment's format.
    pub color_format: vk::Format,
    /// Formats of the colour attachments after the first (a G-buffer's channels), never
    /// blended.
    pub extra_colors: &'a [vk::Format],
    /// Whether the shader's writes to `extra_colors` land (else their write masks are empty).
    pub writes_extra: bool,
    /// `UNDEFINED` for a pass without depth.
    pub depth_format: vk::Format,
    /// Which faces are culled.
    pub cull: vk::CullModeFlags,
    /// The descriptor set layouts, set 0 first.
    pub set_layouts: &'a [&'a DescriptorLayout],
    /// Bytes of push constants, seen by both stages.
    pub push_bytes: u32,
    /// Blend over the target with the fragment's alpha (and leave depth unwritten).
    pub blend: bool,
    /// Samples per pixel of the attachments it draws into (1 for none).
    pub samples: u32,
}

/// Creates a triangle-list graphics pipeline for dynamic rendering with one colour and one depth
/// attachment; viewport and scissor are dynamic.
pub fn graphics_pipeline(
    ctx: &Arc<Context>,
    desc: &GraphicsDesc,
    name: &str,
) -> VkResult<Pipeline> {
    let vs = Module::new(ctx, desc.vertex, &format!("{name} vs"))?;
    let fs = Module::new(ctx, desc.fragment, &format!("{name} fs"))?;
    let push_stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
    let layout = create_layout(ctx, desc.set_layouts, desc.push_bytes, push_stages, name)?;
    let spec = desc.fragment_spec.info();
    let stages = [
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::VERTEX)
            .module(vs.raw)
            .name(c"main"),
        vk::PipelineShaderStageCreateInfo::default()
            .stage(vk::ShaderStageFlags::FRAGMENT)
            .module(fs.raw)
            .name(c"main")
            .specialization_info(&spec),
    ];
    let bindings = vertex_bindings(desc.vertex_stride);
    let vertex_input = vk::PipelineVertexInputStateCreateInfo::default()
        .vertex_binding_descriptions(&bindings)
        .vertex_attribute_descriptions(desc.attributes);
    let assembly = vk::PipelineInputAssemblyStateCreateInfo::default()
        .topology(vk::PrimitiveTopology::TRIANGLE_LIST);
    let viewport = vk::PipelineViewportStateCreateInfo::default()
        .viewport_count(1)
        .scissor_count(1);
    let raster = raster_state(desc.cull);
    let multisample = vk::PipelineMultisampleStateCreateInfo::default()
        .rasterization_samples(vk::SampleCountFlags::from_raw(desc.samples.max(1)));
    let depth = depth_state(desc);
    let blend_attachments = blend_attachments(desc);
    let blend = vk::PipelineColorBlendStateCreateInfo::default().attachments(&blend_attachments);
    let dynamic_states = [vk::DynamicState::VIEWPORT, vk::DynamicState::SCISSOR];
    let dynamic = vk::PipelineDynamicStateCreateInfo::default().dynamic_states(&dynamic_states);
    let mut color_formats = vec![desc.color_format];
    color_formats.extend_from_slice(desc.extra_colors);
    let mut rendering = vk::PipelineRenderingCreateInfo::default()
        .color_attachment_formats(&color_formats)
        .depth_attachment_format(desc.depth_format);
    let info = vk::GraphicsPipelineCreateInfo::default()
        .stages(&stages)
        .vertex_input_state(&vertex_input)
        .input_assembly_state(&assembly)
        .viewport_state(&viewport)
        .rasterization_state(&raster)
        .multisample_state(&multisample)
        .depth_stencil_state(&depth)
        .color_blend_state(&blend)
        .dynamic_state(&dynamic)
        .layout(layout)
        .push_next(&mut rendering);
    // SAFETY: every struct referenced by `info` lives until the call returns; the cache is held.
    let created = ctx.with_pipeline_cache(|cache| unsafe {
        ctx.device().create_graphics_pipelines(cache, &[info], None)
    });
    finish(
        ctx,
        created,
        (layout, push_stages, desc.push_bytes),
        vk::PipelineBindPoint::GRAPHICS,
        name,
    )
}

/// The vertex buffer binding 0 of `stride` bytes per vertex; none for a stride of 0, whose
/// vertex shader makes its own vertices (full-screen passes).
fn vertex_bindings(stride: u32) -> Vec<vk::VertexInputBindingDescription> {
    if stride == 0 {
        return Vec::new();
    }
    vec![vk::VertexInputBindingDescription {
        binding: 0,
        stride,
        input_rate: vk::VertexInputRate::VERTEX,
    }]
}

/// Filled triangles with `cull` faces culled.
fn raster_state(cull: vk::CullModeFlags) -> vk::PipelineRasterizationStateCreateInfo<'static> {
    vk::PipelineRasterizationStateCreateInfo::default()
        .polygon_mode(vk::PolygonMode::FILL)
        .cull_mode(cull)
        // Counter-clockwise as in glTF: the projection's y flip and Vulkan's y-down framebuffer
        // cancel, so winding seen on screen is unchanged.
        .front_face(vk::FrontFace::COUNTER_CLOCKWISE)
        .line_width(1.0)
}

/// The depth test where `desc` has a depth attachment, written unless it blends.
fn depth_state(desc: &GraphicsDesc) -> vk::PipelineDepthStencilStateCreateInfo<'static> {
    let has_depth = desc.depth_format != vk::Format::UNDEFINED;
    vk::PipelineDepthStencilStateCreateInfo::default()
        .depth_test_enable(has_depth)
        .depth_write_enable(has_depth && !desc.blend)
        .depth_compare_op(vk::CompareOp::LESS_OR_EQUAL)
}

/// The first colour attachment's blend (alpha over the target when `desc.blend`), then the
/// extra attachments, never blended and written only when `desc.writes_extra`.
fn blend_attachments(desc: &GraphicsDesc) -> Vec<vk::PipelineColorBlendAttachmentState> {
    let mut attachments = vec![vk::PipelineColorBlendAttachmentState::default()
        .blend_enable(desc.blend)
        .src_color_blend_factor(vk::BlendFactor::SRC_ALPHA)
        .dst_color_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
        .color_blend_op(vk::BlendOp::ADD)
        .src_alpha_blend_factor(vk::BlendFactor::ONE)
        .dst_alpha_blend_factor(vk::BlendFactor::ONE_MINUS_SRC_ALPHA)
        .alpha_blend_op(vk::BlendOp::ADD)
        .color_write_mask(vk::ColorComponentFlags::RGBA)];
    let extra_mask = if desc.writes_extra {
        vk::ColorComponentFlags::RGBA
    } else {
        vk::ColorComponentFlags::empty()
    };
    attachments.extend(
        desc.extra_colors
            .iter()
            .map(|_| vk::PipelineColorBlendAttachmentState::default().color_write_mask(extra_mask)),
    );
    attachments
}
