#version 460
// The occluder pass: before the surface pass traces anything, every opaque surface that cannot
// be cut away writes, per pixel, the farthest depth it can reach there. A plain mesh reaches its
// own rasterised depth; a relief surface reaches at most the bottom of its slab: every ray
// entering the top meets the height field by the time it has descended depth_scale (heights
// never go below 0), so the point where the view ray, as the surface pass builds it, crosses
// the bottom plane is behind its hit. The depth test keeps the nearest polygon, whose bound is
// the colour the surface pass reads (occluders.glsl): a fragment whose polygon lies behind it
// is hidden, whatever either trace finds. Neither variant writes depth or discards, so the
// driver tests depth before running them, and hidden polygons cost no shading here.
#extension GL_GOOGLE_include_directive : require
#include "conventions.glsl"
#include "numeric.glsl"
#include "bindings.glsl"
#include "draw.glsl"
#ifndef PLAIN_SURFACE
#include "relief_frame.glsl"
#endif

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv0;
layout(location = 3) in vec2 in_uv1;
layout(location = 4) in vec4 in_tangent;
layout(location = 5) in vec4 in_color;

layout(location = 0) out float out_bound;

void main() {
#ifdef PLAIN_SURFACE
    out_bound = gl_FragCoord.z;
#else
    vec3 n = normalize(gl_FrontFacing ? in_normal : -in_normal);
    float depth_scale = material.relief.x;
    ReliefFrame f = relief_frame(in_world, n, in_tangent, in_uv0, in_uv1);
    vec3 view = view_ray_dir(in_world);
    vec2 uv_h = slot_uv(SLOT_HEIGHT, in_uv0, in_uv1);
    Ray ray = Ray(uv_h, height_space_ray_dir(f, view), depth_scale);
    vec2 uv_bottom = ray_uv(ray, depth_scale);
    vec3 bottom = relief_hit_world(f, in_world, uv_h, uv_bottom, depth_scale);
    vec4 clip = frame.view_proj * vec4(bottom, 1.0);
    // Depth along the traced ray is monotonic, and the surface pass writes the hit's depth no
    // nearer than the polygon's, so this max bounds what it writes.
    float reach = clip.w > 0.0 ? clamp(clip.z / clip.w, 0.0, 1.0) : 1.0;
    // A clamp-addressed map cuts the rays that leave its bounds (the surface pass discards
    // them): there the polygon bounds nothing. One whose bottom point is still inside cannot
    // leave before its hit.
    bool cut = frame.height_info.w < 0.5 && leaves_clamped_map(uv_h, uv_bottom);
    out_bound = cut ? 1.0 : max(gl_FragCoord.z, reach);
#endif
}
