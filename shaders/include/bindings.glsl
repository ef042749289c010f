// The descriptor bindings every pass that traces shares (surface and trace), so methods compare
// like with like. Push constants belong to each entry point.
#ifndef BINDINGS_GLSL
#define BINDINGS_GLSL

layout(set = 0, binding = 0, std140) uniform Frame {
    mat4 view_proj;
    vec4 eye;          // xyz: camera position (world)
    vec4 light_dir;    // xyz: direction toward the light (world), w: 1 if the light is on
    vec4 light_color;  // rgb: radiance times intensity
    vec4 ambient;      // rgb: ambient radiance
    vec4 height_info;  // x: width, y: height, z: mip levels, w: 1 for repeat addressing, 0 clamp
} frame;

// The height field and its max pyramid in one mip-chained image, read two ways.
layout(set = 0, binding = 1) uniform sampler2D height_point;   // nearest, nearest mip
layout(set = 0, binding = 2) uniform sampler2D height_linear;  // bilinear

#ifdef USES_METHOD_MAP
// The method's precomputed map (cone ratios, quadric coefficients), one texel per height texel,
// read by integer texel. build.rs defines USES_METHOD_MAP for methods that mention it.
layout(set = 0, binding = 3) uniform sampler2D method_map;
#endif


#endif
