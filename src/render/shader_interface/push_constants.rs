//! The push-constant blocks shared by Rust and GLSL (std430), declared with their fields' GLSL
//! types: build.rs writes each into "interface.glsl" as the define `<NAME>_FIELDS`.

use super::{ShaderLayout, MAX_LEVELS};

// Level offsets are spelled `[u32; 15]`: with `MAX_LEVELS` there, rustc 1.95 hit an internal
// error ("broken MIR") when a closure captured a copy of the struct. The layout check below
// catches a `MAX_LEVELS` that no longer matches.

shader_layout! {
    /// `cone_map.comp`: a pyramid level or the conservative cone search of rows.
    block std430 ConeMapParams {
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

shader_layout! {
    /// `quadric_map.comp`: a pyramid level or the quadric fit of rows.
    block std430 QuadricMapParams {
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

shader_layout! {
    /// The relaxed cone map's kernels (`shaders/include/relaxed_cone.glsl`).
    block std430 RelaxedConeParams {
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

shader_layout! {
    /// `ao_horizon.comp`: the horizon-sampled AO of the texels `origin <= t < end`.
    block std430 AoHorizonParams {
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

shader_layout! {
    /// `ao_sweep.comp`: one azimuth's walk, or the whole map for the unpack and resolve modes.
    block std430 AoSweepParams {
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

shader_layout! {
    /// `pyramid.comp`: one level of the conservative max pyramid, over `region`.
    block std430 PyramidParams {
        /// x: 1 when building level 1 from the map (each range widened by a texel, so the node
        /// bounds the bilinear surface); y: 1 to wrap the widened range around the map (repeat
        /// addressing), 0 to clamp it.
        flags: [u32; 4] => "uvec4",
        /// The coarse texels to write, (x0, y0, width, height): the whole level, or after a brush
        /// stroke only the nodes that read a changed texel.
        region: [u32; 4] => "uvec4",
    }
}

shader_layout! {
    /// `trace.comp`: one sweep of parallel rays.
    block std430 TraceParams {
        /// xyz: the ray direction (dz > 0); w: the depth scale.
        dir: [f32; 4] => "vec4",
        /// x: columns, y: rows.
        grid: [u32; 4] => "uvec4",
        /// xyz: the unit direction toward the light (u, v, up); w: its angular radius (radians).
        light: [f32; 4] => "vec4",
    }
}

shader_layout! {
    /// `traced_occlusion.comp`: one batch of occlusion rays.
    block std430 OcclusionParams {
        /// x: the rays in the batch.
        count: [u32; 4] => "uvec4",
    }
}

shader_layout! {
    /// `lighting.comp:traced`: the scene's relief height map beside the frame's, and how its
    /// shadow rays are cast.
    block std430 TracedLightingParams {
        /// The traced scene's height map: width, height, mip levels, 1 for repeat addressing.
        height_info: [f32; 4] => "vec4",
        /// x: how far a shadow ray starts off its receiver, along the ray (world units); y:
        /// samples per side of the grid over a light with a size (its rays are x^2).
        rays: [f32; 4] => "vec4",
    }
}

shader_layout! {
    /// `brush.comp`: one stroke over the texels of `region`.
    block std430 BrushParams {
        /// Centre x, y (texels), radius (texels), strength.
        stroke: [f32; 4] => "vec4",
        /// x: the flatten target; y: the kind (`BRUSH_*`, as a float).
        shape: [f32; 4] => "vec4",
        /// The texels to visit (x0, y0, width, height).
        region: [u32; 4] => "uvec4",
    }
}

shader_layout! {
    /// `blended_pyramid.comp`: one level of the blended pyramid over `region`.
    block std430 BlendParams {
        /// x: the blend mode (`BLEND_*`); y: the level; z: 1 when the output stores 16-bit unorm,
        /// so that bounds round up to the next step.
        flags: [u32; 4] => "uvec4",
        /// The texels written (x0, y0, width, height): the whole level, or what painted weights
        /// changed.
        region: [u32; 4] => "uvec4",
    }
}

shader_layout! {
    /// The environment kernels: one image level written from the source environment.
    block std430 EnvironmentParams {
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

shader_layout! {
    /// What every mesh draw pushes (`shaders/include/draw.glsl`): the model matrix, its normal
    /// matrix (made once per object on the CPU rather than per vertex) and the draw's ids. 128
    /// bytes, the least every device allows.
    #[derive(Debug)]
    block std430 DrawPush as Draw {
        /// Object to world, column-major.
        model: [[f32; 4]; 4] => "mat4",
        /// Columns of the inverse transpose of the model's 3x3; `normal[0].w` is -1 when the
        /// model flips handedness (negative determinant), else 1.
        normal: [[f32; 4]; 3] => "vec4" [3],
        /// x: the shadow view a caster draw renders into (shadow pass only); y: the scene mesh
        /// index + 1, which the G-buffer records; z, w: unused.
        extra: [u32; 4] => "uvec4",
    }
}

shader_layout! {
    /// The tone-mapping pass (`tonemap.frag`, `tonemap_resolve.frag`).
    block std430 ToneMapPush {
        /// 2^EV.
        exposure: f32 => "float",
        /// `TONE_CURVE_*`.
        curve: u32 => "uint",
        /// Supersampling: the radiance is `scale` times the frame's size along each axis.
        scale: u32 => "uint",
        /// Samples per texel of a multisampled radiance (`tonemap_resolve.frag`).
        samples: u32 => "uint",
    }
}

shader_layout! {
    /// The environment drawn behind the scene (`background.frag`).
    block std430 BackgroundPush {
        /// Clip space back to world space, column-major.
        inverse_view_proj: [[f32; 4]; 4] => "mat4",
    }
}

shader_layout! {
    /// `cells_trace.comp`: a batch of rays marched through a cell complex.
    block std430 CellsTraceParams {
        /// The grid's low corner (xyz) and its cell side (w).
        origin_size: [f32; 4] => "vec4",
        /// Cells along each axis.
        n: u32 => "uint",
        /// Height texels along a cell face.
        resolution: u32 => "uint",
        ray_count: u32 => "uint",
        /// Halvings of the step once a ray is inside.
        refinements: u32 => "uint",
        /// March samples per height texel.
        samples_per_texel: f32 => "float",
    }
}

/// Every push-constant layout above, for build.rs's header.
#[allow(dead_code)] // Read by build.rs.
pub const PUSH_LAYOUTS: &[ShaderLayout] = &[
    DrawPush::LAYOUT,
    ToneMapPush::LAYOUT,
    BackgroundPush::LAYOUT,
    CellsTraceParams::LAYOUT,
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
