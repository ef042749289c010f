// The occluder pass's bounds, read by the relief surface variants before they trace
// (shaders/passes/occluders.frag): a fragment whose polygon lies behind the farthest depth the
// nearest opaque surface can reach is hidden whatever its trace finds, since a relief hit is
// never nearer than its polygon.
#ifndef OCCLUDERS_GLSL
#define OCCLUDERS_GLSL

layout(set = SET_OCCLUDERS, binding = BINDING_OCCLUDER_BOUNDS) uniform sampler2D occluder_bounds;
layout(constant_id = SPEC_OCCLUDER_TAPS) const uint OCCLUDER_TAPS = 0u;

// Whether every sample this fragment covers lies behind the occluders. Call it where every
// lane of the quad is still running (it takes a derivative).
bool behind_occluders() {
    // The polygon's nearest depth over the pixel: with MSAA its samples sit off the centre.
    float nearest = gl_FragCoord.z - fwidth(gl_FragCoord.z);
    if (OCCLUDER_TAPS == 0u) {
        return false;
    }
    ivec2 p = ivec2(gl_FragCoord.xy);
    float bound = texelFetch(occluder_bounds, p, 0).r;
    if (OCCLUDER_TAPS > 1u) {
        // The bounds hold pixel centres; a sample elsewhere in the pixel lies inside the square
        // of the eight around it, over which a plane's depth is at most their largest.
        ivec2 last = textureSize(occluder_bounds, 0) - 1;
        for (int dy = -1; dy <= 1; ++dy) {
            for (int dx = -1; dx <= 1; ++dx) {
                ivec2 q = clamp(p + ivec2(dx, dy), ivec2(0), last);
                bound = max(bound, texelFetch(occluder_bounds, q, 0).r);
            }
        }
    }
    return nearest > bound;
}

#endif
