// The descriptor bindings every pass that traces shares (surface and trace), so methods compare
// like with like. Push constants belong to each entry point.
#ifndef BINDINGS_GLSL
#define BINDINGS_GLSL

#include "interface.glsl"

// A punctual light; mirrors `LightUniform` in src/render/kit/frame_uniforms.rs.
struct LightData {
    vec4 position;   // xyz: world position (point, spot); w: kind, 0 directional, 1 point, 2 spot
    vec4 direction;  // xyz: direction the light travels (directional, spot); w: range, 0 = none
    vec4 color;      // rgb: colour times intensity; w: 1 if relief traces shadow rays toward it
    vec4 cone;       // x, y: cos of the outer and inner cone angles (spot); z: radius (see Light)
};

// One shadow map's view; mirrors `ShadowTileUniform` in src/render/kit/frame_uniforms.rs.
struct ShadowTile {
    mat4 view_proj;
    vec4 rect;    // xy: atlas texel of its corner; z: size in texels; w: 1 perspective, 0 orthographic
    vec4 depth;   // x: near (perspective); y: far, or the depth range (orthographic); z: texel world size
    vec4 origin;  // xyz: light position (perspective) or the direction it travels (orthographic)
};

layout(set = 0, binding = BINDING_FRAME, std140) uniform Frame {
    mat4 view_proj;
    vec4 eye;          // xyz: camera position (world)
    vec4 ambient;      // rgb: flat ambient radiance; w: the prefiltered map's last level
    vec4 height_info;  // x: width, y: height, z: mip levels, w: 1 for repeat addressing, 0 clamp
    ivec4 counts;      // x: lights in use; y: 1 + the probed light (visibility written), 0 shades;
                       // z: 1 when lit by the environment maps
    LightData lights[MAX_LIGHTS];
    ivec4 light_shadows[MAX_LIGHTS];  // x: first tile, y: tiles (0: no map), z: filter
    ShadowTile shadow_tiles[MAX_SHADOW_TILES];
    vec4 view_depth;   // dot(xyz, p) + w: world point p's depth along the camera's axis
    mat4 previous_view_proj;  // the previous frame's view_proj (the G-buffer's motion)
    vec4 viewport;     // xy: the frame's size in pixels
    vec4 view_axis;    // xyz: the camera's forward axis; w: 1 orthographic, 0 perspective
} frame;

// The direction of the view ray through world point p: from the eye for a perspective camera,
// along the camera's axis for an orthographic one, whose rays are parallel.
vec3 view_ray_dir(vec3 p) {
    return frame.view_axis.w > 0.5 ? frame.view_axis.xyz : normalize(p - frame.eye.xyz);
}

#ifndef PLAIN_SURFACE
// The height field and its max pyramid in one mip-chained image, read two ways.
layout(set = 0, binding = BINDING_HEIGHT_POINT) uniform sampler2D height_point;   // nearest, nearest mip
layout(set = 0, binding = BINDING_HEIGHT_LINEAR) uniform sampler2D height_linear;  // bilinear

#ifdef USES_METHOD_MAP
// The method's precomputed map (cone ratios, quadric coefficients), one texel per height texel,
// read by integer texel. build.rs defines USES_METHOD_MAP for the methods whose row in the method
// table (src/method/table.rs) names a method map.
layout(set = 0, binding = BINDING_METHOD_MAP) uniform sampler2D method_map;
#endif
#endif

#endif
