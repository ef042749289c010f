// The occluder pass's bounds, read by the relief surface variants before they trace
// (shaders/passes/occluders.frag): a fragment whose polygon lies behind the farthest depth the
// nearest opaque surface can reach is hidden whatever its trace finds, since a relief hit is
// never nearer than its polygon.
#ifndef OCCLUDERS_GLSL
#define OCCLUDERS_GLSL

layout(set = SET_OCCLUDERS, binding = BINDING_OCCLUDER_BOUNDS) uniform sampler2D occluder_bounds;
layout(constant_id = SPEC_OCCLUDER_TAPS) const uint OCCLUDER_TAPS = 0u;

// The frame's work counters beside the bounds (src/render/frame/work_counters.rs): per pixel of
// the targets, the relief fragments that survived the bounds and traced, their steps and their
// traces' texel fetches (heightfield.glsl counts those when the pipeline sets COUNT_FETCHES).
layout(set = SET_OCCLUDERS, binding = BINDING_WORK_COUNTS, std430) buffer WorkCounts {
    uint work_counts[];
};
layout(constant_id = SPEC_COUNT_WORK) const uint COUNT_WORK = 0u;

uint work_index() {
    ivec2 p = ivec2(gl_FragCoord.xy);
    return 3u * uint(p.y * textureSize(occluder_bounds, 0).x + p.x);
}

// Counts this fragment as traced (after the bounds let it through).
void count_traced_fragment() {
    if (COUNT_WORK != 0u) {
        atomicAdd(work_counts[work_index()], 1u);
    }
}

// Adds the trace's steps, and the fetches counted so far (the trace's: it is called right after
// it), to this pixel's counts.
void count_traced_steps(uint steps) {
    if (COUNT_WORK != 0u) {
        atomicAdd(work_counts[work_index() + 1u], steps);
        atomicAdd(work_counts[work_index() + 2u], height_fetches);
    }
}

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
