#version 460
#extension GL_GOOGLE_include_directive : require
// The relaxed cone map's RELAXED kernel (see relaxed_cone.glsl): each texel's ratio and bound
// height, for rows [row0, row0 + rows).
layout(local_size_x = 8, local_size_y = 8) in;

#include "relaxed_cone.glsl"

// The least reach, in u-texels, over the quadrants in `mask` of a node.
float least_reach(uvec4 node, uint mask) {
    uvec2 words = node.zw;
    uvec4 quadrants = uvec4(words.x & 0xffffu, words.x >> 16, words.y & 0xffffu, words.y >> 16);
    uvec4 counted = mix(uvec4(0xffffu), quadrants, quadrant_bits(mask));
    uint least = min(min(counted.x, counted.y), min(counted.z, counted.w));
    return mask == 0u ? 0.0 : float(least) * params.reach_unit;
}

// The relaxed value of node `at` on `level` of a region, or NO_BOUND when it holds nothing higher
// than hp or cannot beat `best`; the value without reach goes first, as a cheaper bound. A node's
// quadrants hold those of every texel under it and its reaches are their least, so its value
// bounds theirs from below.
uvec2 relaxed_kid(ivec2 axes, uint level, uvec2 at, Node prect, vec2 centre, float hp,
                  float best) {
    uvec2 none = uvec2(0u, NO_BOUND);
    uvec4 node = nodes[node_index(level, at)];
    float h = node_height(node);
    if (!(h > hp)) {
        return none;
    }
    Node rect = region_rect(axes, level, at);
    float extra = region_real(axes) ? least_reach(node, quadrants_between(prect, rect)) : 0.0;
    float b = cone_map_value(centre, rect.lo, rect.hi, h - hp, extra);
    return b < best ? entry(level, at.x, at.y, b) : none;
}

void relaxed_texel() {
    uvec2 p = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y + params.row0);
    if (p.x >= params.width || p.y >= params.height) {
        return;
    }
    uint index = p.y * params.width + p.x;
    float hp = node_height(nodes[index]);
    uint top = params.top;
    float top_height = node_height(nodes[params.offsets[top]]);
    float best = CONE_RATIO_MAX;
    vec2 centre = vec2(p) + 0.5;
    Node prect = node_rect(0u, p, vec2(0.0));
    // Seed with the 8 neighbours, genuine candidates (the map's own texels, or their copies in the
    // next tiles), so most of the pyramid is pruned from the first node on.
    for (int n = 0; n < 9 && top_height > hp; ++n) {
        ivec2 q = ivec2(p) + ivec2(n % 3 - 1, n / 3 - 1);
        ivec2 size = ivec2(params.width, params.height);
        ivec2 wrapped = ivec2(q.x < 0 ? q.x + size.x : (q.x >= size.x ? q.x - size.x : q.x),
                              q.y < 0 ? q.y + size.y : (q.y >= size.y ? q.y - size.y : q.y));
        if (n == 4 || (params.repeat_address == 0u && q != wrapped)) {
            continue;
        }
        ivec2 axes = ivec2(sign(q - wrapped));
        uvec2 e = relaxed_kid(axes, 0u, uvec2(wrapped), prect, centre, hp, best);
        best = e.y != NO_BOUND ? uintBitsToFloat(e.y) : best;
    }
    for (int r = 0; r < 9 && top_height > hp; ++r) {
        ivec2 axes = region_axes(r);
        uvec2 root = relaxed_kid(axes, top, uvec2(0u), prect, centre, hp, best);
        int sp = 0;
        if (root.y != NO_BOUND) {
            search_stack[0] = root;
            sp = 1;
        }
        while (sp > 0) {
            --sp;
            uvec2 e = search_stack[sp];
            float bound = uintBitsToFloat(e.y);
            if (!(bound < best)) {
                continue;
            }
            uint level = entry_level(e.x);
            uvec2 at = entry_at(e.x);
            if (level == 0u) {
                best = bound;
                continue;
            }
            uint child = level - 1u;
            uvec2 size = level_size(child);
            uvec2 xs = axis_children(axes.x, child, at.x, size.x, params.width);
            uvec2 ys = axis_children(axes.y, child, at.y, size.y, params.height);
            uvec2 none = uvec2(0u, NO_BOUND);
            uvec2 e0 = relaxed_kid(axes, child, uvec2(xs.x, ys.x), prect, centre, hp, best);
            uvec2 e1 = xs.x == xs.y ? none
                : relaxed_kid(axes, child, uvec2(xs.y, ys.x), prect, centre, hp, best);
            uvec2 e2 = ys.x == ys.y ? none
                : relaxed_kid(axes, child, uvec2(xs.x, ys.y), prect, centre, hp, best);
            uvec2 e3 = xs.x == xs.y || ys.x == ys.y ? none
                : relaxed_kid(axes, child, uvec2(xs.y, ys.y), prect, centre, hp, best);
            push_children(sp, e0, e1, e2, e3);
        }
    }
    float ratio = best < CONE_RATIO_MAX ? step_down(best, STEP_DOWN) : CONE_RATIO_MAX;
    cone_map[index] = vec2(ratio, hp);
}

void main() {
    relaxed_texel();
}
