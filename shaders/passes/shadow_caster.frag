#version 460
// The shadow pass: a mesh seen from a light. Relief variants (build.rs maps "method.glsl" to the
// method's file) trace the light's ray through the height field with the material's own method,
// exactly as the surface pass traces the view ray, and write the hit's depth in the shadow view:
// a height field casts the shadow of its relief, not of its polygon. The plain variant
// (PLAIN_SURFACE) keeps the rasterised depth. Both honour alpha-mask cut-outs, and both write the
// depth twice: for the depth test, and as the colour the surface pass samples (shadow_atlas.rs).
#extension GL_GOOGLE_include_directive : require
#include "conventions.glsl"
#include "numeric.glsl"
#include "bindings.glsl"
#include "draw.glsl"
#include "material_sample.glsl"
#ifndef PLAIN_SURFACE
#include "heightfield.glsl"
#include "relief_frame.glsl"
#include "method.glsl"
#ifdef CURVED
#include "curved.glsl"
#endif
#ifdef SHELLS
#include "curved.glsl"
#include "shells.glsl"
#endif
#endif

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv0;
layout(location = 3) in vec2 in_uv1;
layout(location = 4) in vec4 in_tangent;
layout(location = 5) in vec4 in_color;

layout(location = 0) out float out_depth;
#ifndef PLAIN_SURFACE
// The hit is never nearer the light than the polygon, as in the surface pass.
layout(depth_greater) out float gl_FragDepth;
#endif

void main() {
    vec2 uv0 = in_uv0;
    vec2 uv1 = in_uv1;
#ifndef PLAIN_SURFACE
    ShadowTile tile = frame.shadow_tiles[draw.extra.x];
    // The light's ray through this fragment: from the light's position, or along its direction.
    vec3 along = tile.rect.w > 0.5 ? normalize(in_world - tile.origin.xyz) : tile.origin.xyz;
#ifdef SHELLS
    // The light's ray through the prism this face bounds, as the surface pass walks the view's.
    ShellPrism prism = shell_prism();
    ShellHit shell_hit;
    if (!trace_shell(prism, in_world, along, in_prism.xyz, shell_entry_face(in_prism.z), shell_hit)) {
        discard;
    }
    uv0 = prism_blend2(prism.uv0, shell_hit.coords.xy);
    uv1 = prism_blend2(prism.uv1, shell_hit.coords.xy);
    vec3 world = in_world + along * shell_hit.t;
#else
    vec3 n = normalize(gl_FrontFacing ? in_normal : -in_normal);
    float depth_scale = material.relief.x;
    ReliefFrame f = relief_frame(in_world, n, in_tangent, in_uv0, in_uv1);
    vec2 uv_h = slot_uv(SLOT_HEIGHT, in_uv0, in_uv1);
    Ray ray = Ray(uv_h, height_space_ray_dir(f, along), depth_scale);
#ifdef CURVED
    // The light's ray through the curved shell: one that leaves it without meeting the surface
    // casts nothing, so the shadow's outline is the displaced surface's, as the frame's is.
    Hit hit = trace_curved(ray, ray_budget(ray), f, surface_curvature(in_world, n, f));
    if (hit.z < 0.0) {
        discard;
    }
    float z = max(hit.z, 0.0);
#else
    Hit hit = METHOD_TRACE(ray, ray_budget(ray));
    float z = clamp(hit.z, 0.0, depth_scale);
#endif
    vec2 uv_hit = ray_uv(ray, z);
    if (frame.height_info.w < 0.5 && leaves_clamped_map(uv_h, uv_hit)) {
        discard;
    }
    vec2 d0 = f.from_height * (uv_hit - uv_h);
    uv0 += d0;
    uv1 += f.uv1_per_uv0 * d0;
    vec3 world = relief_hit_world(f, in_world, uv_h, uv_hit, z);
#endif
    vec4 clip = tile.view_proj * vec4(world, 1.0);
    gl_FragDepth = relief_fragment_depth(clip, gl_FragCoord.z);
    out_depth = gl_FragDepth;
#else
    out_depth = gl_FragCoord.z;
#endif
    if (material.emissive.w >= 0.0 && material_cut(sample_material(uv0, uv1, in_color))) {
        discard;
    }
}
