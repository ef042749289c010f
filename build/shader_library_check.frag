#version 460
// Every file of the shader library in one fragment shader, compiled by build.rs with an include
// resolver that knows only the library's files: a library file that uses one of relief's own
// bindings, blocks or interface names, or two files that define the same name, fail the build.
#extension GL_GOOGLE_include_directive : require

layout(set = 0, binding = 0) uniform sampler2D check_point;
layout(set = 0, binding = 1) uniform sampler2D check_linear;
layout(set = 0, binding = 2) uniform sampler2D check_map;
layout(push_constant) uniform Push {
    vec4 height_info;
} push;

#define RELIEF_HEIGHT_POINT check_point
#define RELIEF_HEIGHT_LINEAR check_linear
#define RELIEF_HEIGHT_INFO push.height_info
#define RELIEF_METHOD_MAP check_map
#include "relief_library.glsl"
#include "parallax.glsl"
#include "steep.glsl"
#include "relief.glsl"
#include "pom.glsl"
#include "csm.glsl"
#include "rcsm.glsl"
#include "qrm.glsl"
#include "pdm.glsl"
#include "qdm.glsl"
#include "maxmip.glsl"
#include "quadric.glsl"
#define METHOD_TRACE trace_relief
#include "shadows.glsl"
#include "relief_frame.glsl"
#include "curved.glsl"

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec2 in_uv;
layout(location = 0) out vec4 out_hit;

void main() {
    ReliefFrame f = relief_frame(in_world, vec3(0.0, 1.0, 0.0), vec4(1.0, 0.0, 0.0, 1.0), in_uv, in_uv);
    Ray ray = Ray(in_uv, height_space_ray_dir(f, vec3(0.0, -1.0, 0.0)), 0.1);
    Budget b = ray_budget(ray);
    float z = trace_parallax(ray, b).z + trace_steep(ray, b).z + trace_relief(ray, b).z
            + trace_pom(ray, b).z + trace_csm(ray, b).z + trace_rcsm(ray, b).z
            + trace_qrm(ray, b).z + trace_pdm(ray, b).z + trace_qdm(ray, b).z
            + trace_maxmip(ray, b).z + trace_quadric(ray, b).z
            + trace_curved(ray, b, f, surface_curvature(in_world, f.n, f)).z;
    out_hit = vec4(ray_uv(ray, z), z, light_visible(in_uv, z, vec3(0.0, 0.0, 1.0), 0.05, 0.1));
}
