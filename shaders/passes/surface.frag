#version 460
// The surface pass: builds the view ray in texture space, traces it with the method this variant
// was compiled with (build.rs maps "method.glsl" to shaders/methods/<id>.glsl), shades the hit
// with the height field's normal, and writes the displaced point's depth.
#extension GL_GOOGLE_include_directive : require
#include "conventions.glsl"
#include "numeric.glsl"
#include "bindings.glsl"
#include "draw.glsl"
#include "heightfield.glsl"
#include "lighting.glsl"
#include "method.glsl"

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv;
layout(location = 3) in vec4 in_tangent;

layout(location = 0) out vec4 out_color;

// Smallest dir.z of a view ray: below this (about 0.06 degrees) the ray is treated as this steep,
// so grazing views stay finite instead of producing inf offsets.
const float MIN_DIR_Z = 1e-3;

// World-space lengths of one uv unit along u and v, from screen-space derivatives.
vec2 world_per_uv() {
    vec3 dpx = dFdx(in_world), dpy = dFdy(in_world);
    vec2 dux = dFdx(in_uv), duy = dFdy(in_uv);
    float det = dux.x * duy.y - dux.y * duy.x;
    if (abs(det) < 1e-20) {
        return vec2(1.0);
    }
    vec3 dpdu = (dpx * duy.y - dpy * dux.y) / det;
    vec3 dpdv = (dpy * dux.x - dpx * duy.x) / det;
    return max(vec2(length(dpdu), length(dpdv)), vec2(1e-12));
}

void main() {
    vec3 n = normalize(gl_FrontFacing ? in_normal : -in_normal);
    vec3 t = normalize(in_tangent.xyz - n * dot(n, in_tangent.xyz));
    vec3 b = cross(n, t) * (in_tangent.w < 0.0 ? -1.0 : 1.0);
    vec2 scale = world_per_uv();
    // Depth is measured in uv units; one uv unit of depth spans the mean of the two uv lengths.
    float depth_len = sqrt(scale.x * scale.y);
    vec3 view = normalize(in_world - frame.eye.xyz);
    vec3 dir = vec3(dot(view, t) / scale.x, dot(view, b) / scale.y, -dot(view, n) / depth_len);
    dir.z = max(dir.z, MIN_DIR_Z * length(dir.xy));
    dir = normalize(dir);

    float depth_scale = draw.material.x;
    vec2 uv = in_uv;
    float z = 0.0;
    vec3 normal = n;
    if (depth_scale > 0.0) {
        Ray ray = Ray(in_uv, dir, depth_scale);
        Hit hit = METHOD_TRACE(ray, default_budget());
        z = clamp(hit.z, 0.0, depth_scale);
        uv = ray_uv(ray, z);
        // The surface sits at height s*h above the bottom plane; its normal in uv units, mapped to
        // world with the inverse-transpose of the (t*scale.x, b*scale.y, n*depth_len) frame.
        vec2 grad = depth_scale * height_gradient(uv);
        normal = normalize(t * (-grad.x / scale.x) + b * (-grad.y / scale.y) + n / depth_len);
    }

    vec3 world = in_world + t * ((uv.x - in_uv.x) * scale.x) + b * ((uv.y - in_uv.y) * scale.y)
        - n * (z * depth_len);
    vec4 clip = frame.view_proj * vec4(world, 1.0);
    gl_FragDepth = clamp(clip.z / clip.w, 0.0, 1.0);

    float shade_h = depth_scale > 0.0 ? height_bilinear(uv) : 1.0;
    vec3 albedo = draw.base_color.rgb * mix(0.45, 1.0, shade_h);
    vec3 v = -view;
    vec3 color = frame.ambient.rgb * albedo;
    if (frame.light_dir.w > 0.0) {
        vec3 l = normalize(frame.light_dir.xyz);
        color += shade_ggx(albedo, draw.material.y, draw.material.z, normal, v, l, frame.light_color.rgb);
    }
    out_color = vec4(color, draw.base_color.a);
}
