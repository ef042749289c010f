#version 460
#extension GL_GOOGLE_include_directive : require
// The relaxed cone map's REDUCE kernel (see relaxed_cone.glsl): level L of the max pyramid and of
// the max pyramid of 1 - h, both from level L - 1.
layout(local_size_x = 8, local_size_y = 8) in;

#include "relaxed_cone.glsl"

void reduce() {
    uint level = params.level;
    uvec2 at = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(at, level_size(level)))) {
        return;
    }
    uvec2 fine = level_size(level - 1u);
    uvec2 first = at * 2u;
    uvec2 last = min(first + 1u, fine - 1u);
    vec2 top = vec2(0.0);
    for (uint y = first.y; y <= last.y; ++y) {
        for (uint x = first.x; x <= last.x; ++x) {
            uvec4 child = nodes[node_index(level - 1u, uvec2(x, y))];
            top = max(top, vec2(node_height(child), node_depth(child)));
        }
    }
    nodes[node_index(level, at)].xy = floatBitsToUint(top);
}

void main() {
    reduce();
}
