#version 460
// The tone-mapping pass: the frame's linear radiance (the scene passes' half-float target), scaled
// by the exposure and mapped into [0, 1] by the chosen curve. The target is an sRGB image, so the
// hardware encodes the result once, on write; nothing else in relief encodes sRGB.
// The curves mirror src/render/frame/tonemap.rs (ToneMap::apply), which the tests compare with.

layout(set = 0, binding = 0) uniform sampler2D hdr;

layout(push_constant) uniform ToneMapPush {
    // 2^EV.
    float exposure;
    // 0: none (clamped), 1: Khronos PBR Neutral, 2: ACES (Narkowicz's fit of the RRT and ODT).
    uint curve;
    // Supersampling: the radiance is `scale` times the frame's size along each axis.
    uint scale;
} tm;

layout(location = 0) out vec4 out_color;

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

vec3 tone_map(vec3 radiance) {
    // Infinite radiance saturates; NaN (a degenerate shading input) is drawn black, never spread.
    vec3 c = radiance * tm.exposure;
    c = mix(c, vec3(65504.0), vec3(isinf(c)));
    c = mix(c, vec3(0.0), vec3(isnan(c)));
    c = max(c, vec3(0.0));
    if (tm.curve == 1u) {
        c = pbr_neutral(c);
    } else if (tm.curve == 2u) {
        c = aces(c);
    }
    return clamp(c, 0.0, 1.0);
}

void main() {
    // Supersampled: the mean of the pixel's scale x scale radiance texels (a box over exactly its
    // footprint), each tone mapped first, so that a highlight far beyond white weighs as white
    // and does not swallow the edge it sits on.
    ivec2 corner = ivec2(gl_FragCoord.xy) * int(tm.scale);
    vec3 sum = vec3(0.0);
    float alpha = 0.0;
    for (int y = 0; y < int(tm.scale); ++y) {
        for (int x = 0; x < int(tm.scale); ++x) {
            vec4 radiance = texelFetch(hdr, corner + ivec2(x, y), 0);
            sum += tone_map(radiance.rgb);
            alpha += radiance.a;
        }
    }
    float n = float(tm.scale * tm.scale);
    out_color = vec4(sum / n, alpha / n);
}
