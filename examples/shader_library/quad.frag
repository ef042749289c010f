#version 460
// A relief quad drawn with the shader library alone: QDM finds where the view ray meets the
// height field, the library's cone walk shades the hit's self-shadow, and the pass writes the
// shaded colour and, beside it, what the hit is (uv, steps, view depth) for checking.
#extension GL_GOOGLE_include_directive : require

layout(push_constant, std430) uniform Push {
    mat4 view_proj;
    vec4 eye;
    vec4 forward;
    vec4 quad;
    vec4 height_info;
} push;

// The example's own bindings: the library only needs their names.
layout(set = 0, binding = 0) uniform sampler2D heights_nearest;
layout(set = 0, binding = 1) uniform sampler2D heights_bilinear;

#define RELIEF_HEIGHT_POINT heights_nearest
#define RELIEF_HEIGHT_LINEAR heights_bilinear
#define RELIEF_HEIGHT_INFO push.height_info
#include "relief_library.glsl"
#include "qdm.glsl"
#define METHOD_TRACE trace_qdm
#include "shadows.glsl"
#include "relief_frame.glsl"

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec2 in_uv;

// The displaced depth is never nearer than the polygon's, so early depth tests still hold; in
// an engine whose depth is reversed (RELIEF_REVERSE_Z) nearer is larger.
#ifdef RELIEF_REVERSE_Z
layout(depth_less) out float gl_FragDepth;
#else
layout(depth_greater) out float gl_FragDepth;
#endif
layout(location = 0) out vec4 out_color;
// u, v, steps, linear view depth of the hit.
layout(location = 1) out vec4 out_hit;

const vec3 SUN = vec3(-0.5, 0.6, 0.4);
const float SUN_RADIUS = 0.05;

void main() {
    float depth_scale = push.quad.y;
    // The quad's tangent frame: +u along +x, +v along +z, so the bitangent's sign is -1.
    ReliefFrame f = relief_frame(in_world, vec3(0.0, 1.0, 0.0), vec4(1.0, 0.0, 0.0, -1.0), in_uv, in_uv);
    vec3 view = normalize(in_world - push.eye.xyz);
    Ray ray = Ray(in_uv, height_space_ray_dir(f, view), depth_scale);
    Hit hit = trace_qdm(ray, ray_budget(ray));
    float z = clamp(hit.z, 0.0, depth_scale);
    vec2 uv = ray_uv(ray, z);
    vec3 world = relief_hit_world(f, in_world, in_uv, uv, z);

    // The displaced surface's normal, from the height gradient carried to world space.
    vec2 g = depth_scale * height_gradient(uv);
    vec3 n = normalize(f.n - f.t * (f.depth_len * g.x / f.scale.x) - f.b * (f.depth_len * g.y / f.scale.y));
    vec3 sun = normalize(SUN);
    float lit = light_visible(uv, z, to_height_space(f, sun), SUN_RADIUS, depth_scale);
    vec2 checks = floor(uv * 8.0);
    vec3 albedo = mod(checks.x + checks.y, 2.0) < 1.0 ? vec3(0.80, 0.72, 0.60) : vec3(0.45, 0.40, 0.34);
    vec3 colour = albedo * (0.2 + 0.8 * lit * max(dot(n, sun), 0.0));
    // The target is sRGB: the hardware encodes.
    out_color = vec4(colour, 1.0);
    out_hit = vec4(uv, float(hit.steps), dot(world - push.eye.xyz, push.forward.xyz));

    gl_FragDepth = relief_fragment_depth(push.view_proj * vec4(world, 1.0), gl_FragCoord.z);
}
