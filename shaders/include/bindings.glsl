// The descriptor bindings every pass that traces shares (surface and trace), so methods compare
// like with like. Push constants belong to each entry point.
#ifndef BINDINGS_GLSL
#define BINDINGS_GLSL

#include "interface.glsl"

// The frame's camera, ambient light, lights and shadow views: `FrameUniforms`, with `LightData`
// and `ShadowTile`, in interface.glsl.
layout(set = 0, binding = BINDING_FRAME, std140) uniform Frame {
    FRAME_FIELDS
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
