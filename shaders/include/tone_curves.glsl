// The tone curves: exposure, then none (clamped), Khronos PBR Neutral or ACES. The CPU applies
// the same curves (ToneMap::apply in src/render/kit/tone_curves.rs), and the tests compare the two.
#ifndef TONE_CURVES_GLSL
#define TONE_CURVES_GLSL

#include "interface.glsl"

// Khronos PBR Neutral: colours below the compression start pass unchanged (less a small toe
// that lifts the darkest values' offset), brighter ones are compressed toward 1 along their hue
// and desaturated in proportion to the compression.
vec3 pbr_neutral(vec3 c) {
    const float start = 0.8 - 0.04;
    const float desaturation = 0.15;
    float low = min(c.r, min(c.g, c.b));
    float offset = low < 0.08 ? low - 6.25 * low * low : 0.04;
    c -= offset;
    float peak = max(c.r, max(c.g, c.b));
    if (peak < start) {
        return c;
    }
    float d = 1.0 - start;
    float mapped = 1.0 - d * d / (peak + d - start);
    c *= mapped / peak;
    float g = 1.0 - 1.0 / (desaturation * (peak - mapped) + 1.0);
    return mix(c, vec3(mapped), g);
}

// ACES filmic, Narkowicz's rational fit.
vec3 aces(vec3 c) {
    return clamp((c * (2.51 * c + 0.03)) / (c * (2.43 * c + 0.59) + 0.14), 0.0, 1.0);
}

vec3 tone_map(vec3 radiance, float exposure, uint curve) {
    // Infinite radiance saturates; NaN (a degenerate shading input) is drawn black, never spread.
    vec3 c = radiance * exposure;
    c = mix(c, vec3(65504.0), vec3(isinf(c)));
    c = mix(c, vec3(0.0), vec3(isnan(c)));
    c = max(c, vec3(0.0));
    if (curve == TONE_CURVE_PBR_NEUTRAL) {
        c = pbr_neutral(c);
    } else if (curve == TONE_CURVE_ACES) {
        c = aces(c);
    }
    return clamp(c, 0.0, 1.0);
}

#endif
