#version 460
// The deferred frame's lighting pass: once the scene is drawn, every pixel a deferred surface
// variant wrote (surface.frag with DEFERRED) is lit here, once: the ambient or image-based
// light, and each punctual light with its shadow-map lookup and the height field's own shadow
// the surface pass traced. The radiance already holds the surface's emission; the light adds
// to it. Pixels that nothing deferred drew (the sky, cell complexes) are left as they are.
#extension GL_GOOGLE_include_directive : require
#ifdef TRACED_SHADOWS
#extension GL_EXT_ray_query : require
#endif
#define PLAIN_SURFACE
#include "conventions.glsl"
#include "numeric.glsl"
#include "bindings.glsl"
#include "lighting.glsl"
#include "punctual.glsl"
#include "scene_shadows.glsl"
#include "environment_light.glsl"
#include "direct_light.glsl"
#include "octahedral.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

#ifdef TRACED_SHADOWS
// Ray-traced shadows (lighting.comp:traced): every light that casts shadows is tested by rays
// through the scene's acceleration structure (set 2, src/render/traced) instead of shadow maps
// and the height field's own walk, the receiver's own relief solid included.
// The fields: TracedLightingParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform TracedLightingParams {
    TRACED_LIGHTING_PARAMS_FIELDS
} traced;
#define HEIGHT_INFO traced.height_info
layout(set = 2, binding = BINDING_HEIGHT_POINT) uniform sampler2D height_point;
layout(set = 2, binding = BINDING_HEIGHT_LINEAR) uniform sampler2D height_linear;
layout(set = 2, binding = BINDING_OCCLUSION_SCENE) uniform accelerationStructureEXT scene;
#include "heightfield.glsl"
#include "relief_prism.glsl"
layout(set = 2, binding = BINDING_OCCLUSION_PRISMS, std430) readonly buffer Prisms {
    PrismRecord prisms[];
};
#include "traced_query.glsl"
#include "light_rays.glsl"

// The share of light i's rays from p that reach it (light_rays.glsl's samples, as the exact
// reference casts them: each leaves p at the receiver offset along itself).
float traced_visibility(int i, vec3 p) {
    LightCone cone = light_cone(i, p);
    if (!cone.reachable) {
        return 1.0;
    }
    uint n = cone.half_angle > 0.0 ? max(uint(traced.rays.y), 1u) : 1u;
    float offset = traced.rays.x;
    uint tested = 0u;
    uint steps = 0u;
    bool capped = false;
    uint open = 0u;
    for (uint j = 0u; j < n; ++j) {
        for (uint k = 0u; k < n; ++k) {
            vec3 dir;
            float reach = light_ray(cone, p, k, j, n, dir) - offset;
            if (reach <= 0.0 || !segment_blocked(p + dir * offset, 0.0, dir, reach, tested, steps, capped)) {
                open += 1u;
            }
        }
    }
    return float(open) / float(n * n);
}
#endif

layout(set = 1, binding = BINDING_LIGHTING_RADIANCE, rgba16f) uniform image2D radiance;
// Albedo (rgb) and ambient occlusion (a): the G-buffer's material channel.
layout(set = 1, binding = BINDING_LIGHTING_MATERIAL, rgba16f) uniform readonly image2D material;
// Motion (xy) and the shadow share (z), which only the lights can tell: written here.
layout(set = 1, binding = BINDING_LIGHTING_MOTION, rgba16f) uniform image2D motion;
// The shaded point (xyz, world) and 1 + its depth below the relief's top plane (w; 0: nothing
// deferred drawn here).
layout(set = 1, binding = BINDING_LIGHTING_POINT, rgba32f) uniform readonly image2D shading_point;
// Shading normal, polygon plane, polygon normal (octahedral), roughness and metallic.
layout(set = 1, binding = BINDING_LIGHTING_FRAME, rgba32ui) uniform readonly uimage2D shading_frame;
// The height field's own shadow toward each of the first four lights.
layout(set = 1, binding = BINDING_LIGHTING_SELF_SHADOW, rgba8) uniform readonly image2D self_shadow;

void main() {
    ivec2 p = ivec2(gl_GlobalInvocationID.xy);
    if (any(greaterThanEqual(p, imageSize(radiance)))) {
        return;
    }
    vec4 point = imageLoad(shading_point, p);
    if (point.w < 0.5) {
        return;
    }
    vec3 world = point.xyz;
    float lift = point.w - 1.0;
    uvec4 bits = imageLoad(shading_frame, p);
    vec3 normal = unpack_direction(bits.x);
    vec3 face = unpack_direction(bits.y);
    vec3 n = unpack_direction(bits.z);
    vec2 rough_metal = unpackUnorm2x16(bits.w);
    vec4 albedo_ao = imageLoad(material, p);
    vec4 selfs = imageLoad(self_shadow, p);
    vec3 v = -view_ray_dir(world);

    vec3 color = ambient_light(albedo_ao.rgb, rough_metal.x, rough_metal.y, normal, v, albedo_ao.a);
    DirectSum direct = DirectSum(vec3(0.0), 0.0, 0.0);
    for (int i = 0; i < min(frame.counts.x, MAX_LIGHTS); ++i) {
        float attenuation;
        vec3 l = light_toward(i, world, attenuation);
        if (!(dot(normal, l) > 0.0 && attenuation > 0.0)) {
            continue;
        }
        float lit;
#ifdef TRACED_SHADOWS
        if (frame.lights[i].color.w > 0.5) {
            lit = traced_visibility(i, world);
        } else
#endif
        {
            float lit_map = scene_shadow(i, map_shadow_point(world, n, l, lift), face, l);
            float lit_self = i < DEFERRED_SELF_SHADOW_LIGHTS ? selfs[i] : 1.0;
            lit = lit_map * lit_self;
        }
        add_direct_light(direct, i, attenuation, lit, albedo_ao.rgb, rough_metal.x,
                         rough_metal.y, normal, v, l);
    }
    vec4 emitted = imageLoad(radiance, p);
    imageStore(radiance, p, vec4(emitted.rgb + color + direct.radiance, emitted.a));
    vec4 moved = imageLoad(motion, p);
    imageStore(motion, p, vec4(moved.xy, direct_lit_share(direct), moved.w));
}
