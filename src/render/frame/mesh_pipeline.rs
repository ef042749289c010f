//! The pipelines that draw meshes: the surface pass's (one per plan pipeline key) and the shadow
//! pass's casters (the same key traced from a light), built from the same vertex layout, set
//! layouts and specialization constants.

use std::sync::Arc;

use ash::vk;

use super::occluders::BOUNDS_FORMAT;
use crate::render::kit::draw_push::DrawPush;
use crate::render::kit::formats::DEPTH_FORMAT;
use crate::render::kit::formats::HDR_FORMAT;
use crate::render::kit::hard_shadow::hard_shadow_texels;
use crate::render::kit::shadow_mode_value::shadow_mode_value;
use crate::render::plan::frame_plan::PipelineKey;
use crate::render::shader_interface::{
    LOCATION_COLOR, LOCATION_CORNER_NORMAL, LOCATION_CORNER_UV, LOCATION_NORMAL, LOCATION_POSITION,
    LOCATION_PRISM, LOCATION_TANGENT, LOCATION_TOP, LOCATION_UV0, LOCATION_UV1, SHADOW_MODE_NONE,
    SPEC_BUDGET_EXTENT_LIMIT, SPEC_BUDGET_LEAF_EXACT, SPEC_BUDGET_MAX_STEPS,
    SPEC_BUDGET_REFINE_STEPS, SPEC_COUNT_FETCHES, SPEC_COUNT_WORK, SPEC_DEFERRED,
    SPEC_HARD_SHADOW_TEXELS, SPEC_LOD_AVERAGE_BELOW, SPEC_LOD_BIAS, SPEC_LOD_FACTOR,
    SPEC_LOD_FADE_END, SPEC_LOD_FADE_START, SPEC_OCCLUDER_TAPS, SPEC_SHADOW_FILTER,
    SPEC_SHADOW_MODE, SPEC_SHADOW_REACH, SPEC_SHADOW_STEPS, SPEC_WRITE_DEPTH,
};
use crate::render::shadows::shadow_atlas::SHADOW_FORMAT;
use crate::scene::{Lod, Vertex};
use crate::shaders;
use crate::shells::ShellVertex;
use crate::vk::{
    graphics_pipeline, Context, DescriptorLayout, GraphicsDesc, Pipeline, SpecConstants, VkError,
    VkResult,
};

/// The LOD variants' constants (`shaders/include/lod.glsl`).
fn lod_spec_constants(spec: SpecConstants, lod: &Lod) -> SpecConstants {
    spec.f32(SPEC_LOD_FACTOR, lod.factor)
        .f32(SPEC_LOD_BIAS, lod.bias)
        .f32(SPEC_LOD_FADE_START, lod.fade_start)
        .f32(SPEC_LOD_FADE_END, lod.fade_end)
        .u32(SPEC_LOD_AVERAGE_BELOW, lod.average_below)
}

/// The shaders and target of a mesh pipeline: the surface pass's, a shadow caster's, or an
/// occluder's.
pub(super) struct MeshStages {
    vertex: &'static str,
    fragment: String,
    color_format: vk::Format,
    name: String,
    /// `SPEC_SHADOW_FILTER`: the most capable filter a lookup may need, 0 for none.
    shadow_filter: u32,
    /// Samples per pixel of its targets.
    samples: u32,
    /// `SPEC_OCCLUDER_TAPS`: the occluder bounds a relief fragment reads, 0 for none.
    occluder_taps: u32,
    /// `SPEC_COUNT_WORK`: relief fragments count their traces and steps.
    count_work: bool,
    /// Colour attachments after the first (the G-buffer's), which the surface pass writes.
    extra_colors: &'static [vk::Format],
    /// `SPEC_DEFERRED`: the fragment writes its shading inputs and the lighting pass lights it.
    deferred: bool,
    /// The lighting pass traces the shadows, the receiver's own relief included: the height
    /// field's self-shadow walk is compiled out (`SPEC_SHADOW_MODE` 0).
    traced_shadows: bool,
}

impl MeshStages {
    /// The surface pass's, looking shadow maps up with filters up to `shadow_filter`, into
    /// targets of `samples` samples per pixel, relief reading `occluder_taps` occluder bounds
    /// before it traces.
    pub(super) fn surface(
        key: &PipelineKey,
        shadow_filter: u32,
        samples: u32,
        (occluder_taps, count_work): (u32, bool),
        extra_colors: &'static [vk::Format],
    ) -> MeshStages {
        MeshStages {
            vertex: if key.shells {
                "shell.vert"
            } else {
                "mesh.vert"
            },
            fragment: key.shader(),
            color_format: HDR_FORMAT,
            name: format!("surface {}", describe(key)),
            shadow_filter,
            samples,
            occluder_taps,
            count_work,
            extra_colors,
            deferred: false,
            traced_shadows: false,
        }
    }

    /// The same, lit by the deferred frame's lighting pass when `deferred`, which traces the
    /// shadows when `traced_shadows`.
    pub(super) fn lit_deferred(self, deferred: bool, traced_shadows: bool) -> MeshStages {
        MeshStages {
            deferred,
            traced_shadows: deferred && traced_shadows,
            ..self
        }
    }

    /// The occluder pass's: the farthest depth the draw's surface can reach, written as the
    /// colour the surface pass samples (`occluders.frag`).
    pub(super) fn occluder(key: &PipelineKey) -> MeshStages {
        let fragment = match key.method {
            Some(_) => "occluders.frag",
            None => "occluders.frag:plain",
        };
        MeshStages {
            vertex: "mesh.vert",
            fragment: fragment.to_owned(),
            color_format: BOUNDS_FORMAT,
            name: format!("occluder {}", describe(key)),
            shadow_filter: 0,
            samples: 1,
            occluder_taps: 0,
            count_work: false,
            extra_colors: &[],
            deferred: false,
            traced_shadows: false,
        }
    }

    /// From the light, depth written as the colour the surface pass samples: relief traced with
    /// the method's own variant (without level of detail, so a map shows the full relief however
    /// far the camera is).
    pub(super) fn caster(key: &PipelineKey) -> MeshStages {
        let fragment = match key.method {
            Some(m) if key.curved => format!("shadow_caster.frag:{}:curved", m.id()),
            Some(m) if key.shells => format!("shadow_caster.frag:{}:shells", m.id()),
            Some(m) => format!("shadow_caster.frag:{}", m.id()),
            None => "shadow_caster.frag:plain".to_owned(),
        };
        MeshStages {
            vertex: if key.shells {
                "shell.vert:shadow"
            } else {
                "mesh.vert:shadow"
            },
            name: format!("shadow caster {fragment}"),
            fragment,
            color_format: SHADOW_FORMAT,
            shadow_filter: 0,
            samples: 1,
            occluder_taps: 0,
            count_work: false,
            extra_colors: &[],
            deferred: false,
            traced_shadows: false,
        }
    }
}

pub(super) fn create_pipeline(
    ctx: &Arc<Context>,
    key: &PipelineKey,
    stages: &MeshStages,
    set_layouts: &[&DescriptorLayout],
) -> VkResult<Pipeline> {
    let missing = |k: &str| VkError::Invalid(format!("no compiled shader {k}"));
    let vs = shaders::spirv(stages.vertex).ok_or_else(|| missing(stages.vertex))?;
    let fs = shaders::spirv(&stages.fragment).ok_or_else(|| missing(&stages.fragment))?;
    let mut spec = SpecConstants::default()
        .u32(
            SPEC_SHADOW_MODE,
            if stages.traced_shadows {
                SHADOW_MODE_NONE
            } else {
                shadow_mode_value(key.shadows.mode)
            },
        )
        .u32(SPEC_SHADOW_STEPS, key.shadows.resolved_steps())
        .f32(SPEC_SHADOW_REACH, key.shadows.horizon_reach)
        .u32(SPEC_SHADOW_FILTER, stages.shadow_filter)
        .u32(SPEC_OCCLUDER_TAPS, stages.occluder_taps)
        .u32(SPEC_WRITE_DEPTH, u32::from(key.write_depth))
        .u32(SPEC_COUNT_WORK, u32::from(stages.count_work))
        .u32(SPEC_COUNT_FETCHES, u32::from(stages.count_work))
        .u32(SPEC_DEFERRED, u32::from(stages.deferred));
    if let Some(method) = key.method {
        let budget = method.info().default_budget;
        spec = spec
            .f32(SPEC_HARD_SHADOW_TEXELS, hard_shadow_texels(method))
            .u32(
                SPEC_BUDGET_MAX_STEPS,
                key.max_steps.unwrap_or(budget.max_steps),
            )
            .u32(SPEC_BUDGET_REFINE_STEPS, budget.refine_steps)
            .u32(SPEC_BUDGET_LEAF_EXACT, budget.leaf.spec_value())
            // A material's own budget is a fixed cap.
            .u32(
                SPEC_BUDGET_EXTENT_LIMIT,
                key.max_steps.map_or(budget.extent_limit, |_| 0),
            );
    }
    if let Some(lod) = key.lod {
        spec = lod_spec_constants(spec, &lod);
    }
    let (attributes, vertex_stride) = vertex_layout(key.shells);
    let desc = GraphicsDesc {
        vertex: vs,
        fragment: fs,
        fragment_spec: &spec,
        vertex_stride,
        attributes: &attributes,
        color_format: stages.color_format,
        extra_colors: stages.extra_colors,
        // Blended surfaces leave the G-buffer to the opaque ones under them.
        writes_extra: !key.blend,
        depth_format: DEPTH_FORMAT,
        // A prism is closed: a ray enters it through a face that faces the ray, double-sided
        // material or not, and a face it leaves by must not start a march.
        cull: if key.double_sided && !key.shells {
            vk::CullModeFlags::NONE
        } else {
            vk::CullModeFlags::BACK
        },
        set_layouts,
        push_bytes: std::mem::size_of::<DrawPush>() as u32,
        blend: key.blend && stages.color_format == HDR_FORMAT,
        samples: stages.samples,
    };
    graphics_pipeline(ctx, &desc, &stages.name)
}

/// The vertex attributes and stride of a mesh's [`Vertex`], or of a shell's [`ShellVertex`]:
/// the same six first, then the prism's coordinates at the corner and the prism's three vec4
/// arrays. Offsets come from the Rust structs, locations from `shader_interface`.
fn vertex_layout(shells: bool) -> (Vec<vk::VertexInputAttributeDescription>, u32) {
    use std::mem::offset_of;
    const RGB: vk::Format = vk::Format::R32G32B32_SFLOAT;
    const RG: vk::Format = vk::Format::R32G32_SFLOAT;
    const RGBA: vk::Format = vk::Format::R32G32B32A32_SFLOAT;
    let attribute =
        |location: u32, format: vk::Format, offset: usize| vk::VertexInputAttributeDescription {
            location,
            binding: 0,
            format,
            offset: offset as u32,
        };
    // A mesh vertex's six attributes, which a shell vertex starts with too.
    macro_rules! mesh_attributes {
        ($vertex:ty) => {
            vec![
                attribute(LOCATION_POSITION, RGB, offset_of!($vertex, position)),
                attribute(LOCATION_NORMAL, RGB, offset_of!($vertex, normal)),
                attribute(LOCATION_UV0, RG, offset_of!($vertex, uv)),
                attribute(LOCATION_UV1, RG, offset_of!($vertex, uv1)),
                attribute(LOCATION_TANGENT, RGBA, offset_of!($vertex, tangent)),
                attribute(LOCATION_COLOR, RGBA, offset_of!($vertex, color)),
            ]
        };
    }
    let mut attributes = if shells {
        let mut shell = mesh_attributes!(ShellVertex);
        shell.push(attribute(
            LOCATION_PRISM,
            RGBA,
            offset_of!(ShellVertex, prism),
        ));
        shell
    } else {
        mesh_attributes!(Vertex)
    };
    let stride = if shells {
        let arrays = [
            (LOCATION_TOP, offset_of!(ShellVertex, top)),
            (LOCATION_CORNER_NORMAL, offset_of!(ShellVertex, normals)),
            (LOCATION_CORNER_UV, offset_of!(ShellVertex, uvs)),
        ];
        for (location, offset) in arrays {
            attributes
                .extend((0..3).map(|k| attribute(location + k, RGBA, offset + 16 * k as usize)));
        }
        std::mem::size_of::<ShellVertex>()
    } else {
        std::mem::size_of::<Vertex>()
    };
    (attributes, stride as u32)
}

/// A pipeline's name for debug labels and `--explain`.
pub fn describe(key: &PipelineKey) -> String {
    let mut name = key.shader();
    if let Some(steps) = key.max_steps {
        name.push_str(&format!(" budget {steps}"));
    }
    for (on, what) in [(key.double_sided, "double-sided"), (key.blend, "blend")] {
        if on {
            name.push(' ');
            name.push_str(what);
        }
    }
    if key.shadows.mode.is_some() {
        name.push_str(&format!(" shadows {}", key.shadows.mode));
    }
    if !key.write_depth {
        name.push_str(" polygon depth");
    }
    name
}
