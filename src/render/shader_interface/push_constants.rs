//! The push-constant layouts shared by Rust and GLSL: each a `#[repr(C)]` struct declared with
//! its fields' GLSL types, which build.rs writes into "interface.glsl" as the body of a define
//! and checks against std430.

use super::MAX_LEVELS;

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
    /// `cone_map.comp`: a pyramid level or the conservative cone search of rows.
    ConeMapParams {
        /// `MODE_REDUCE` or `MODE_SEARCH`.
        mode: u32 => "uint",
        /// Level 0 size in texels.
        width: u32 => "uint",
        height: u32 => "uint",
        /// 1 for Repeat, 0 for Clamp.
        repeat_address: u32 => "uint",
        /// Reductions: the level written.
        level: u32 => "uint",
        /// Searches: the first row of this dispatch.
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
    /// `quadric_map.comp`: a pyramid level or the quadric fit of rows.
    QuadricMapParams {
        /// `MODE_REDUCE` or `MODE_SEARCH`.
        mode: u32 => "uint",
        /// Level 0 size in texels.
        width: u32 => "uint",
        height: u32 => "uint",
        /// 1 for Repeat, 0 for Clamp.
        repeat_address: u32 => "uint",
        /// Reductions: the level written.
        level: u32 => "uint",
        /// Searches: the first row of this dispatch.
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
    /// `ao_sweep.comp`: one azimuth's walk, or the whole map for the unpack and resolve modes.
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
        /// `MODE_SWEEP`, `MODE_RESOLVE` or `MODE_UNPACK`.
        mode: u32 => "uint",
        depth_scale: f32 => "float",
        /// Length in uv of one lattice step.
        step_uv: f32 => "float",
        /// The horizon's azimuth as a uv unit vector (-walk, normalised in uv).
        dir: [f32; 2] => "vec2",
        /// This azimuth's share of the circle (the weights of a sweep sum to 1).
        weight: f32 => "float",
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
    /// `traced_occlusion.comp`: one batch of occlusion rays.
    OcclusionParams {
        /// x: the rays in the batch.
        count: [u32; 4] => "uvec4",
    }
}

push_constants! {
    /// `lighting.comp:traced`: the scene's relief height map beside the frame's, and how its
    /// shadow rays are cast.
    TracedLightingParams {
        /// The traced scene's height map: width, height, mip levels, 1 for repeat addressing.
        height_info: [f32; 4] => "vec4",
        /// x: how far a shadow ray starts off its receiver, along the ray (world units); y:
        /// samples per side of the grid over a light with a size (its rays are x^2).
        rays: [f32; 4] => "vec4",
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

push_constants! {
    /// The environment kernels: one image level written from the source environment.
    EnvironmentParams {
        /// The level written, in texels.
        out_width: u32 => "uint",
        out_height: u32 => "uint",
        /// The source level read (the irradiance kernel sums all its texels) and its size.
        source_level: u32 => "uint",
        source_width: u32 => "uint",
        source_height: u32 => "uint",
        /// Samples per texel (prefiltering, the BRDF table).
        samples: u32 => "uint",
        /// The GGX roughness of the level written (prefiltering).
        roughness: f32 => "float",
        /// The source's level 0 width over the width written, as a level of detail (roughness 0).
        base_lod: f32 => "float",
    }
}

/// Every push-constant layout above, for build.rs's header.
#[allow(dead_code)] // Read by build.rs.
pub const PUSH_LAYOUTS: &[PushLayout] = &[
    EnvironmentParams::LAYOUT,
    ConeMapParams::LAYOUT,
    QuadricMapParams::LAYOUT,
    RelaxedConeParams::LAYOUT,
    AoHorizonParams::LAYOUT,
    AoSweepParams::LAYOUT,
    PyramidParams::LAYOUT,
    TraceParams::LAYOUT,
    OcclusionParams::LAYOUT,
    TracedLightingParams::LAYOUT,
    BrushParams::LAYOUT,
    BlendParams::LAYOUT,
];
