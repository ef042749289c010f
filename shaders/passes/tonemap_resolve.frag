#version 460
#extension GL_GOOGLE_include_directive : require
// The tone-mapping pass of a multisampled frame, which is also its resolve: every sample of the
// pixel's radiance (of each of its scale x scale texels when supersampled) is tone mapped, then
// they are averaged. Averaging radiance first, as a hardware resolve does, lets one sample far
// beyond white outweigh its dark neighbours, and the edge between them stays jagged.

#include "tone_curves.glsl"

layout(set = 0, binding = 0) uniform sampler2DMS hdr;

// Exposure, curve, supersampling scale and samples: `ToneMapPush` in interface.glsl.
layout(push_constant, std430) uniform ToneMapPush {
    TONE_MAP_PUSH_FIELDS
} tm;

layout(location = 0) out vec4 out_color;

void main() {
    ivec2 corner = ivec2(gl_FragCoord.xy) * int(tm.scale);
    vec3 sum = vec3(0.0);
    float alpha = 0.0;
    for (int y = 0; y < int(tm.scale); ++y) {
        for (int x = 0; x < int(tm.scale); ++x) {
            for (int s = 0; s < int(tm.samples); ++s) {
                vec4 radiance = texelFetch(hdr, corner + ivec2(x, y), s);
                sum += tone_map(radiance.rgb, tm.exposure, tm.curve);
                alpha += radiance.a;
            }
        }
    }
    float n = float(tm.scale * tm.scale * tm.samples);
    out_color = vec4(sum / n, alpha / n);
}
