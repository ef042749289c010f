// Level of detail of relief surfaces (surface.frag's RELIEF_LOD variants; Drobot section 1.4,
// Ki and Oh section 2.5). Per pixel, once before any trace (lod_begin):
// - the stop level: the height map's mip level under the pixel's footprint times LOD_FACTOR plus
//   LOD_BIAS; the pyramid traversal (pyramid.glsl, LOD_MEAN_PYRAMID variants) stops at its floor
//   and takes the node's plane as the hit, the plane's depth blended toward the next coarser
//   level by the fractional part, so detail fades continuously;
// - below LOD_AVERAGE_BELOW the stopping planes are the averaged pyramid's (binding 4), the
//   low-frequency surface, instead of the max pyramid's upper bounds (Ki and Oh);
// - the iteration budget from the view angle: parallax grows toward grazing views, so rays seen
//   from above get fewer steps, never fewer than the pyramid's levels (Drobot) or a quarter of
//   a linear search's samples;
// - a fade to plain normal mapping between LOD_FADE_START and LOD_FADE_END (world distance from
//   the eye); beyond the end nothing is traced.
#ifndef LOD_GLSL
#define LOD_GLSL

#include "interface.glsl"

// Ids: src/render/shader_interface/mod.rs. Values: src/scene/lod.rs.
layout(constant_id = SPEC_LOD_FACTOR) const float LOD_FACTOR = 1.0;
layout(constant_id = SPEC_LOD_BIAS) const float LOD_BIAS = 0.0;
layout(constant_id = SPEC_LOD_FADE_START) const float LOD_FADE_START = 0.0;
layout(constant_id = SPEC_LOD_FADE_END) const float LOD_FADE_END = 0.0;
layout(constant_id = SPEC_LOD_AVERAGE_BELOW) const uint LOD_AVERAGE_BELOW = 16;

#ifdef LOD_MEAN_PYRAMID
// The averaged height pyramid: level L holds the mean of the level-0 texels its texel covers.
// Variants whose material does not use it bind the max pyramid here and never read it.
layout(set = 0, binding = BINDING_HEIGHT_MEAN) uniform sampler2D height_mean;
#endif

// The pixel's stop level (floor and fraction) and fade, written by lod_begin. Globals, because
// the traversal reads them deep inside the method without a change to its signature.
int lod_stop = 0;
float lod_frac = 0.0;
float lod_fade = 0.0;

// log2 of the longer screen-space step of uv, in texels of level 0: the mip level a trilinear
// fetch would take. Needs uniform control flow (derivatives).
float lod_mip_level(vec2 uv) {
    vec2 dx = dFdx(uv) * height_size();
    vec2 dy = dFdy(uv) * height_size();
    return 0.5 * log2(max(max(dot(dx, dx), dot(dy, dy)), 1.0e-30));
}

void lod_begin(vec2 uv, float eye_distance) {
    float top = HEIGHT_INFO.z - 1.0;
    float level = clamp(lod_mip_level(uv) * LOD_FACTOR + LOD_BIAS, 0.0, top);
    lod_stop = int(floor(level));
    lod_frac = level - floor(level);
    lod_fade = 0.0;
    if (LOD_FADE_END > 0.0) {
        lod_fade = clamp((eye_distance - LOD_FADE_START) / (LOD_FADE_END - LOD_FADE_START), 0.0, 1.0);
    }
}

// The budget scaled by the view angle: all of it at grazing rays (dir.z -> 0), `floor_steps`
// looking straight down.
Budget lod_budget(Budget b, Ray ray) {
#if defined(LOD_MEAN_PYRAMID)
    uint floor_steps = 2u * uint(HEIGHT_INFO.z);
#elif defined(LOD_LINEAR_SEARCH)
    uint floor_steps = max(b.max_steps / 4u, 4u);
#else
    uint floor_steps = b.max_steps;
#endif
    floor_steps = min(floor_steps, b.max_steps);
    float n = mix(float(b.max_steps), float(floor_steps), clamp(ray.dir.z, 0.0, 1.0));
    b.max_steps = uint(ceil(n));
    return b;
}

#ifdef LOD_MEAN_PYRAMID
vec2 lod_level_size(int level) {
    return max(floor(height_size() / exp2(float(level))), vec2(1.0));
}

// Depth of the texel holding uv at `level`, of the averaged pyramid or (`mean` false) the max one.
float lod_level_depth(vec2 uv, int level, bool mean, float depth_scale) {
    vec2 size = lod_level_size(level);
    ivec2 texel = address_cell(floor(uv * size), size);
    float h = mean ? counted_texel(height_mean, texel, level).r : counted_texel(height_point, texel, level).r;
    return depth_scale * (1.0 - h);
}

// The level the traversal stops at instead of descending to `leaf`.
int lod_stop_level(int leaf) {
    return max(leaf, lod_stop);
}

// The depth of node `cell` at `level` as the traversal should see it: the max pyramid's `d_max`
// above the stop level; at the stop level the averaged (or max) plane blended toward the next
// coarser level's by the fraction, which is continuous with the next stop level at fraction 1.
float lod_node_depth(float d_max, vec2 cell, int level, int leaf, float depth_scale) {
    if (level != lod_stop || level <= leaf) {
        return d_max;
    }
    vec2 uv = (cell + 0.5) / lod_level_size(level);
    int above = min(level + 1, int(HEIGHT_INFO.z) - 1);
    bool mean = uint(level) < LOD_AVERAGE_BELOW;
    float here = mean ? lod_level_depth(uv, level, true, depth_scale) : d_max;
    return mix(here, lod_level_depth(uv, above, mean, depth_scale), lod_frac);
}
#endif

#endif
