//! The uniform blocks (std140) and the structs inside them, shared by Rust and GLSL: build.rs
//! writes each struct into "interface.glsl" as a GLSL `struct` and each block as the define
//! `<NAME>_FIELDS`. What fills them lives with the passes that bind them.

use super::{ShaderLayout, MAX_LIGHTS, MAX_SHADOW_TILES};

shader_layout! {
    /// One punctual light of the frame.
    #[derive(Debug, Default)]
    record std140 LightUniform as LightData {
        /// xyz: world position (point, spot); w: kind, 0 directional, 1 point, 2 spot.
        position: [f32; 4] => "vec4",
        /// xyz: unit world direction the light travels (directional, spot); w: range, 0 for none.
        direction: [f32; 4] => "vec4",
        /// rgb: linear colour times intensity; w: 1 if relief traces self-shadow rays toward it.
        color: [f32; 4] => "vec4",
        /// x, y: cosines of the outer and inner cone angles (spot, else 0); z: the light's size
        /// (`Light::radius`: radians for directional, world units otherwise); w: unused.
        cone: [f32; 4] => "vec4",
    }
}

shader_layout! {
    /// One shadow map's view: a cascade, a spot light's map or a cube face.
    #[derive(Debug, Default)]
    record std140 ShadowTileUniform as ShadowTile {
        /// World to the view's clip space, column-major.
        view_proj: [[f32; 4]; 4] => "mat4",
        /// xy: the atlas texel of the tile's corner; z: its size in texels; w: 1 perspective, 0
        /// orthographic.
        rect: [f32; 4] => "vec4",
        /// x: near plane (perspective); y: far plane, or the depth range in world units
        /// (orthographic); z: world size of a texel (at unit distance when perspective); w: unused.
        depth: [f32; 4] => "vec4",
        /// xyz: the light's position (perspective) or the direction it travels (orthographic).
        origin: [f32; 4] => "vec4",
    }
}

shader_layout! {
    /// The frame uniform block every pass that traces binds (set 0, `BINDING_FRAME`): camera,
    /// ambient, the height map's size, the punctual lights and the views of their shadow maps.
    #[derive(Debug)]
    block std140 FrameUniforms as Frame {
        /// World to clip space, column-major (glam's `to_cols_array_2d`).
        view_proj: [[f32; 4]; 4] => "mat4",
        /// xyz: camera position in world space; w: 1.
        eye: [f32; 4] => "vec4",
        /// rgb: flat ambient radiance, linear; w: with an environment, the prefiltered specular
        /// map's last level.
        ambient: [f32; 4] => "vec4",
        /// x: width and y: height in texels, z: mip levels, w: 1 for repeat addressing, 0 for
        /// clamp. Filled in per height map; zero until then.
        height_info: [f32; 4] => "vec4",
        /// x: lights in use (at most `MAX_LIGHTS`); y: 1 + the light whose visibility the frame
        /// writes instead of colours (the shadow probe, `relief shadows`), 0 to shade; z: 1 when
        /// the ambient light comes from the environment maps, 0 for the flat colour; w: unused.
        counts: [i32; 4] => "ivec4",
        /// The first `counts.x` are the frame's lights; the rest are zero.
        lights: [LightUniform; MAX_LIGHTS as usize] => "LightData" [MAX_LIGHTS],
        /// Per light: x the first of its shadow tiles, y how many (0: no shadow map), z its
        /// shadow filter (`SHADOW_FILTER_*`); w: unused.
        light_shadows: [[i32; 4]; MAX_LIGHTS as usize] => "ivec4" [MAX_LIGHTS],
        /// The shadow maps' views.
        shadow_tiles: [ShadowTileUniform; MAX_SHADOW_TILES as usize] => "ShadowTile" [MAX_SHADOW_TILES],
        /// The plane of linear view depth: `dot(xyz, p) + w` is world point p's distance along
        /// the camera's axis (the G-buffer's depth).
        view_depth: [f32; 4] => "vec4",
        /// The previous frame's world to clip space (the G-buffer's motion is measured against
        /// it); the frame's own when there is none.
        previous_view_proj: [[f32; 4]; 4] => "mat4",
        /// x, y: the frame's size in pixels; z, w: unused.
        viewport: [f32; 4] => "vec4",
        /// xyz: the camera's axis (unit, world space, looking forward); w: 1 for an orthographic
        /// camera, whose view rays all run along it, 0 for a perspective one.
        view_axis: [f32; 4] => "vec4",
    }
}

shader_layout! {
    /// A material's parameters (set 1, `BINDING_MATERIAL_PARAMS`, `shaders/include/draw.glsl`).
    #[derive(Debug)]
    block std140 MaterialUniform as MaterialParams {
        /// Linear base colour factor and alpha.
        base_color: [f32; 4] => "vec4",
        /// rgb: emissive factor; w: alpha cutoff (mask mode), -1 otherwise.
        emissive: [f32; 4] => "vec4",
        /// x: roughness, y: metallic, z: normal scale, w: occlusion strength.
        pbr: [f32; 4] => "vec4",
        /// x: depth scale (uv units of the height map, 0 = none); y: 1 if blended; z, w: unused.
        relief: [f32; 4] => "vec4",
        /// x: bit k set when texture slot k (`SLOT_*`) has a texture, and bit
        /// `SLOT_RELIEF_AO` when the relief's AO map is bound.
        textures: [u32; 4] => "uvec4",
        /// Per slot (and the height map's uv after them), `KHR_texture_transform` as two rows
        /// of a 2x3 matrix; row 0's w: the texCoord set.
        uv_rows: [[f32; 4]; 12] => "vec4" [12],
    }
}

shader_layout! {
    /// A height-blended layered material's parameters (set 2, `BINDING_LAYER_PARAMS`,
    /// `shaders/include/terrain_layers.glsl`).
    #[derive(Debug)]
    block std140 LayerUniform as LayerParams {
        /// x: blend mode (`BLEND_*`); y: layer count; z: bit k set when layer k has a normal
        /// map; w: 1 when vertex colours weigh the layers (so do not tint).
        info: [u32; 4] => "uvec4",
        /// Repeats of each layer across the height uv.
        tiling: [f32; 4] => "vec4",
        /// Each layer's height scale.
        depth: [f32; 4] => "vec4",
    }
}

shader_layout! {
    /// A cell complex's grid as the cells pass reads it (set 2, `BINDING_CELLS_PARAMS`,
    /// `cells.frag`).
    block std140 CellsUniform as CellsParams {
        /// The grid's low corner (xyz) and its cell side (w).
        origin_size: [f32; 4] => "vec4",
        /// Cells along each axis.
        n: u32 => "uint",
        /// Height texels along a cell face.
        resolution: u32 => "uint",
        /// Halvings of the step once a ray is inside.
        refinements: u32 => "uint",
        /// March samples per height texel.
        samples_per_texel: f32 => "float",
    }
}

/// Every uniform block and the structs they hold, structs first, for build.rs's header.
#[allow(dead_code)] // Read by build.rs.
pub const UNIFORM_LAYOUTS: &[ShaderLayout] = &[
    LightUniform::LAYOUT,
    ShadowTileUniform::LAYOUT,
    FrameUniforms::LAYOUT,
    MaterialUniform::LAYOUT,
    LayerUniform::LAYOUT,
    CellsUniform::LAYOUT,
];
