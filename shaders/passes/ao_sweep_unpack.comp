#version 460
#extension GL_GOOGLE_include_directive : require
// Level 0 of the height image into `field` for the exact-horizon sweeps (see ao_sweep.glsl).
layout(local_size_x = 64) in;

#include "ao_sweep.glsl"

void unpack() {
    // Dispatched as rows of 64-texel groups (x) by rows (y), within the group count limits.
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (t.x >= params.size.x || t.y >= params.size.y) {
        return;
    }
    field[t.y * params.size.x + t.x] = texelFetch(heights, t, 0).r;
}

void main() {
    unpack();
}
