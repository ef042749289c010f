#version 460
// A prism shell's corner (src/shells/shell_mesh.rs), already in world space, to clip space;
// the whole prism rides along, flat, for the fragment's march (shells.glsl). The shadow pass's
// variant (SHADOW_CASTER) places it in the shadow view the draw renders into.
#extension GL_GOOGLE_include_directive : require
#define PLAIN_SURFACE
#include "bindings.glsl"
#include "draw.glsl"

layout(location = LOCATION_POSITION) in vec3 in_position;
layout(location = LOCATION_NORMAL) in vec3 in_normal;
layout(location = LOCATION_UV0) in vec2 in_uv0;
layout(location = LOCATION_UV1) in vec2 in_uv1;
layout(location = LOCATION_TANGENT) in vec4 in_tangent;
layout(location = LOCATION_COLOR) in vec4 in_color;
layout(location = LOCATION_PRISM) in vec4 in_prism;
layout(location = LOCATION_TOP) in vec4 in_top[3];
layout(location = LOCATION_CORNER_NORMAL) in vec4 in_corner_normal[3];
layout(location = LOCATION_CORNER_UV) in vec4 in_corner_uv[3];

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec2 out_uv0;
layout(location = 3) out vec2 out_uv1;
layout(location = 4) out vec4 out_tangent;
layout(location = 5) out vec4 out_color;
layout(location = 6) out vec4 out_prism;
layout(location = 7) flat out vec4 out_top[3];
layout(location = 10) flat out vec4 out_corner_normal[3];
layout(location = 13) flat out vec4 out_corner_uv[3];

void main() {
    out_world = in_position;
    out_normal = in_normal;
    out_uv0 = in_uv0;
    out_uv1 = in_uv1;
    out_tangent = in_tangent;
    out_color = in_color;
    out_prism = in_prism;
    out_top = in_top;
    out_corner_normal = in_corner_normal;
    out_corner_uv = in_corner_uv;
#ifdef SHADOW_CASTER
    gl_Position = frame.shadow_tiles[draw.extra.x].view_proj * vec4(in_position, 1.0);
#else
    gl_Position = frame.view_proj * vec4(in_position, 1.0);
#endif
}
