#version 460
#extension GL_GOOGLE_include_directive : require
// The relaxed cone map's REACH_REDUCE kernel (see relaxed_cone.glsl): level L of the reaches, per
// node and quadrant the least reach under it.
layout(local_size_x = 8, local_size_y = 8) in;

#include "relaxed_cone.glsl"

void reach_reduce() {
    uint level = params.level;
    uvec2 at = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(at, level_size(level)))) {
        return;
    }
    uvec2 fine = level_size(level - 1u);
    uvec2 first = at * 2u;
    uvec2 last = min(first + 1u, fine - 1u);
    uvec4 least = uvec4(0xffffu);
    for (uint y = first.y; y <= last.y; ++y) {
        for (uint x = first.x; x <= last.x; ++x) {
            uint child = node_index(level - 1u, uvec2(x, y));
            uvec2 words = nodes[child].zw;
            least = min(least, uvec4(words.x & 0xffffu, words.x >> 16, words.y & 0xffffu,
                                     words.y >> 16));
        }
    }
    uint node = node_index(level, at);
    nodes[node].zw = uvec2(least.x | (least.y << 16), least.z | (least.w << 16));
}

void main() {
    reach_reduce();
}
