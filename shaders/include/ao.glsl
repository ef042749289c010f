// Shared by the AO map passes (ao_horizon.comp, ao_sweep.comp): the height fetch with the map's
// addressing, the texel normal and the closed-form occlusion of one azimuth slice, exactly as
// docs/conventions.md ("Lights, shadows and ambient occlusion") and heightfield::ambient_occlusion define them.
//
// Bindings every AO pass shares: the height image (level 0 and, for the horizon pass, its max
// pyramid in the mips; read with texelFetch, so the sampler's filter and addressing play no part)
// and the AO map written as r32f.
#ifndef AO_GLSL
#define AO_GLSL

const float AO_HALF_PI = 1.57079632679;

#include "interface.glsl"

layout(set = 0, binding = BINDING_AO_HEIGHTS) uniform sampler2D heights;
layout(set = 0, binding = BINDING_AO_MAP, r32f) uniform writeonly image2D ao_out;

// Texel index k of an axis of n texels under the map's addressing: wrapped (repeat) or clamped
// (the border extends outward). GLSL leaves % of negatives undefined, hence the correction.
int ao_address(int k, int n, bool repeat) {
    if (repeat) {
        int m = k % n;
        return m < 0 ? m + n : m;
    }
    return clamp(k, 0, n - 1);
}

// The stored height of texel (i, j) of mip `level`, addressing applied at that level's size.
float ao_texel(ivec2 t, int level, bool repeat) {
    ivec2 size = textureSize(heights, level);
    return texelFetch(heights, ivec2(ao_address(t.x, size.x, repeat), ao_address(t.y, size.y, repeat)), level).r;
}

// The unit normal at a texel in (u, v, up) units from its four neighbours' heights:
// (-s dh/du, -s dh/dv, 1) normalised, with central differences of the texel values. A zero gradient gives exactly (0, 0, 1), so a flat
// field's AO comes out exactly 1.
vec3 ao_normal_of(float left, float right, float down, float up, ivec2 size, float s) {
    float dhdu = (right - left) * float(size.x) * 0.5;
    float dhdv = (up - down) * float(size.y) * 0.5;
    vec2 g = vec2(-s * dhdu, -s * dhdv);
    if (g == vec2(0.0)) {
        return vec3(0.0, 0.0, 1.0);
    }
    return normalize(vec3(g, 1.0));
}

// ao_normal_of with the neighbours fetched from the height image.
vec3 ao_normal(ivec2 t, ivec2 size, float s, bool repeat) {
    return ao_normal_of(ao_texel(t - ivec2(1, 0), 0, repeat), ao_texel(t + ivec2(1, 0), 0, repeat),
                        ao_texel(t - ivec2(0, 1), 0, repeat), ao_texel(t + ivec2(0, 1), 0, repeat),
                        size, s);
}

// What one azimuth slice loses: 1 - 2 * integral from t0 to pi/2 of (n_z sin t + c cos t) cos t dt,
// t0 = max(horizon, edge of the normal's hemisphere), c = n . (cos phi, sin phi, 0). The AO is
// 1 - (weighted mean of this over azimuths): 0 for an open slice about an upright normal, so a
// flat field gives exactly 1 whatever the weights' rounding.
float ao_slice_occlusion(vec3 n, vec2 dir, float tau) {
    float c = dot(n.xy, dir);
    float t0 = max(atan(max(tau, 0.0)), atan(-c, n.z));
    float cos_t0 = cos(t0);
    return 1.0 - n.z * cos_t0 * cos_t0 - c * (AO_HALF_PI - t0) + c * sin(2.0 * t0) * 0.5;
}

#endif
