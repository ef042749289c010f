//! What the Rust side and the shaders must agree on — descriptor bindings, specialization-constant
//! ids, array sizes, mode values, texture slots, and the layouts of push constants, uniform blocks
//! and storage records — written once, here. build.rs compiles this module as one of its own and
//! writes every table below and every layout into the GLSL header "interface.glsl", which the
//! shaders include; so the module uses nothing outside itself but `bytemuck`.

/// Declares each constant as a `u32` and lists it by name in `$table`, for build.rs's header.
macro_rules! glsl_table {
    ($(#[$table_doc:meta])* $table:ident { $($(#[$doc:meta])* $name:ident = $value:expr;)* }) => {
        $($(#[$doc])* pub const $name: u32 = $value;)*
        $(#[$table_doc])*
        // Read by build.rs; the library names the constants themselves.
        #[allow(dead_code)]
        pub const $table: &[(&str, u32)] = &[$((stringify!($name), $name)),*];
    };
}

#[macro_use]
mod shader_layout;
mod push_constants;
mod storage_records;
mod uniform_blocks;
pub use push_constants::*;
pub use shader_layout::{LayoutForm, LayoutRules, ShaderField, ShaderLayout};
pub use storage_records::*;
pub use uniform_blocks::*;

glsl_table! {
    /// Set 0 of the passes that trace (surface and trace, `shaders/include/bindings.glsl`,
    /// `lod.glsl`), written as `#define`s so they can stand in layout qualifiers.
    FRAME_BINDINGS {
        /// The frame's uniform block (camera, lights).
        BINDING_FRAME = 0;
        /// The height field and its max pyramid, nearest texel, nearest mip.
        BINDING_HEIGHT_POINT = 1;
        /// The same image, bilinear.
        BINDING_HEIGHT_LINEAR = 2;
        /// The method's precomputed map, for the methods whose table row names one.
        BINDING_METHOD_MAP = 3;
        /// The averaged height pyramid of level-of-detail variants.
        BINDING_HEIGHT_MEAN = 4;
        /// The scene's shadow maps, one depth atlas (`shaders/include/scene_shadows.glsl`).
        BINDING_SHADOW_ATLAS = 5;
        /// Drawing passes: the environment's cosine-weighted radiance, equirectangular
        /// (`shaders/include/environment_light.glsl`).
        BINDING_ENV_IRRADIANCE = 6;
        /// Drawing passes: the environment prefiltered for GGX lobes, one roughness per mip.
        BINDING_ENV_SPECULAR = 7;
        /// Drawing passes: the GGX lobe's albedo as (scale, bias) on F0, by view cosine and
        /// roughness.
        BINDING_ENV_BRDF = 8;
    }
}

glsl_table! {
    /// Set 0 of the environment kernels (`environment_irradiance.comp`,
    /// `environment_prefilter.comp`, `brdf_table.comp`), as `#define`s.
    ENVIRONMENT_BINDINGS {
        /// The environment's radiance, equirectangular, with its mip chain.
        BINDING_ENV_SOURCE = 0;
        /// The level written.
        BINDING_ENV_OUT = 1;
    }
}

glsl_table! {
    /// Set 0 of the map searches (`cone_map.comp`,
    /// `quadric_map.comp`, `relaxed_cone_*.comp`), as `#define`s.
    SEARCH_BINDINGS {
        /// Every pyramid level back to back, level 0 first.
        BINDING_SEARCH_PYRAMID = 0;
        /// The map being built, per texel of level 0.
        BINDING_SEARCH_MAP = 1;
    }
}

glsl_table! {
    /// Set 0 of the trace pass after the frame bindings (`trace.comp`), as `#define`s.
    TRACE_BINDINGS {
        /// Per ray: origin, direction and hit (eight floats).
        BINDING_TRACE_HITS = 4;
        /// Per ray: steps used, and 1 if the method hit its cap.
        BINDING_TRACE_STEPS = 5;
        /// Per ray: the light's visible fraction at the hit.
        BINDING_TRACE_VISIBLE = 6;
        /// Per ray, when the pass counts fetches: the method's texel fetches and the shadow
        /// walk's after it.
        BINDING_TRACE_FETCHES = 7;
    }
}

glsl_table! {
    /// Set 0 of the ray-query occlusion pass after the frame bindings (`traced_occlusion.comp`),
    /// as `#define`s.
    OCCLUSION_BINDINGS {
        /// The scene's top-level acceleration structure.
        BINDING_OCCLUSION_SCENE = 4;
        /// Per relief prism: its frame (`PrismRecord`).
        BINDING_OCCLUSION_PRISMS = 5;
        /// Per ray: origin and its first t, direction and its last t.
        BINDING_OCCLUSION_RAYS = 6;
        /// Per ray: blocked or not, prisms tested, height-field steps, walks capped.
        BINDING_OCCLUSION_RESULTS = 7;
    }
}

glsl_table! {
    /// Set 0 of the pyramid reductions over images (`pyramid.comp`, `mean_pyramid.comp`), as
    /// `#define`s.
    PYRAMID_BINDINGS {
        /// The finer level, read.
        BINDING_PYRAMID_FINE = 0;
        /// The level written.
        BINDING_PYRAMID_COARSE = 1;
    }
}

glsl_table! {
    /// Set 0 of the AO map kernels (`shaders/include/ao.glsl`, `ao_sweep.comp`), as `#define`s.
    AO_BINDINGS {
        /// The height image (and, for the horizon kernel, its max pyramid in the mips).
        BINDING_AO_HEIGHTS = 0;
        /// The AO map, written as r32f.
        BINDING_AO_MAP = 1;
        /// The exact sweep: per line, its hull ring and walk state.
        BINDING_AO_HULLS = 2;
        /// The exact sweep: per texel, the weighted occlusion summed so far.
        BINDING_AO_ACCUM = 3;
        /// The exact sweep: level 0 of the heights, unpacked.
        BINDING_AO_FIELD = 4;
        /// The exact sweep: each azimuth's grid-line crossings.
        BINDING_AO_CROSSINGS = 5;
    }
}

glsl_table! {
    /// Set 0 of the terrain kernels (`brush.comp`, `blended_pyramid.comp`), as `#define`s.
    TERRAIN_BINDINGS {
        /// `brush.comp`: level 0 of the elevation, read and written.
        BINDING_BRUSH_HEIGHTS = 0;
        /// `blended_pyramid.comp`: the layers' max pyramids, one layer per channel.
        BINDING_BLEND_LAYER_HEIGHTS = 0;
        /// `blended_pyramid.comp`: the weights' max pyramids.
        BINDING_BLEND_LAYER_WEIGHTS = 1;
        /// `blended_pyramid.comp`: the level of the blended pyramid written.
        BINDING_BLEND_OUT = 2;
        /// `blended_pyramid.comp`: the max pyramid of 1 - min(sum of weights, 1).
        BINDING_BLEND_SLACK = 3;
    }
}

glsl_table! {
    /// Set 1 of the drawing passes (surface and cells): one material's textures and parameters
    /// (`shaders/include/draw.glsl`), as `#define`s.
    MATERIAL_BINDINGS {
        /// Base colour texture (sRGB).
        BINDING_MATERIAL_BASE_COLOR = 0;
        /// Metallic (b) and roughness (g) texture.
        BINDING_MATERIAL_METALLIC_ROUGHNESS = 1;
        /// Tangent-space normal map.
        BINDING_MATERIAL_NORMAL = 2;
        /// Ambient occlusion texture (r).
        BINDING_MATERIAL_OCCLUSION = 3;
        /// Emissive texture (sRGB).
        BINDING_MATERIAL_EMISSIVE = 4;
        /// The material's uniform block (factors, texture flags, relief settings).
        BINDING_MATERIAL_PARAMS = 5;
        /// The relief's texture-space AO map; bit 6 of the texture flags says it is bound.
        BINDING_MATERIAL_RELIEF_AO = 6;
    }
}

glsl_table! {
    /// Set 2 of a layered material's surface variant (`shaders/include/terrain_layers.glsl`), as
    /// `#define`s.
    LAYER_BINDINGS {
        /// The layers' albedo (rgb) and height (a), one array layer per terrain layer.
        BINDING_LAYER_ALBEDO_HEIGHT = 0;
        /// The layers' normals (rgb) and roughness (a).
        BINDING_LAYER_NORMAL_ROUGHNESS = 1;
        /// The splat map: one weight per layer and channel.
        BINDING_LAYER_WEIGHTS = 2;
        /// The layers' uniform block (tiling, blend mode and its sharpness).
        BINDING_LAYER_PARAMS = 3;
    }
}

glsl_table! {
    /// Set 3 of the relief surface variants: the occluder pass's bounds
    /// (`shaders/include/occluders.glsl`), as `#define`s.
    OCCLUDER_BINDINGS {
        /// The set's index: after the layers' set 2 (an empty set 2 stands in for materials
        /// without layers).
        SET_OCCLUDERS = 3;
        /// Per pixel, the farthest depth the nearest opaque surface can reach.
        BINDING_OCCLUDER_BOUNDS = 0;
        /// Per pixel of the scene's targets, two counters: relief fragments traced and the
        /// steps they took (written only where `SPEC_COUNT_WORK` is 1).
        BINDING_WORK_COUNTS = 1;
    }
}

glsl_table! {
    /// Set 1 of the deferred frame's lighting pass (`shaders/passes/lighting.comp`): the
    /// radiance it adds to and the surface pass's attachments it reads, as storage images.
    LIGHTING_BINDINGS {
        /// The radiance (emission written by the surface pass; the light is added).
        BINDING_LIGHTING_RADIANCE = 0;
        /// The G-buffer's albedo and ambient occlusion.
        BINDING_LIGHTING_MATERIAL = 1;
        /// The G-buffer's motion and shadow share (the share written here).
        BINDING_LIGHTING_MOTION = 2;
        /// The shaded point and its depth below the relief's top plane.
        BINDING_LIGHTING_POINT = 3;
        /// Shading normal, polygon plane and normal, roughness and metallic.
        BINDING_LIGHTING_FRAME = 4;
        /// The height field's own shadow toward the first lights.
        BINDING_LIGHTING_SELF_SHADOW = 5;
    }
}

glsl_table! {
    /// A cell complex's set (`shaders/include/cells_march.glsl`; set 2 of `cells.frag`, set 0 of
    /// `cells_trace.comp`), as `#define`s.
    CELLS_BINDINGS {
        /// Per cell of the grid: its colour and, for a grey cell, its index.
        BINDING_CELLS_CELLS = 0;
        /// Per grey cell: its case, projection and map offset.
        BINDING_CELLS_GREY = 1;
        /// The grey cells' distance maps, back to back.
        BINDING_CELLS_MAPS = 2;
        /// `cells.frag`: the complex's uniform block (its grid, transform and march settings).
        BINDING_CELLS_PARAMS = 3;
        /// `cells.frag`: per map texel, the mesh triangle its line meets.
        BINDING_CELLS_SURFACE_TRIANGLES = 4;
        /// `cells.frag`: the mesh triangles' corners, with the attributes shaded from.
        BINDING_CELLS_CORNERS = 5;
        /// `cells_trace.comp`: the rays to march.
        BINDING_CELLS_RAYS = 3;
        /// `cells_trace.comp`: per ray, the hit distance and the samples taken.
        BINDING_CELLS_HITS = 4;
    }
}

glsl_table! {
    /// Mode values the map and AO kernels branch on per dispatch (`params.mode`), as `#define`s.
    MODES {
        /// `cone_map.comp`, `quadric_map.comp`: one level of the max pyramid from the level below.
        MODE_REDUCE = 0;
        /// `cone_map.comp`, `quadric_map.comp`: the per-texel search of rows from `row0`.
        MODE_SEARCH = 1;
        /// `ao_sweep.comp`: one chunk of one azimuth's line walks.
        MODE_SWEEP = 0;
        /// `ao_sweep.comp`: the sums turned into the map.
        MODE_RESOLVE = 1;
        /// `ao_sweep.comp`: level 0 of the heights unpacked for the walks.
        MODE_UNPACK = 2;
    }
}

glsl_table! {
    /// Mode values the terrain kernels branch on per dispatch, as `#define`s.
    TERRAIN_MODES {
        /// `brush.comp`'s kind: raise, lower, flatten, crater (`BrushKind`).
        BRUSH_RAISE = 0;
        BRUSH_LOWER = 1;
        BRUSH_FLATTEN = 2;
        BRUSH_CRATER = 3;
        /// `blended_pyramid.comp`'s blend mode (`BlendMode`).
        BLEND_ALPHA = 0;
        BLEND_HEIGHT = 1;
        BLEND_HEIGHT_INTERSECT = 2;
    }
}

glsl_table! {
    /// How a scene shadow map is filtered (`ShadowFilter`; `shaders/include/scene_shadows.glsl`),
    /// as `#define`s.
    SHADOW_FILTERS {
        /// One tap: the nearest texel, exact to the map's resolution.
        SHADOW_FILTER_HARD = 1;
        /// Percentage-closer filtering over a fixed footprint.
        SHADOW_FILTER_PCF = 2;
        /// Percentage-closer soft shadows: blocker search, penumbra from the light's size, filter.
        SHADOW_FILTER_PCSS = 3;
    }
}

glsl_table! {
    /// Vertex input locations of the mesh and shell passes (`mesh.vert`, `shell.vert`,
    /// `cells.vert`): a mesh `Vertex`'s six attributes, then a shell
    /// vertex's prism (`ShellVertex`), its vec4 arrays taking one location per element.
    VERTEX_LOCATIONS {
        LOCATION_POSITION = 0;
        LOCATION_NORMAL = 1;
        LOCATION_UV0 = 2;
        LOCATION_UV1 = 3;
        LOCATION_TANGENT = 4;
        LOCATION_COLOR = 5;
        LOCATION_PRISM = 6;
        /// Three locations.
        LOCATION_TOP = 7;
        /// Three locations.
        LOCATION_CORNER_NORMAL = 10;
        /// Three locations.
        LOCATION_CORNER_UV = 13;
    }
}

glsl_table! {
    /// The height field's self-shadow modes, the value of `SPEC_SHADOW_MODE`
    /// (`shaders/include/shadows.glsl`; `ShadowMode` in the scene).
    SHADOW_MODES {
        SHADOW_MODE_NONE = 0;
        SHADOW_MODE_HARD = 1;
        SHADOW_MODE_POM_SOFT = 2;
        SHADOW_MODE_HORIZON = 3;
        SHADOW_MODE_CONE = 4;
    }
}

glsl_table! {
    /// The tone curves, `ToneMapPush::curve` (`shaders/include/tone_curves.glsl`; `ToneMap`).
    TONE_CURVES {
        /// Clamped to [0, 1].
        TONE_CURVE_NONE = 0;
        /// Khronos PBR Neutral.
        TONE_CURVE_PBR_NEUTRAL = 1;
        /// ACES, Narkowicz's fit.
        TONE_CURVE_ACES = 2;
    }
}

glsl_table! {
    /// A material's texture slots: bit k of `MaterialUniform::textures.x` and rows 2k, 2k + 1
    /// of its `uv_rows` (`shaders/include/draw.glsl`; `TextureSlot` in the scene).
    TEXTURE_SLOTS {
        SLOT_BASE_COLOR = 0;
        SLOT_METALLIC_ROUGHNESS = 1;
        SLOT_NORMAL = 2;
        SLOT_OCCLUSION = 3;
        SLOT_EMISSIVE = 4;
        /// Not a texture of the material's own: the uv transform of its height map.
        SLOT_HEIGHT = 5;
    }
}

glsl_table! {
    /// Specialization-constant ids, as `#define`s. The trace and surface passes share the budget
    /// and shadow ids; the level-of-detail ids start at 20 to keep clear of them.
    SPEC_IDS {
        /// The iteration cap.
        SPEC_BUDGET_MAX_STEPS = 0;
        /// Refinement steps after the search.
        SPEC_BUDGET_REFINE_STEPS = 1;
        /// 1: methods with a leaf stage finish on the exact bilinear patch.
        SPEC_BUDGET_LEAF_EXACT = 2;
        /// Nonzero: each ray's cap grows with the texels it crosses, up to this.
        SPEC_BUDGET_EXTENT_LIMIT = 3;
        /// `ShadowMode::shader_value`.
        SPEC_SHADOW_MODE = 8;
        /// Shadow samples or the shadow walk's iteration cap.
        SPEC_SHADOW_STEPS = 9;
        /// How far the horizon shadow's samples reach.
        SPEC_SHADOW_REACH = 10;
        /// How far a hard shadow's first hit must lie from the shaded point, in texels.
        SPEC_HARD_SHADOW_TEXELS = 11;
        /// The most capable shadow-map filter any light of the frame uses (`ShadowFilter`), 0
        /// for none: lookups compile only the filters up to it.
        SPEC_SHADOW_FILTER = 12;
        /// Level of detail: the stop level's scale with distance.
        SPEC_LOD_FACTOR = 20;
        /// Level of detail: added to the stop level.
        SPEC_LOD_BIAS = 21;
        /// Level of detail: where the fade to normal mapping starts.
        SPEC_LOD_FADE_START = 22;
        /// Level of detail: where it ends.
        SPEC_LOD_FADE_END = 23;
        /// Level of detail: below this many samples a linear search averages.
        SPEC_LOD_AVERAGE_BELOW = 24;
        /// The occluder bounds a relief fragment reads before tracing: 0 none, 1 its own pixel,
        /// 9 its pixel and the eight around it (multisampled targets).
        SPEC_OCCLUDER_TAPS = 30;
        /// 1: a relief fragment writes its displaced hit's depth; 0: the polygon's own.
        SPEC_WRITE_DEPTH = 31;
        /// 1: relief fragments count themselves and their steps per pixel (`relief render
        /// --count-work`); 0, the default, compiles the counting out.
        SPEC_COUNT_WORK = 32;
        /// 1: every height, pyramid and method-map fetch is counted (`heightfield.glsl`); 0,
        /// the default, compiles the counting out.
        SPEC_COUNT_FETCHES = 33;
        /// 1: a surface fragment writes its shading inputs and emission, and the lighting pass
        /// lights it (`RenderOptions::lighting`, deferred); 0 lights it in the fragment.
        SPEC_DEFERRED = 34;
    }
}

glsl_table! {
    /// Array sizes, as `#define`s.
    SIZES {
        /// Punctual lights in the frame's uniform block.
        MAX_LIGHTS = 8;
        /// Lights whose height-field self-shadow the deferred frame's shading inputs carry (one
        /// byte each): a deferred frame has at most this many self-shadowing lights.
        DEFERRED_SELF_SHADOW_LIGHTS = 4;
        /// Shadow-map views in the frame's uniform block (a cascade, a spot's map, a cube face).
        MAX_SHADOW_TILES = 16;
        /// Pyramid levels the map searches' push constants hold offsets for.
        MAX_LEVELS = 15;
        /// The horizon AO's cap on samples per azimuth.
        AO_HORIZON_MAX_SAMPLES = 64;
        /// The exact AO sweep's hull entries per line, a power of two: a fuller stack forgets
        /// its oldest, farthest entry.
        AO_HULL_CAPACITY = 128;
        /// The exact AO sweep's slots of 16 bytes per line after its hull ring: the walk's state
        /// between dispatches.
        AO_STATE_SLOTS = 2;
    }
}

/// Every layout shared with the shaders: the storage records and uniform blocks (structs first,
/// so that the header declares a struct before a block holds it), then the push constants.
#[allow(dead_code)] // Read by build.rs.
pub const SHADER_LAYOUTS: &[&[ShaderLayout]] = &[RECORD_LAYOUTS, UNIFORM_LAYOUTS, PUSH_LAYOUTS];

/// The tables written as `#define NAME value`, for layout qualifiers and array sizes.
#[allow(dead_code)] // Read by build.rs.
pub const GLSL_DEFINES: &[&[(&str, u32)]] = &[
    FRAME_BINDINGS,
    SEARCH_BINDINGS,
    TRACE_BINDINGS,
    OCCLUSION_BINDINGS,
    PYRAMID_BINDINGS,
    AO_BINDINGS,
    TERRAIN_BINDINGS,
    MATERIAL_BINDINGS,
    LAYER_BINDINGS,
    OCCLUDER_BINDINGS,
    LIGHTING_BINDINGS,
    CELLS_BINDINGS,
    ENVIRONMENT_BINDINGS,
    TERRAIN_MODES,
    SHADOW_FILTERS,
    SHADOW_MODES,
    TONE_CURVES,
    TEXTURE_SLOTS,
    VERTEX_LOCATIONS,
    MODES,
    SPEC_IDS,
    SIZES,
];

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_in_the_header_is_declared_once() {
        let mut names: Vec<&str> = GLSL_DEFINES
            .iter()
            .flat_map(|table| table.iter().map(|&(name, _)| name))
            .collect();
        let all = names.len();
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), all);
    }

    #[test]
    fn ids_in_one_pipeline_do_not_collide() {
        let mut traced: Vec<u32> = SPEC_IDS.iter().map(|&(_, id)| id).collect();
        let all = traced.len();
        traced.sort_unstable();
        traced.dedup();
        assert_eq!(traced.len(), all);
    }
}
