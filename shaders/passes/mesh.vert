#version 460
// Transforms a mesh vertex to clip space and hands the fragment shader its world-space frame;
// the shadow pass's variant (SHADOW_CASTER) to the clip space of the shadow view it renders.
#extension GL_GOOGLE_include_directive : require
#define PLAIN_SURFACE
#include "bindings.glsl"
#include "draw.glsl"

layout(location = LOCATION_POSITION) in vec3 in_position;
layout(location = LOCATION_NORMAL) in vec3 in_normal;
layout(location = LOCATION_UV0) in vec2 in_uv0;
layout(location = LOCATION_UV1) in vec2 in_uv1;
layout(location = LOCATION_TANGENT) in vec4 in_tangent;  // xyz: tangent, w: bitangent sign
layout(location = LOCATION_COLOR) in vec4 in_color;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec3 out_normal;
layout(location = 2) out vec2 out_uv0;
layout(location = 3) out vec2 out_uv1;
layout(location = 4) out vec4 out_tangent;
layout(location = 5) out vec4 out_color;

void main() {
    vec4 world = draw.model * vec4(in_position, 1.0);
    // Normals transform with the inverse transpose, so non-uniform scales stay correct.
    mat3 normal_matrix = mat3(draw.normal[0].xyz, draw.normal[1].xyz, draw.normal[2].xyz);
    out_world = world.xyz;
    out_normal = normal_matrix * in_normal;
    out_uv0 = in_uv0;
    out_uv1 = in_uv1;
    // A mirroring transform flips normal x tangent relative to the mapped bitangent.
    float mirror = draw.normal[0].w;
    out_tangent = vec4(mat3(draw.model) * in_tangent.xyz, in_tangent.w * mirror);
    out_color = in_color;
#ifdef SHADOW_CASTER
    gl_Position = frame.shadow_tiles[draw.extra.x].view_proj * world;
#else
    gl_Position = frame.view_proj * world;
#endif
}
