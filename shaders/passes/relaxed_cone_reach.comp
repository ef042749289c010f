#version 460
#extension GL_GOOGLE_include_directive : require
// The relaxed cone map's REACH kernel (see relaxed_cone.glsl): each texel's four reaches, for rows
// [row0, row0 + rows).
layout(local_size_x = 8, local_size_y = 8) in;

#include "relaxed_cone.glsl"

// Whether a quadrant in `quadrants` still has a reach above d.
bool is_open(vec4 reaches, float d, uint quadrants) {
    return (quadrant_mask(greaterThan(reaches, vec4(d))) & quadrants) != 0u;
}

// The search's node `at` on `level` of a region, as a stack entry with its distance from box(q),
// or NO_BOUND when it holds no texel lower than the searched one (1 - min below g) or lies in no
// quadrant whose reach is still above its distance.
uvec2 reach_kid(ivec2 axes, uint level, uvec2 at, Node q, float g, vec4 reaches) {
    uvec2 none = uvec2(0u, NO_BOUND);
    // One component, not the node: a whole node costs four loads on lavapipe.
    if (uintBitsToFloat(nodes[node_index(level, at)].y) < g) {
        return none;
    }
    Node rect = region_rect(axes, level, at);
    float d = rect_gap(q, rect);
    return is_open(reaches, d, quadrants_between(q, rect)) ? entry(level, at.x, at.y, d) : none;
}

// A u16 reach count: a quadrant nothing lowered keeps the cap's full count, as on the CPU; the
// others are stepped down past f32 rounding, then rounded down.
uint reach_units(float r, float cap) {
    float units = r >= cap ? REACH_MAX_UNITS
        : floor(step_down(r / params.reach_unit, REACH_DOWN));
    return uint(min(units, REACH_MAX_UNITS));
}

void reach_texel() {
    uvec2 p = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y + params.row0);
    if (p.x >= params.width || p.y >= params.height) {
        return;
    }
    uint index = p.y * params.width + p.x;
    float hq = uintBitsToFloat(nodes[index].x);
    // As the CPU: the inverted level holds 1 - h rounded like this, so h < hq gives 1 - h >= g.
    float g = 1.0 - hq;
    float cap = params.reach_cap;
    vec4 reaches = vec4(cap);
    Node q = node_rect(0u, p, vec2(0.0));
    for (int r = 0; r < 9; ++r) {
        ivec2 axes = region_axes(r);
        uvec2 root = reach_kid(axes, params.top, uvec2(0u), q, g, reaches);
        int sp = 0;
        if (root.y != NO_BOUND) {
            search_stack[0] = root;
            sp = 1;
        }
        while (sp > 0) {
            --sp;
            uvec2 e = search_stack[sp];
            float d = uintBitsToFloat(e.y);
            uint level = entry_level(e.x);
            uvec2 at = entry_at(e.x);
            uint quadrants = quadrants_between(q, region_rect(axes, level, at));
            if (!is_open(reaches, d, quadrants)) {
                continue;
            }
            if (level == 0u) {
                if (uintBitsToFloat(nodes[node_index(0u, at)].x) < hq) {
                    reaches = mix(reaches, min(reaches, vec4(d)), quadrant_bits(quadrants));
                }
                continue;
            }
            uint child = level - 1u;
            uvec2 size = level_size(child);
            uvec2 xs = axis_children(axes.x, child, at.x, size.x, params.width);
            uvec2 ys = axis_children(axes.y, child, at.y, size.y, params.height);
            uvec2 none = uvec2(0u, NO_BOUND);
            uvec2 e0 = reach_kid(axes, child, uvec2(xs.x, ys.x), q, g, reaches);
            uvec2 e1 = xs.x == xs.y ? none : reach_kid(axes, child, uvec2(xs.y, ys.x), q, g, reaches);
            uvec2 e2 = ys.x == ys.y ? none : reach_kid(axes, child, uvec2(xs.x, ys.y), q, g, reaches);
            uvec2 e3 = xs.x == xs.y || ys.x == ys.y ? none
                : reach_kid(axes, child, uvec2(xs.y, ys.y), q, g, reaches);
            push_children(sp, e0, e1, e2, e3);
        }
    }
    nodes[index].zw = uvec2(reach_units(reaches.x, cap) | (reach_units(reaches.y, cap) << 16),
                            reach_units(reaches.z, cap) | (reach_units(reaches.w, cap) << 16));
}

void main() {
    reach_texel();
}
