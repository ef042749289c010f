//! What the Rust side and the shaders must agree on — descriptor bindings, specialization-constant
//! ids, array sizes and the push-constant layouts of the map and AO builders — written once,
//! here. build.rs compiles this file as a module of its own and writes every table below into the
//! GLSL header "interface.glsl", which the shaders include; so this file uses nothing outside
//! itself but `bytemuck`.

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
    }
}

glsl_table! {
    /// Set 0 of the map searches (`buffer_pyramid_reduce.comp`, `cone_map.comp`,
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
    /// Set 0 of the AO map kernels (`shaders/include/ao.glsl`, `ao_sweep.glsl`), as `#define`s.
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
    }
}

glsl_table! {
    /// Array sizes, as `#define`s.
    SIZES {
        /// Punctual lights in the frame's uniform block.
        MAX_LIGHTS = 8;
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

/// The tables written as `#define NAME value`, for layout qualifiers and array sizes.
#[allow(dead_code)] // Read by build.rs.
pub const GLSL_DEFINES: &[&[(&str, u32)]] = &[
    FRAME_BINDINGS,
    SEARCH_BINDINGS,
    TRACE_BINDINGS,
    PYRAMID_BINDINGS,
    AO_BINDINGS,
    TERRAIN_BINDINGS,
    TERRAIN_MODES,
    SPEC_IDS,
    SIZES,
];

/// One push-constant field: its GLSL type, its array length (the header's name for it and the
/// value), and its offset in the Rust struct.
#[allow(dead_code)] // Read by build.rs, which writes and checks the GLSL side.
pub struct PushField {
    pub name: &'static str,
    pub glsl: &'static str,
    pub array: Option<(&'static str, usize)>,
    pub offset: usize,
}

/// A push-constant struct as the header declares it: the shaders write
/// `layout(push_constant, std430) uniform Params { <NAME>_FIELDS } params;`.
#[allow(dead_code)] // Read by build.rs, which writes and checks the GLSL side.
pub struct PushLayout {
    /// The Rust struct's name, CamelCase; the header's define is its UPPER_SNAKE form.
    pub name: &'static str,
    pub fields: &'static [PushField],
    pub size: usize,
}

/// Declares a `#[repr(C)]` push-constant struct with each field's GLSL type, and its
/// [`PushLayout`] as `LAYOUT`.
macro_rules! push_constants {
    (
        $(#[$doc:meta])*
        $name:ident {
            $($(#[$fdoc:meta])* $field:ident: $ty:ty => $glsl:literal $([$len:ident])?,)*
        }
    ) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(Clone, Copy, bytemuck::Pod, bytemuck::Zeroable)]
        pub struct $name {
            $($(#[$fdoc])* pub $field: $ty,)*
        }

        impl $name {
            // Read by build.rs and the tests; the library uses the struct.
            #[allow(dead_code)]
            pub const LAYOUT: PushLayout = PushLayout {
                name: stringify!($name),
                fields: &[$(PushField {
                    name: stringify!($field),
                    glsl: $glsl,
                    array: push_constants!(@len $($len)?),
                    offset: std::mem::offset_of!($name, $field),
                }),*],
                size: std::mem::size_of::<$name>(),
            };
        }
    };
    (@len) => { None };
    (@len $len:ident) => { Some((stringify!($len), $len as usize)) };
}

// Level offsets are spelled `[u32; 15]`: with `MAX_LEVELS` there, rustc 1.95 hit an internal
// error ("broken MIR") when a closure captured a copy of the struct. The layout check below
// catches a `MAX_LEVELS` that no longer matches.

push_constants! {
    /// `buffer_pyramid_reduce.comp`: level `level` of the max pyramid from the level below.
    PyramidReduceParams {
        /// Level 0 size in texels.
        width: u32 => "uint",
        height: u32 => "uint",
        level: u32 => "uint",
        /// Where each level starts in the pyramid buffer, in floats (the host computes them).
        offsets: [u32; 15] => "uint" [MAX_LEVELS],
    }
}

push_constants! {
    /// `cone_map.comp`: the conservative cone search of rows from `row0`.
    ConeMapParams {
        /// Level 0 size in texels.
        width: u32 => "uint",
        height: u32 => "uint",
        /// 1 for Repeat, 0 for Clamp.
        repeat_address: u32 => "uint",
        /// The first row of this dispatch.
        row0: u32 => "uint",
        /// width / height rounded to f32: the v distance in u-texel units is dy * aspect.
        aspect: f32 => "float",
        /// The level whose single node covers the map.
        top: u32 => "uint",
        /// Where each level starts in the pyramid buffer.
        offsets: [u32; 15] => "uint" [MAX_LEVELS],
    }
}

push_constants! {
    /// `quadric_map.comp`: the quadric fit of rows from `row0`.
    QuadricMapParams {
        /// Level 0 size in texels.
        width: u32 => "uint",
        height: u32 => "uint",
        /// 1 for Repeat, 0 for Clamp.
        repeat_address: u32 => "uint",
        /// The first row of this dispatch.
        row0: u32 => "uint",
        /// The level whose single node covers the map.
        top: u32 => "uint",
        /// Where each level starts in the pyramid buffer.
        offsets: [u32; 15] => "uint" [MAX_LEVELS],
    }
}

push_constants! {
    /// The relaxed cone map's kernels (`shaders/include/relaxed_cone.glsl`).
    RelaxedConeParams {
        width: u32 => "uint",
        height: u32 => "uint",
        /// 1 for Repeat, 0 for Clamp.
        repeat_address: u32 => "uint",
        /// The reductions: the level written.
        level: u32 => "uint",
        /// The searches: the first row of this dispatch.
        row0: u32 => "uint",
        aspect: f32 => "float",
        /// The level whose single node covers the map.
        top: u32 => "uint",
        /// A reach unit: the reach cap's 65535th part.
        reach_unit: f32 => "float",
        /// The reach cap in u-texels (0.25 uv or 16 texels, whichever is less).
        reach_cap: f32 => "float",
        offsets: [u32; 15] => "uint" [MAX_LEVELS],
    }
}

push_constants! {
    /// `ao_horizon.comp`: the horizon-sampled AO of the texels `origin <= t < end`.
    AoHorizonParams {
        size: [i32; 2] => "ivec2",
        /// 1 for repeat, 0 for clamp.
        repeat_address: u32 => "uint",
        directions: u32 => "uint",
        /// 1 to turn each texel's azimuths by a hash of the texel.
        rotated: u32 => "uint",
        depth_scale: f32 => "float",
        /// The first sample's distance in texels of the longer side, and the growth per sample.
        first_distance: f32 => "float",
        growth: f32 => "float",
        /// Samples stop beyond this distance in uv: the whole profile that can matter, or a
        /// bounded reach (`AoMapPass::prepare_reaching`) so that a height change is seen from
        /// nearby only.
        reach_uv: f32 => "float",
        /// Level read at distance d texels: floor(log2(d)) - level_bias, within the image's mips.
        level_bias: i32 => "int",
        /// The texels written: the whole map, or after a local change of the heights only the
        /// texels that can see it (every texel's value is the same either way).
        origin: [i32; 2] => "ivec2",
        end: [i32; 2] => "ivec2",
    }
}

push_constants! {
    /// The exact-horizon AO kernels (`shaders/include/ao_sweep.glsl`): one azimuth's walk, or
    /// the whole map for the unpack and resolve kernels.
    AoSweepParams {
        size: [i32; 2] => "ivec2",
        /// The lattice step of the walk; the horizon looks the other way.
        walk: [i32; 2] => "ivec2",
        /// (x, y) with x * walk.y - y * walk.x = 1: line c of a clamped sweep passes through
        /// c * (x, y).
        euclid: [i32; 2] => "ivec2",
        /// Clamp: the first line's c = i * walk.y - j * walk.x. Repeat: unused.
        c_min: i32 => "int",
        lines: u32 => "uint",
        repeat_address: u32 => "uint",
        /// Repeat: lattice steps around one orbit; the orbits start at (l % g_a, l / g_a).
        period: u32 => "uint",
        g_a: u32 => "uint",
        /// This azimuth's share of the circle (the weights of a sweep sum to 1).
        weight: f32 => "float",
        depth_scale: f32 => "float",
        /// Length in uv of one lattice step.
        step_uv: f32 => "float",
        /// The horizon's azimuth as a uv unit vector (-walk, normalised in uv).
        dir: [f32; 2] => "vec2",
        /// This azimuth's crossings: `crossing_count` entries from `crossing_base`.
        crossing_base: u32 => "uint",
        crossing_count: u32 => "uint",
        /// Repeat: line l is segment l % segments of orbit l / segments: it records
        /// segment_steps texels after warm_steps steps of warm-up (a whole period unless the
        /// orbit is very long).
        segments: u32 => "uint",
        segment_steps: u32 => "uint",
        warm_steps: u32 => "uint",
        /// This dispatch walks steps [chunk * chunk_steps, (chunk + 1) * chunk_steps) of every
        /// line.
        chunk: u32 => "uint",
        chunk_steps: u32 => "uint",
    }
}

push_constants! {
    /// `pyramid.comp`: one level of the conservative max pyramid, over `region`.
    PyramidParams {
        /// x: 1 when building level 1 from the map (each range widened by a texel, so the node
        /// bounds the bilinear surface); y: 1 to wrap the widened range around the map (repeat
        /// addressing), 0 to clamp it.
        flags: [u32; 4] => "uvec4",
        /// The coarse texels to write, (x0, y0, width, height): the whole level, or after a brush
        /// stroke only the nodes that read a changed texel.
        region: [u32; 4] => "uvec4",
    }
}

push_constants! {
    /// `trace.comp`: one sweep of parallel rays.
    TraceParams {
        /// xyz: the ray direction (dz > 0); w: the depth scale.
        dir: [f32; 4] => "vec4",
        /// x: columns, y: rows.
        grid: [u32; 4] => "uvec4",
        /// xyz: the unit direction toward the light (u, v, up); w: its angular radius (radians).
        light: [f32; 4] => "vec4",
    }
}

push_constants! {
    /// `brush.comp`: one stroke over the texels of `region`.
    BrushParams {
        /// Centre x, y (texels), radius (texels), strength.
        stroke: [f32; 4] => "vec4",
        /// x: the flatten target; y: the kind (`BRUSH_*`, as a float).
        shape: [f32; 4] => "vec4",
        /// The texels to visit (x0, y0, width, height).
        region: [u32; 4] => "uvec4",
    }
}

push_constants! {
    /// `blended_pyramid.comp`: one level of the blended pyramid over `region`.
    BlendParams {
        /// x: the blend mode (`BLEND_*`); y: the level; z: 1 when the output stores 16-bit unorm,
        /// so that bounds round up to the next step.
        flags: [u32; 4] => "uvec4",
        /// The texels written (x0, y0, width, height): the whole level, or what painted weights
        /// changed.
        region: [u32; 4] => "uvec4",
    }
}

/// Every push-constant layout above, for build.rs's header.
#[allow(dead_code)] // Read by build.rs.
pub const PUSH_LAYOUTS: &[PushLayout] = &[
    PyramidReduceParams::LAYOUT,
    ConeMapParams::LAYOUT,
    QuadricMapParams::LAYOUT,
    RelaxedConeParams::LAYOUT,
    AoHorizonParams::LAYOUT,
    AoSweepParams::LAYOUT,
    PyramidParams::LAYOUT,
    TraceParams::LAYOUT,
    BrushParams::LAYOUT,
    BlendParams::LAYOUT,
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
