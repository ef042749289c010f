#version 460
#extension GL_GOOGLE_include_directive : require
// The exact-horizon AO map from the sweeps' sums (see ao_sweep.glsl): ao = clamp(1 - accum, 0, 1).
layout(local_size_x = 64) in;

#include "ao_sweep.glsl"

void resolve() {
    // Dispatched as rows of 64-texel groups (x) by rows (y), within the group count limits.
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (t.x >= params.size.x || t.y >= params.size.y) {
        return;
    }
    float ao = clamp(1.0 - accum[t.y * params.size.x + t.x], 0.0, 1.0);
    imageStore(ao_out, t, vec4(ao));
}

void main() {
    resolve();
}
