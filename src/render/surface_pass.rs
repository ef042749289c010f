//! The surface pass: mesh buffers, the frame's uniforms and descriptor set, one graphics pipeline
//! per (method, sidedness) the scene uses, and the draw recording with dynamic rendering.

use std::collections::BTreeMap;
use std::sync::Arc;

use ash::vk;
use glam::Mat4;

use super::height_resources::HeightResources;
use crate::method::Method;
use crate::scene::{Scene, Vertex};
use crate::shaders;
use crate::vk::{
    graphics_pipeline, Buffer, Context, DescriptorLayout, DescriptorPool, GraphicsDesc, Pipeline,
    SpecConstants, VkError, VkResult,
};

/// Colour target format: sRGB, so the hardware encodes the shader's linear output.
pub const COLOR_FORMAT: vk::Format = vk::Format::R8G8B8A8_SRGB;
/// Depth target format.
pub const DEPTH_FORMAT: vk::Format = vk::Format::D32_SFLOAT;

/// The frame uniform block; mirrors `Frame` in `shaders/include/bindings.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
pub struct FrameUniforms {
    pub view_proj: [[f32; 4]; 4],
    pub eye: [f32; 4],
    pub light_dir: [f32; 4],
    pub light_color: [f32; 4],
    pub ambient: [f32; 4],
    pub height_info: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<FrameUniforms>() == 144);

/// Per-draw push constants; mirrors `Draw` in `shaders/include/bindings.glsl`.
#[repr(C)]
#[derive(Debug, Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
struct DrawConstants {
    model: [[f32; 4]; 4],
    base_color: [f32; 4],
    material: [f32; 4],
}
const _: () = assert!(std::mem::size_of::<DrawConstants>() == 96);

struct MeshBuffers {
    vertices: Buffer,
    indices: Buffer,
    index_count: u32,
    pipeline: (Method, bool),
    constants: DrawConstants,
}

/// Everything the surface pass needs for one scene.
pub struct SurfacePass {
    _layout: DescriptorLayout,
    _pool: DescriptorPool,
    set: vk::DescriptorSet,
    pipelines: BTreeMap<(String, bool), Pipeline>,
    meshes: Vec<MeshBuffers>,
}

fn pipeline_key(key: &(Method, bool)) -> (String, bool) {
    (key.0.id().to_owned(), key.1)
}

impl SurfacePass {
    /// Uploads the scene's meshes and builds the pipelines its materials use (plain materials
    /// share the first relief method's pipeline, with relief switched off by depth scale 0).
    pub fn new(ctx: &Arc<Context>, scene: &Scene, res: &HeightResources) -> VkResult<SurfacePass> {
        let stages = vk::ShaderStageFlags::VERTEX | vk::ShaderStageFlags::FRAGMENT;
        let layout = DescriptorLayout::new(ctx, &res.layout_bindings(), stages, "surface layout")?;
        let pool = DescriptorPool::new(ctx, 1, 2, "surface sets")?;
        let set = pool.allocate(&layout, &res.binds())?;
        let fallback = scene
            .materials
            .iter()
            .find_map(|m| m.relief.map(|r| r.method))
            .unwrap_or(Method::POM);
        let meshes = upload_meshes(ctx, scene, fallback)?;
        let mut pipelines = BTreeMap::new();
        for mesh in &meshes {
            let key = pipeline_key(&mesh.pipeline);
            if let std::collections::btree_map::Entry::Vacant(slot) = pipelines.entry(key) {
                slot.insert(create_pipeline(
                    ctx,
                    mesh.pipeline.0,
                    mesh.pipeline.1,
                    layout.raw(),
                )?);
            }
        }
        Ok(SurfacePass {
            _layout: layout,
            _pool: pool,
            set,
            pipelines,
            meshes,
        })
    }

    /// Keys (`method id`, double-sided) of the pipelines built.
    pub fn pipeline_keys(&self) -> Vec<(String, bool)> {
        self.pipelines.keys().cloned().collect()
    }

    /// Records every draw. Rendering must have begun with the targets' formats.
    pub fn record_draws(&self, device: &ash::Device, cmd: vk::CommandBuffer) {
        for mesh in &self.meshes {
            let Some(pipeline) = self.pipelines.get(&pipeline_key(&mesh.pipeline)) else {
                continue;
            };
            pipeline.bind(cmd, Some(self.set));
            pipeline.push(cmd, bytemuck::bytes_of(&mesh.constants));
            // SAFETY: `cmd` is recording inside dynamic rendering; buffers outlive the submission.
            unsafe {
                device.cmd_bind_vertex_buffers(cmd, 0, &[mesh.vertices.raw()], &[0]);
                device.cmd_bind_index_buffer(cmd, mesh.indices.raw(), 0, vk::IndexType::UINT32);
                device.cmd_draw_indexed(cmd, mesh.index_count, 1, 0, 0, 0);
            }
        }
    }
}

fn upload_meshes(
    ctx: &Arc<Context>,
    scene: &Scene,
    fallback: Method,
) -> VkResult<Vec<MeshBuffers>> {
    let mut out = Vec::new();
    for mesh in scene.meshes.iter().filter(|m| !m.indices.is_empty()) {
        let material = scene.materials.get(mesh.material).ok_or_else(|| {
            VkError::Invalid(format!(
                "mesh {:?} names material {}",
                mesh.name, mesh.material
            ))
        })?;
        let method = material.relief.map(|r| r.method).unwrap_or(fallback);
        let depth_scale = material.relief.map(|r| r.depth_scale).unwrap_or(0.0);
        let vertices = Buffer::with_data(
            ctx,
            bytemuck::cast_slice(&mesh.vertices),
            vk::BufferUsageFlags::VERTEX_BUFFER,
            &format!("{} vertices", mesh.name),
        )?;
        let indices = Buffer::with_data(
            ctx,
            bytemuck::cast_slice(&mesh.indices),
            vk::BufferUsageFlags::INDEX_BUFFER,
            &format!("{} indices", mesh.name),
        )?;
        let transform: Mat4 = mesh.transform;
        out.push(MeshBuffers {
            vertices,
            indices,
            index_count: mesh.indices.len() as u32,
            pipeline: (method, material.double_sided),
            constants: DrawConstants {
                model: transform.to_cols_array_2d(),
                base_color: material.base_color,
                material: [depth_scale, material.roughness, material.metallic, 0.0],
            },
        });
    }
    Ok(out)
}

fn create_pipeline(
    ctx: &Arc<Context>,
    method: Method,
    double_sided: bool,
    set_layout: vk::DescriptorSetLayout,
) -> VkResult<Pipeline> {
    let missing = |k: &str| VkError::Invalid(format!("no compiled shader {k}"));
    let vs = shaders::spirv("mesh.vert").ok_or_else(|| missing("mesh.vert"))?;
    let key = method.surface_shader_key();
    let fs = shaders::spirv(&key).ok_or_else(|| missing(&key))?;
    let budget = method.info().default_budget;
    let spec = SpecConstants::default()
        .u32(0, budget.max_steps)
        .u32(1, budget.refine_steps);
    let attributes = [
        (0, vk::Format::R32G32B32_SFLOAT, 0),
        (1, vk::Format::R32G32B32_SFLOAT, 12),
        (2, vk::Format::R32G32_SFLOAT, 24),
        (3, vk::Format::R32G32B32A32_SFLOAT, 32),
    ]
    .map(
        |(location, format, offset)| vk::VertexInputAttributeDescription {
            location,
            binding: 0,
            format,
            offset,
        },
    );
    let desc = GraphicsDesc {
        vertex: vs,
        fragment: fs,
        fragment_spec: &spec,
        vertex_stride: std::mem::size_of::<Vertex>() as u32,
        attributes: &attributes,
        color_format: COLOR_FORMAT,
        depth_format: DEPTH_FORMAT,
        cull: if double_sided {
            vk::CullModeFlags::NONE
        } else {
            vk::CullModeFlags::BACK
        },
        set_layouts: &[set_layout],
        push_bytes: std::mem::size_of::<DrawConstants>() as u32,
    };
    let sided = if double_sided {
        "double-sided"
    } else {
        "single-sided"
    };
    graphics_pipeline(ctx, &desc, &format!("surface {method} {sided}"))
}
