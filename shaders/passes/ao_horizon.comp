#version 460
// The AO map by Drobot's fast horizon approximation (section 1.6.1 over the horizon queries of
// 1.5.2, Listing 1.4): one invocation per texel. For each of `directions` evenly spaced azimuths
// (the reference's midpoints, or turned by a per-texel hash when `rotated`), the horizon is the
// steepest elevation toward samples at geometrically growing distances, far samples reading the
// coarser levels of the max pyramid (so log n samples see the whole profile, as in the paper);
// the slice integral about the normal is then closed-form (ao.glsl). Near samples read level 0
// bilinearly (the true surface), so small features nearby are not inflated to pyramid boxes.
// A dispatch may cover a rectangle of the map only (`origin`, `end`): a texel's value depends on
// the texel and the heights alone, so a partial rebuild equals a full one where it writes.
//
// Invariants: a flat field gives exactly 1 (every sample equals the texel's own height, so every
// slope is 0 and every slice's occlusion 0); values are clamped to [0, 1]; no loop is unbounded
// (MAX_SAMPLES per azimuth).
#extension GL_GOOGLE_include_directive : require
#include "ao.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

const float TAU = 6.28318530718;
const int MAX_SAMPLES = AO_HORIZON_MAX_SAMPLES;

// The fields: AoHorizonParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    AO_HORIZON_PARAMS_FIELDS
} params;

// A per-texel number in [0, 1) (PCG hash), for the rotated variant.
float texel_hash(ivec2 t) {
    uint v = uint(t.x) * 747796405u + uint(t.y) * 2891336453u + 12345u;
    v = ((v >> ((v >> 28u) + 4u)) ^ v) * 277803737u;
    v = (v >> 22u) ^ v;
    return float(v >> 8u) / 16777216.0;
}

// The bilinear surface at uv point p (level 0, the map's addressing).
float bilinear_height(vec2 p, bool repeat) {
    vec2 g = p * vec2(params.size) - 0.5;
    vec2 g0 = floor(g);
    vec2 f = g - g0;
    ivec2 t = ivec2(g0);
    float h00 = ao_texel(t, 0, repeat);
    float h10 = ao_texel(t + ivec2(1, 0), 0, repeat);
    float h01 = ao_texel(t + ivec2(0, 1), 0, repeat);
    float h11 = ao_texel(t + ivec2(1, 1), 0, repeat);
    // a + f (b - a): equal corners give exactly their value, which keeps a flat field exact.
    float bottom = h00 + f.x * (h10 - h00);
    float top = h01 + f.x * (h11 - h01);
    return bottom + f.y * (top - bottom);
}

// The highest height near uv point p as seen from `distance` texels away: level 0's bilinear
// surface close by, the max node of a coarser pyramid level farther out. Beyond a clamped map's
// edge the surface is the border's extension, which level 0 gives exactly; a border node of the
// pyramid would also hold the interior behind the border, far higher than the extension.
float horizon_sample(vec2 p, float distance, int levels, bool repeat) {
    int level = clamp(int(floor(log2(distance))) - params.level_bias, 0, levels - 1);
    bool outside = any(lessThan(p, vec2(0.0))) || any(greaterThan(p, vec2(1.0)));
    if (level == 0 || (outside && !repeat)) {
        return bilinear_height(p, repeat);
    }
    ivec2 size = textureSize(heights, level);
    return ao_texel(ivec2(floor(p * vec2(size))), level, repeat);
}

// The slope of the bilinear surface leaving texel t (height hp) along uv direction dir: the cell
// on that side's derivative at its corner. The exact horizon includes this limit at distance 0,
// which matters beside steep cells (a wall's foot); samples a texel or more away miss it.
float tangent(ivec2 t, float hp, vec2 dir, bool repeat) {
    vec2 rate = abs(dir) * vec2(params.size);
    ivec2 side = ivec2(sign(dir));
    float rise = rate.x * (ao_texel(t + ivec2(side.x, 0), 0, repeat) - hp)
               + rate.y * (ao_texel(t + ivec2(0, side.y), 0, repeat) - hp);
    return params.depth_scale * rise;
}

// The horizon tangent along uv unit direction dir from the texel centre p (height hp).
float horizon(vec2 p, float hp, vec2 dir, int levels, bool repeat) {
    float texel_uv = 1.0 / float(max(params.size.x, params.size.y));
    float tau = max(tangent(ivec2(floor(p * vec2(params.size))), hp, dir, repeat), 0.0);
    float d = params.first_distance;
    for (int m = 0; m < MAX_SAMPLES && d * texel_uv <= params.reach_uv; ++m) {
        float x = d * texel_uv;
        float h = horizon_sample(p + x * dir, d, levels, repeat);
        tau = max(tau, params.depth_scale * (h - hp) / x);
        d *= params.growth;
    }
    return tau;
}

void main() {
    ivec2 t = ivec2(gl_GlobalInvocationID.xy) + params.origin;
    if (any(greaterThanEqual(t, min(params.end, params.size)))) {
        return;
    }
    bool repeat = params.repeat_address != 0u;
    int levels = textureQueryLevels(heights);
    vec3 n = ao_normal(t, params.size, params.depth_scale, repeat);
    float hp = ao_texel(t, 0, repeat);
    vec2 p = (vec2(t) + 0.5) / vec2(params.size);
    float turn = params.rotated != 0u ? texel_hash(t) : 0.5;
    float occlusion = 0.0;
    for (uint k = 0u; k < params.directions; ++k) {
        float phi = TAU * (float(k) + turn) / float(params.directions);
        vec2 dir = vec2(cos(phi), sin(phi));
        occlusion += ao_slice_occlusion(n, dir, horizon(p, hp, dir, levels, repeat));
    }
    float ao = clamp(1.0 - occlusion / float(params.directions), 0.0, 1.0);
    imageStore(ao_out, t, vec4(ao));
}
