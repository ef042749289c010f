// The relaxed cone map on the GPU (heightfield::cone_map, "Relaxed cone"): the CPU builder's two
// searches per texel over the bilinear bound's box surface (level 0 of `nodes`, computed on
// the CPU), but with the directions cut into the four quadrants, each the union of four of the
// CPU's sectors:
//   reach(q, Q) = distance from box(q) to the nearest texel lower than q whose direction from
//                 box(q) may lie in quadrant Q (by the signs of the offsets alone), capped at
//                 0.25 uv or 16 texels;
//   c(p) = min over q with h(q) > h(p) of
//          (dist(p_c, box(q)) + min over quadrants Q the offsets from box(p) to box(q) allow
//           of reach(q, Q)) / (h(q) - h(p)),
// over the 3x3 tiles around the map under Repeat (farther tiles are at least 1 uv away, while a
// copy of the global maximum lies within sqrt(0.5) + 0.25 < 1 uv), and under Clamp over the
// map and the border: four strips (a border row or column extended to infinity) and four corner
// quadrants, which hold no reach (0) as on the CPU. The CPU takes the larger of this and the
// conservative ratio, but with reaches never negative this is never below the conservative
// minimum, so the GPU needs no conservative pass.
//
// Why quadrants: every quadrant the signs allow holds a CPU sector the CPU allows, and every
// texel counted for a CPU sector is counted for its quadrant, so a quadrant's reach is at most
// each of its sectors' and the ratio at most the CPU's: still a relaxed cone, never wider than
// proven. The sectors' angles cost divisions at every node, and the finer reaches made the search
// open more nodes; on the test fields and fbm at 1024^2 the quadrant map equals the CPU's to
// 2^-15 while both searches run in about half the time (render::relaxed_cone_map_pass).
//
// What the four kernels share; each kernel is a file of its own under shaders/passes/, so each
// pipeline holds its kernel alone (lavapipe runs that several times faster than one shader
// branching per dispatch):
//  REDUCE (relaxed_cone_reduce.comp): level L of the max pyramid and of the max pyramid of 1 - h (the min pyramid the
//    reach search prunes by, as the CPU's), both from level L - 1.
//  REACH (relaxed_cone_reach.comp): rows [row0, row0 + rows): each texel's 4 reaches, as u16 multiples of a 65535th of
//    the cap (rounded down, like the CPU's), into level 0 of `reach`.
//  REACH_REDUCE (relaxed_cone_reach_reduce.comp): level L of `reach`: per node and quadrant the least reach under it.
//  RELAXED (relaxed_cone_search.comp): rows [row0, row0 + rows): each texel's ratio and bound height.
// Both searches are depth-first over the pyramid, nearest bound first, and exact; only the
// arithmetic is f32.
//
// Rounding: a reach is stepped down by REACH_DOWN ulps (more than its distance's error and the
// pruning's) before it is rounded down to a unit; a ratio is computed like the conservative one
// (cone_search.glsl) and stepped down by STEP_DOWN ulps.
#ifndef RELAXED_CONE_GLSL
#define RELAXED_CONE_GLSL

// MAX_LEVELS and the bindings.
#include "interface.glsl"
// Quadrants 0..3 from +u toward +v: (+u, +v), (-u, +v), (-u, -v), (+u, -v) (the CPU's sectors
// 4k..4k+3); those in the open half-planes u > 0 and v > 0.
const uint ALL_QUADRANTS = 0xfu;
const uint U_POSITIVE = 0x9u;
const uint V_POSITIVE = 0x3u;
const float REACH_MAX_UNITS = 65535.0;
const uint REACH_DOWN = 16u;
// The open side of a clamp strip, in uv as on the CPU (times the side in texels).
const float FAR = 1.0e6;
// Region axes: a tile offset -1, 0 or 1 (the map's texels shifted by whole maps), or the clamp
// border's open side below 0 or above the map, where the axis is pinned to the border texel.
const int PIN_LO = 2;
const int PIN_HI = 3;

// Per node of every level, back to back from level 0 (the texels): the maximum bound height and
// the maximum of 1 - height (the min pyramid the reach search prunes by, as the CPU's), as float
// bits, then the node's least reach per quadrant (two u16 a word: quadrants 0 and 1, 2 and 3).
// Node (i, j) of level L covers the texels [i, i + 1) * 2^L (clipped) along each axis, as in
// buffer_pyramid.glsl. A node's height and reaches sit together because the relaxed search reads
// both (25% faster on lavapipe than two arrays).
layout(set = 0, binding = BINDING_SEARCH_PYRAMID, std430) buffer Nodes {
    uvec4 nodes[];
};

// Per texel of level 0: the ratio and the bound height (MapData's two channels), row-major.
layout(set = 0, binding = BINDING_SEARCH_MAP, std430) writeonly buffer ConeMap {
    vec2 cone_map[];
};

// The fields: RelaxedConeParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    RELAXED_CONE_PARAMS_FIELDS
} params;

// Values, node rectangles, stack entries (needs `params`).
#include "cone_search.glsl"

// Nodes of `level` (levels halve, rounding up, to 1x1).
uvec2 level_size(uint level) {
    uint n = 1u << level;
    return (uvec2(params.width, params.height) + n - 1u) >> level;
}

float node_height(uvec4 node) {
    return uintBitsToFloat(node.x);
}

// The node's maximum of 1 - h: a node with a texel below h has at least 1 - h.
float node_depth(uvec4 node) {
    return uintBitsToFloat(node.y);
}

uint node_index(uint level, uvec2 at) {
    return params.offsets[level] + at.y * level_size(level).x + at.x;
}

// ---- Regions: tiles and the clamp border -------------------------------------------------------

// Region r's two axes (see PIN_LO): under Repeat the 3x3 tiles, the map (r = 0) first; under
// Clamp the map, the strips left, right, below, above, then the corners.
ivec2 region_axes(int r) {
    if (params.repeat_address != 0u) {
        int slot = (r + 4) % 9;
        return ivec2(slot % 3 - 1, slot / 3 - 1);
    }
    // Written without an array: lavapipe keeps private arrays in memory.
    if (r == 0) {
        return ivec2(0);
    }
    if (r < 5) {
        int pin = PIN_LO + (r - 1) % 2;
        return r < 3 ? ivec2(pin, 0) : ivec2(0, pin);
    }
    return ivec2(PIN_LO + (r - 5) % 2, PIN_LO + (r - 5) / 2);
}

// Whether the region's texels are texels of the map (reaches apply), not border copies.
bool region_real(ivec2 axes) {
    return axes.x < PIN_LO && axes.y < PIN_LO;
}

// The texel range [lo, hi] along one axis of n texels of node `at` on `level`.
vec2 axis_range(int kind, uint level, uint at, uint n) {
    float far = FAR * float(n);
    if (kind == PIN_LO) {
        return vec2(-far, 0.0);
    }
    if (kind == PIN_HI) {
        return vec2(float(n), far);
    }
    uint lo = at << level;
    uint hi = min(lo + (1u << level), n);
    float shift = float(kind) * float(n);
    return vec2(float(lo) + shift, float(hi) + shift);
}

Node region_rect(ivec2 axes, uint level, uvec2 at) {
    vec2 x = axis_range(axes.x, level, at.x, params.width);
    vec2 y = axis_range(axes.y, level, at.y, params.height);
    Node node;
    node.lo = vec2(x.x, y.x);
    node.hi = vec2(x.y, y.y);
    return node;
}

// The children of index `at` along one axis on level `child` (of `size` nodes): both halves, or
// the one holding the border texel on a pinned axis. The pyramid node over a pinned border line
// covers more texels than the line; its maximum and minimum still bound the line's.
uvec2 axis_children(int kind, uint child, uint at, uint size, uint n) {
    if (kind == PIN_LO) {
        return uvec2(0u);
    }
    if (kind == PIN_HI) {
        return uvec2((n - 1u) >> child);
    }
    uint first = at * 2u;
    return uvec2(first, min(first + 1u, size - 1u));
}

// ---- Quadrants ----------------------------------------------------------------------------------

// Quadrants of one component's sign of b - a, a in [f0, f1), b in [t0, t1).
uint sign_quadrants(float f0, float f1, float t0, float t1, uint positive) {
    if (t0 >= f1) {
        return positive;
    }
    if (t1 <= f0) {
        return ALL_QUADRANTS & ~positive;
    }
    return ALL_QUADRANTS;
}

// The quadrants a direction from a point of `from` to a point of `to` may lie in (closed
// quadrants: a direction on an axis lies in both of its neighbours).
uint quadrants_between(Node from, Node to) {
    return sign_quadrants(from.lo.x, from.hi.x, to.lo.x, to.hi.x, U_POSITIVE)
         & sign_quadrants(from.lo.y, from.hi.y, to.lo.y, to.hi.y, V_POSITIVE);
}

bvec4 quadrant_bits(uint mask) {
    return notEqual(uvec4(mask) & uvec4(1u, 2u, 4u, 8u), uvec4(0u));
}

uint quadrant_mask(bvec4 b) {
    return uint(b.x) | (uint(b.y) << 1) | (uint(b.z) << 2) | (uint(b.w) << 3);
}

// Distance between two closed rectangles, in u-texels.
float rect_gap(Node a, Node b) {
    float dx = max(max(b.lo.x - a.hi.x, a.lo.x - b.hi.x), 0.0);
    float dy = max(max(b.lo.y - a.hi.y, a.lo.y - b.hi.y), 0.0) * params.aspect;
    return sqrt(dx * dx + dy * dy);
}

#endif
