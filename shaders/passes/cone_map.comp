#version 460
#extension GL_GOOGLE_include_directive : require
// The conservative cone map on the GPU (heightfield::cone_map, "Conservative cone"): per texel p
// of the bilinear bound's box surface (level 0 of `pyramid`, computed exactly on the CPU),
//   c(p) = min over texels q with h(q) > h(p) of dist(p_c, box(q)) / (h(q) - h(p)),
// distances in uv between p's centre and q's closed box, over the 3x3 tiles around the map under
// Repeat (farther tiles are at least 1 uv away while the global maximum always has a copy within
// sqrt(0.5) uv, so they never hold the minimum) and over the map alone under Clamp (the border's
// copies are never nearer than the border texels). Capped at CONE_RATIO_MAX.
//
// Two modes, chosen per dispatch by params.mode:
//  REDUCE: level L of the max pyramid (buffer_pyramid.glsl) from level L - 1.
//  CONE (MODE_SEARCH): one invocation per texel of rows [row0, row0 + rows): the best seeded with the 8
//    neighbours, then a depth-first search of each tile's pyramid, lowest-bound child first,
//    skipping every node whose bound (its rectangle's distance over its maximum's rise) is no
//    lower than the best found. The search itself is
//    exact; only the arithmetic is f32.
//
// Rounding (the guarantee): every candidate's value is computed in f32 with relative error at
// most EPS_ULPS units of 2^-23 under the Vulkan precision rules (sqrt about 5 ULP, division
// 2.5 ULP, the rest correctly rounded; see cone_map_value). The minimum M of the computed values
// is then stepped down by STEP_DOWN ulps, more than that error, so the stored ratio is never
// above the exact minimum (a node is skipped only when its computed bound is >= M, and its true
// bound is at least that bound over 1 + error) and never below it by more than
// (EPS_ULPS + STEP_DOWN) * 2^-23, under 2^-15 relative (render::cone_map_pass states it, the
// tests check it against the CPU builder).
layout(local_size_x = 8, local_size_y = 8) in;

// MODE_REDUCE, MODE_SEARCH (CONE above), MAX_LEVELS and the bindings.
#include "interface.glsl"

// All pyramid levels back to back, level 0 (the bound heights, width x height) first.
layout(set = 0, binding = BINDING_SEARCH_PYRAMID, std430) buffer Pyramid {
    float pyramid[];
};

// Per texel of level 0: the ratio and the bound height (MapData's two channels), row-major.
layout(set = 0, binding = BINDING_SEARCH_MAP, std430) writeonly buffer ConeMap {
    vec2 cone_map[];
};

// The fields: ConeMapParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    CONE_MAP_PARAMS_FIELDS
} params;

// Reads and writes `pyramid` above.
#include "buffer_pyramid.glsl"
// Values, node rectangles and stack entries (needs `params`).
#include "cone_search.glsl"

uvec2 level_size(uint level) {
    return pyramid_level_size(uvec2(params.width, params.height), level);
}

void reduce() {
    uint level = params.level;
    pyramid_reduce(uvec2(params.width, params.height), level, params.offsets[level - 1u],
                   params.offsets[level], gl_GlobalInvocationID.xy);
}

// Child (x, y) of `level` as a stack entry, or NO_BOUND when it holds nothing higher than hp or
// its bound cannot beat `best`.
uvec2 kid(uint level, uvec2 at, uvec2 size, vec2 tile, vec2 centre, float hp, float best) {
    float h = pyramid[params.offsets[level] + at.y * size.x + at.x];
    if (!(h > hp)) {
        return uvec2(0u, NO_BOUND);
    }
    Node n = node_rect(level, at, tile);
    float b = cone_map_value(centre, n.lo, n.hi, h - hp, 0.0);
    return b < best ? entry(level, at.x, at.y, b) : uvec2(0u, NO_BOUND);
}

void cone() {
    uvec2 p = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y + params.row0);
    if (p.x >= params.width || p.y >= params.height) {
        return;
    }
    uint index = p.y * params.width + p.x;
    float hp = pyramid[index];
    uint top = params.top;
    float top_height = pyramid[params.offsets[top]];
    float best = CONE_RATIO_MAX;
    // Centre in texels; the v axis is scaled to u-texel units only inside cone_map_value.
    vec2 centre = vec2(p) + 0.5;
    // Seed the best with the 8 neighbours (genuine candidates, so the minimum is unchanged) so
    // that most of the pyramid is pruned from the first node on, as the CPU search does.
    for (int n = 0; n < 9 && top_height > hp; ++n) {
        ivec2 q = ivec2(p) + ivec2(n % 3 - 1, n / 3 - 1);
        ivec2 size = ivec2(params.width, params.height);
        ivec2 wrapped = ivec2(q.x < 0 ? q.x + size.x : (q.x >= size.x ? q.x - size.x : q.x),
                              q.y < 0 ? q.y + size.y : (q.y >= size.y ? q.y - size.y : q.y));
        // The texel itself is no candidate; under Clamp only texels of the map are.
        if (n == 4 || (params.repeat_address == 0u && q != wrapped)) {
            continue;
        }
        float h = pyramid[uint(wrapped.y) * params.width + uint(wrapped.x)];
        if (h > hp) {
            Node node = node_rect(0u, uvec2(wrapped), vec2(q - wrapped));
            best = min(best, cone_map_value(centre, node.lo, node.hi, h - hp, 0.0));
        }
    }
    int tiles = params.repeat_address != 0u && top_height > hp ? 9 : (top_height > hp ? 1 : 0);
    for (int t = 0; t < tiles; ++t) {
        // Tile (a, b) of the 3x3 block, the map itself (slot 4) first so the ring starts pruned.
        int slot = (t + 4) % 9;
        vec2 tile = vec2(float(slot % 3 - 1) * float(params.width), float(slot / 3 - 1) * float(params.height));
        Node root = node_rect(top, uvec2(0u), tile);
        float root_bound = cone_map_value(centre, root.lo, root.hi, top_height - hp, 0.0);
        int sp = 0;
        if (root_bound < best) {
            search_stack[0] = entry(top, 0u, 0u, root_bound);
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
            // The children on the level below (clipped to it), with their bounds in registers
            // (a node that cannot improve the best gets NO_BOUND), pushed nearest last.
            uint child = level - 1u;
            uvec2 size = level_size(child);
            uvec2 first = at * 2u;
            uvec2 last = min(first + 1u, size - 1u);
            uvec2 e0 = kid(child, uvec2(first.x, first.y), size, tile, centre, hp, best);
            uvec2 e1 = first.x == last.x ? uvec2(0u, NO_BOUND)
                : kid(child, uvec2(last.x, first.y), size, tile, centre, hp, best);
            uvec2 e2 = first.y == last.y ? uvec2(0u, NO_BOUND)
                : kid(child, uvec2(first.x, last.y), size, tile, centre, hp, best);
            uvec2 e3 = first.x == last.x || first.y == last.y ? uvec2(0u, NO_BOUND)
                : kid(child, last, size, tile, centre, hp, best);
            push_children(sp, e0, e1, e2, e3);
        }
    }
    // Below the minimum of the computed values by more than their error (see the header); a
    // texel nothing limits keeps the cap itself, as on the CPU.
    float ratio = best < CONE_RATIO_MAX ? step_down(best, STEP_DOWN) : CONE_RATIO_MAX;
    cone_map[index] = vec2(ratio, hp);
}

void main() {
    if (params.mode == MODE_REDUCE) {
        reduce();
    } else {
        cone();
    }
}
