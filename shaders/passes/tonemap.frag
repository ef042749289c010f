#version 460
#extension GL_GOOGLE_include_directive : require
// The tone-mapping pass: the frame's linear radiance (the scene passes' half-float target), scaled
// by the exposure and mapped into [0, 1] by the chosen curve. The target is an sRGB image, so the
// hardware encodes the result once, on write; nothing else in relief encodes sRGB.

#include "tone_curves.glsl"

layout(set = 0, binding = 0) uniform sampler2D hdr;

// Exposure, curve, supersampling scale and samples: `ToneMapPush` in interface.glsl.
layout(push_constant, std430) uniform ToneMapPush {
    TONE_MAP_PUSH_FIELDS
} tm;

layout(location = 0) out vec4 out_color;

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
            sum += tone_map(radiance.rgb, tm.exposure, tm.curve);
            alpha += radiance.a;
        }
    }
    float n = float(tm.scale * tm.scale);
    out_color = vec4(sum / n, alpha / n);
}
