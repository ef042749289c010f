#version 460
#extension GL_GOOGLE_include_directive : require
// The relaxed cone map on the GPU (heightfield::cone_map, "Relaxed cone"), the CPU builder's two
// searches ported to one invocation per texel, over the bilinear bound's box surface (level 0 of
// `pyramid`, computed on the CPU), with its conservative map (cone_map.comp) as the floor:
//   reach(q, S) = distance from box(q) to the nearest texel lower than q that a line leaving
//                 box(q) in a direction of sector S can enter, capped at 0.25 uv or 16 texels;
//   c(p) = max(conservative c(p), min over q with h(q) > h(p) of
//              (dist(p_c, box(q)) + min over sectors S from box(p) to box(q) of reach(q, S))
//              / (h(q) - h(p))),
// over the 3x3 tiles around the map under Repeat (farther tiles are at least 1 uv away, while a
// copy of the global maximum lies within sqrt(0.5) + 0.25 < 1 uv), and under Clamp over the
// map and the border: four strips (a border row or column extended to infinity) and four corner
// quadrants, which hold no reach (0) as on the CPU.
//
// Modes, one per dispatch (params.mode):
//  REDUCE: level L of the max pyramid and of the max pyramid of 1 - h (the min pyramid the
//    reach search prunes by, as the CPU's), both from level L - 1.
//  REACH: rows [row0, row0 + rows): each texel's 16 reaches, as u16 multiples of a 65535th of
//    the cap (rounded down, like the CPU's), into level 0 of `reach`.
//  REACH_REDUCE: level L of `reach`: per node and sector the least reach under it.
//  RELAXED: rows [row0, row0 + rows): each texel's ratio, written over the conservative one.
// Both searches are depth-first over the pyramid, nearest bound first, and exact; only the
// arithmetic is f32.
//
// Rounding (the guarantee: a stored ratio is never above the CPU's, so never wider than proven).
// Sectors are cut on diamond angles computed in f32 with the slack EPS_LEAF / EPS_NODE (the CPU
// uses 1e-9 / 1e-7 in f64), larger than the f32 angle's error, so every sector set here holds the
// CPU's: a reach is lowered in at least the CPU's sectors, and a ratio takes its reach as the
// least over at least the CPU's sectors. A reach is stepped down by REACH_DOWN ulps (more than its
// distance's error and the pruning's) before it is rounded down to a unit, so it is never above
// the CPU's unit count. A ratio is computed like the conservative one (cone_search.glsl) and
// stepped down by STEP_DOWN ulps; the floor is the GPU conservative map, never above the CPU's.
layout(local_size_x = 8, local_size_y = 8) in;

const uint MODE_REDUCE = 0u;
const uint MODE_REACH = 1u;
const uint MODE_REACH_REDUCE = 2u;
const uint MODE_RELAXED = 3u;
const uint MAX_LEVELS = 15u;
const uint SECTORS = 16u;
const uint ALL_SECTORS = 0xffffu;
// Sectors in the open half-planes u > 0 (12..15, 0..3) and v > 0 (0..7): SECTORS / 4 per quadrant,
// counted from +u toward +v.
const uint U_POSITIVE = 0xf00fu;
const uint V_POSITIVE = 0x00ffu;
// Diamond-angle slack: the f32 angle of integer corners is off by a few ulps of 4 (about 1e-6).
const float EPS_LEAF = 4.0e-6;
const float EPS_NODE = 8.0e-6;
const float REACH_MAX_UNITS = 65535.0;
const uint REACH_DOWN = 16u;
// The open side of a clamp strip, in uv as on the CPU (times the side in texels).
const float FAR = 1.0e6;
// Region axes: a tile offset -1, 0 or 1 (the map's texels shifted by whole maps), or the clamp
// border's open side below 0 or above the map, where the axis is pinned to the border texel.
const int PIN_LO = 2;
const int PIN_HI = 3;
// Uints per node of `reach`: two u16 reaches each.
const uint REACH_WORDS = SECTORS / 2u;

// Max levels back to back (level 0: the bound heights), then from params.min_base the levels of
// 1 - h, laid out alike (buffer_pyramid.glsl).
layout(set = 0, binding = 0, std430) buffer Pyramid {
    float pyramid[];
};

// Per node of every level (the pyramid's layout), REACH_WORDS words: sector 2k in the low half of
// word k, sector 2k + 1 in the high half.
layout(set = 0, binding = 1, std430) buffer Reach {
    uint reach[];
};

// Per texel of level 0: the ratio and the bound height (MapData's two channels), row-major. Holds
// the conservative map on entry; RELAXED writes the relaxed ratio over it.
layout(set = 0, binding = 2, std430) buffer ConeMap {
    vec2 cone_map[];
};

layout(push_constant, std430) uniform Params {
    uint mode;
    uint width;
    uint height;
    // 1 for Repeat, 0 for Clamp.
    uint repeat_address;
    // REDUCE, REACH_REDUCE: the level written. REACH, RELAXED: the first row of this dispatch.
    uint level;
    uint row0;
    float aspect;
    // The level whose single node covers the map.
    uint top;
    // Where the levels of 1 - h start in `pyramid`.
    uint min_base;
    // The reach cap in u-texels (0.25 uv or 16 texels, whichever is less: heightfield::cone_map)
    // and its 65535th part, a reach unit (both rounded to f32).
    float reach_unit;
    float reach_cap;
    // Where `reach` holds, per node, its least reach over every sector (one word).
    uint any_base;

    uint offsets[MAX_LEVELS];
} params;

#include "buffer_pyramid.glsl"
// Values, node rectangles, stack entries (needs `params`).
#include "cone_search.glsl"

uvec2 level_size(uint level) {
    return pyramid_level_size(uvec2(params.width, params.height), level);
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

// ---- Direction sectors (heightfield::cone_map_sectors) ----------------------------------------

// Sectors of one component's sign of b - a, a in [f0, f1), b in [t0, t1).
uint sign_mask(float f0, float f1, float t0, float t1, uint positive) {
    if (t0 >= f1) {
        return positive;
    }
    if (t1 <= f0) {
        return ALL_SECTORS & ~positive;
    }
    return ALL_SECTORS;
}

// In [0, 4), increasing with the angle from +u toward +v; 1, 2, 3 on the axes.
float diamond(vec2 d) {
    if (d.y >= 0.0) {
        return d.x >= 0.0 ? d.y / (d.x + d.y) : 1.0 - d.x / (d.y - d.x);
    }
    return d.x < 0.0 ? 2.0 - d.y / (-d.x - d.y) : 3.0 + d.x / (d.x - d.y);
}

// The angle of corner c relative to the centre's, in (-2, 2].
float relative_angle(vec2 c, float centre) {
    float rel = diamond(c) - centre;
    return rel > 2.0 ? rel - 4.0 : (rel < -2.0 ? rel + 4.0 : rel);
}

// Sectors meeting the angles of a box of differences that excludes the origin (corners c0..c3).
// Written without an array: lavapipe keeps private arrays in memory.
uint angular_mask(vec2 c0, vec2 c1, vec2 c2, vec2 c3, float eps) {
    float centre = diamond(0.25 * c0 + 0.25 * c1 + 0.25 * c2 + 0.25 * c3);
    float r0 = relative_angle(c0, centre);
    float r1 = relative_angle(c1, centre);
    float r2 = relative_angle(c2, centre);
    float r3 = relative_angle(c3, centre);
    float lo = min(min(min(r0, r1), min(r2, r3)), 0.0);
    float hi = max(max(max(r0, r1), max(r2, r3)), 0.0);
    int k_lo = int(floor((centre + lo - eps) * 4.0));
    int k_hi = int(floor((centre + hi + eps) * 4.0));
    int count = k_hi - k_lo + 1;
    if (count >= int(SECTORS)) {
        return ALL_SECTORS;
    }
    uint run = (1u << uint(count)) - 1u;
    uint shift = uint(k_lo & 15);
    return ((run << shift) | (run >> (SECTORS - shift))) & ALL_SECTORS;
}

// Sectors of the directions from a point of `from` to a point of `to` (texel rectangles, v not
// yet scaled): a superset of the CPU's.
uint direction_mask(Node from, Node to, bool leaf) {
    uint mask = sign_mask(from.lo.x, from.hi.x, to.lo.x, to.hi.x, U_POSITIVE)
              & sign_mask(from.lo.y, from.hi.y, to.lo.y, to.hi.y, V_POSITIVE);
    vec2 d_lo = vec2(to.lo.x - from.hi.x, (to.lo.y - from.hi.y) * params.aspect);
    vec2 d_hi = vec2(to.hi.x - from.lo.x, (to.hi.y - from.lo.y) * params.aspect);
    if (!(d_lo.x <= 0.0 && d_hi.x >= 0.0 && d_lo.y <= 0.0 && d_hi.y >= 0.0)) {
        mask &= angular_mask(d_lo, vec2(d_hi.x, d_lo.y), vec2(d_lo.x, d_hi.y), d_hi,
                             leaf ? EPS_LEAF : EPS_NODE);
    }
    return mask;
}

// Distance between two closed rectangles, in u-texels.
float rect_gap(Node a, Node b) {
    float dx = max(max(b.lo.x - a.hi.x, a.lo.x - b.hi.x), 0.0);
    float dy = max(max(b.lo.y - a.hi.y, a.lo.y - b.hi.y), 0.0) * params.aspect;
    return sqrt(dx * dx + dy * dy);
}

// ---- REDUCE -------------------------------------------------------------------------------------

void reduce() {
    uint level = params.level;
    uvec2 size = uvec2(params.width, params.height);
    uint fine = params.offsets[level - 1u];
    uint here = params.offsets[level];
    pyramid_reduce(size, level, fine, here, gl_GlobalInvocationID.xy);
    pyramid_reduce(size, level, params.min_base + fine, params.min_base + here,
                   gl_GlobalInvocationID.xy);
}

// ---- REACH --------------------------------------------------------------------------------------

// The 16 reaches of the texel being searched, in u-texels, sectors 4k..4k+3 in reaches_k: four
// vectors, not an array, which lavapipe would keep in memory.
vec4 reaches_0;
vec4 reaches_1;
vec4 reaches_2;
vec4 reaches_3;

uint mask_of(bvec4 b) {
    return uint(b.x) | (uint(b.y) << 1) | (uint(b.z) << 2) | (uint(b.w) << 3);
}

bvec4 bits_of(uint mask) {
    return notEqual(uvec4(mask) & uvec4(1u, 2u, 4u, 8u), uvec4(0u));
}

// The sectors whose reach is still above d.
uint open_sectors(float d) {
    vec4 dv = vec4(d);
    return mask_of(greaterThan(reaches_0, dv)) | (mask_of(greaterThan(reaches_1, dv)) << 4)
         | (mask_of(greaterThan(reaches_2, dv)) << 8) | (mask_of(greaterThan(reaches_3, dv)) << 12);
}

// Lowers the reaches of the sectors in `mask` to d.
void lower_reaches(uint mask, float d) {
    vec4 dv = vec4(d);
    reaches_0 = mix(reaches_0, min(reaches_0, dv), bits_of(mask));
    reaches_1 = mix(reaches_1, min(reaches_1, dv), bits_of(mask >> 4));
    reaches_2 = mix(reaches_2, min(reaches_2, dv), bits_of(mask >> 8));
    reaches_3 = mix(reaches_3, min(reaches_3, dv), bits_of(mask >> 12));
}

// Two sectors' reaches as u16 units, packed as `reach` holds them: a sector nothing lowered keeps
// the cap's full count, as on the CPU; the others are stepped down past f32 rounding, then
// rounded down.
uint reach_pair(vec2 r, float cap) {
    vec2 units = vec2(floor(step_down(r.x / params.reach_unit, REACH_DOWN)),
                      floor(step_down(r.y / params.reach_unit, REACH_DOWN)));
    units = min(mix(units, vec2(REACH_MAX_UNITS), greaterThanEqual(r, vec2(cap))),
                vec2(REACH_MAX_UNITS));
    return uint(units.x) | (uint(units.y) << 16);
}

// A stack entry of the reach search: entry() and the node's sectors.
uvec3 reach_kid(ivec2 axes, uint level, uvec2 at, Node q, float lower_than) {
    uvec3 none = uvec3(0u, NO_BOUND, 0u);
    // 1 - min: a node with no texel below the searched one holds nothing to drop into.
    if (pyramid[params.min_base + node_index(level, at)] < lower_than) {
        return none;
    }
    Node rect = region_rect(axes, level, at);
    float d = rect_gap(q, rect);
    uint mask = direction_mask(q, rect, level == 0u);
    if ((mask & open_sectors(d)) == 0u) {
        return none;
    }
    return uvec3(entry(level, at.x, at.y, d), mask);
}

void order3(inout uvec3 a, inout uvec3 b) {
    if (a.y < b.y) {
        uvec3 t = a;
        a = b;
        b = t;
    }
}

void reach_texel() {
    uvec2 p = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y + params.row0);
    if (p.x >= params.width || p.y >= params.height) {
        return;
    }
    uint index = p.y * params.width + p.x;
    float hq = pyramid[index];
    // As the CPU: the inverted level holds 1 - h rounded like this, so h < hq gives 1 - h >= g.
    float g = 1.0 - hq;
    float cap = params.reach_cap;
    reaches_0 = vec4(cap);
    reaches_1 = vec4(cap);
    reaches_2 = vec4(cap);
    reaches_3 = vec4(cap);
    Node q = node_rect(0u, p, vec2(0.0));
    uint top = params.top;
    uvec3 stack[STACK];
    for (int r = 0; r < 9; ++r) {
        ivec2 axes = region_axes(r);
        uvec3 root = reach_kid(axes, top, uvec2(0u), q, g);
        int sp = 0;
        if (root.y != NO_BOUND) {
            stack[0] = root;
            sp = 1;
        }
        while (sp > 0) {
            --sp;
            uvec3 e = stack[sp];
            float d = uintBitsToFloat(e.y);
            if ((e.z & open_sectors(d)) == 0u) {
                continue;
            }
            uint level = entry_level(e.x);
            uvec2 at = entry_at(e.x);
            if (level == 0u) {
                if (pyramid[node_index(0u, at)] < hq) {
                    lower_reaches(e.z, d);
                }
                continue;
            }
            uint child = level - 1u;
            uvec2 size = level_size(child);
            uvec2 xs = axis_children(axes.x, child, at.x, size.x, params.width);
            uvec2 ys = axis_children(axes.y, child, at.y, size.y, params.height);
            uvec3 none = uvec3(0u, NO_BOUND, 0u);
            uvec3 e0 = reach_kid(axes, child, uvec2(xs.x, ys.x), q, g);
            uvec3 e1 = xs.x == xs.y ? none : reach_kid(axes, child, uvec2(xs.y, ys.x), q, g);
            uvec3 e2 = ys.x == ys.y ? none : reach_kid(axes, child, uvec2(xs.x, ys.y), q, g);
            uvec3 e3 = xs.x == xs.y || ys.x == ys.y ? none
                : reach_kid(axes, child, uvec2(xs.y, ys.y), q, g);
            order3(e0, e1);
            order3(e2, e3);
            order3(e0, e2);
            order3(e1, e3);
            order3(e1, e2);
            if (e0.y != NO_BOUND && sp < STACK) { stack[sp++] = e0; }
            if (e1.y != NO_BOUND && sp < STACK) { stack[sp++] = e1; }
            if (e2.y != NO_BOUND && sp < STACK) { stack[sp++] = e2; }
            if (e3.y != NO_BOUND && sp < STACK) { stack[sp++] = e3; }
        }
    }
    uvec4 low = uvec4(reach_pair(reaches_0.xy, cap), reach_pair(reaches_0.zw, cap),
                      reach_pair(reaches_1.xy, cap), reach_pair(reaches_1.zw, cap));
    uvec4 high = uvec4(reach_pair(reaches_2.xy, cap), reach_pair(reaches_2.zw, cap),
                       reach_pair(reaches_3.xy, cap), reach_pair(reaches_3.zw, cap));
    uint base = index * REACH_WORDS;
    for (uint w = 0u; w < 4u; ++w) {
        reach[base + w] = low[w];
        reach[base + 4u + w] = high[w];
    }
    uvec4 least4 = min(min(low & 0xffffu, low >> 16), min(high & 0xffffu, high >> 16));
    reach[params.any_base + index] = min(min(least4.x, least4.y), min(least4.z, least4.w));
}

// ---- REACH_REDUCE -------------------------------------------------------------------------------

void reach_reduce() {
    uint level = params.level;
    uvec2 at = gl_GlobalInvocationID.xy;
    uvec2 nodes = level_size(level);
    if (any(greaterThanEqual(at, nodes))) {
        return;
    }
    uvec2 fine = level_size(level - 1u);
    uvec2 first = at * 2u;
    uvec2 last = min(first + 1u, fine - 1u);
    uint out_base = node_index(level, at) * REACH_WORDS;
    uint least = 0xffffu;
    for (uint w = 0u; w < REACH_WORDS; ++w) {
        uint lo = 0xffffu;
        uint hi = 0xffffu;
        for (uint y = first.y; y <= last.y; ++y) {
            for (uint x = first.x; x <= last.x; ++x) {
                uint pair = reach[node_index(level - 1u, uvec2(x, y)) * REACH_WORDS + w];
                lo = min(lo, pair & 0xffffu);
                hi = min(hi, pair >> 16);
            }
        }
        reach[out_base + w] = lo | (hi << 16);
        least = min(least, min(lo, hi));
    }
    reach[params.any_base + node_index(level, at)] = least;
}

// ---- RELAXED ------------------------------------------------------------------------------------

// The least reach, in u-texels, over the sectors in `mask` of node `at` on `level`.
float least_reach(uint level, uvec2 at, uint mask) {
    uint base = node_index(level, at) * REACH_WORDS;
    uint least = 0xffffu;
    for (uint w = 0u; w < REACH_WORDS; ++w) {
        uint pair = reach[base + w];
        least = (mask & (1u << (2u * w))) != 0u ? min(least, pair & 0xffffu) : least;
        least = (mask & (2u << (2u * w))) != 0u ? min(least, pair >> 16) : least;
    }
    return mask == 0u ? 0.0 : float(least) * params.reach_unit;
}

// The least reach over all sectors of node `at` on `level`, in u-texels.
float least_reach_any(uint level, uvec2 at) {
    return float(reach[params.any_base + node_index(level, at)]) * params.reach_unit;
}

// The relaxed value of node `at` on `level` of a region, or NO_BOUND when it holds nothing higher
// than hp or cannot beat `best`. Cheaper lower bounds go first: no reach, then the node's least
// reach over every sector (one word), then the least over the sectors from p's box to the node.
uvec2 relaxed_kid(ivec2 axes, uint level, uvec2 at, Node prect, vec2 centre, float hp,
                  float best) {
    uvec2 none = uvec2(0u, NO_BOUND);
    float h = pyramid[node_index(level, at)];
    if (!(h > hp)) {
        return none;
    }
    Node rect = region_rect(axes, level, at);
    float b = cone_map_value(centre, rect.lo, rect.hi, h - hp, 0.0);
    if (region_real(axes) && b < best) {
        b = cone_map_value(centre, rect.lo, rect.hi, h - hp, least_reach_any(level, at));
        if (b < best) {
            float extra = least_reach(level, at, direction_mask(prect, rect, level == 0u));
            b = cone_map_value(centre, rect.lo, rect.hi, h - hp, extra);
        }
    }
    return b < best ? entry(level, at.x, at.y, b) : none;
}

void relaxed_texel() {
    uvec2 p = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y + params.row0);
    if (p.x >= params.width || p.y >= params.height) {
        return;
    }
    uint index = p.y * params.width + p.x;
    float hp = pyramid[index];
    float floor_ratio = cone_map[index].x;
    uint top = params.top;
    float top_height = pyramid[params.offsets[top]];
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
    uvec2 stack[STACK];
    for (int r = 0; r < 9 && top_height > hp && best > floor_ratio; ++r) {
        ivec2 axes = region_axes(r);
        uvec2 root = relaxed_kid(axes, top, uvec2(0u), prect, centre, hp, best);
        int sp = 0;
        if (root.y != NO_BOUND) {
            stack[0] = root;
            sp = 1;
        }
        // At or below the floor the answer is the floor, whatever else is found.
        while (sp > 0 && best > floor_ratio) {
            --sp;
            uvec2 e = stack[sp];
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
            // One call site in a loop, not four inlined copies: lavapipe runs the smaller code
            // far faster. Pushed, then ordered on the stack so the nearest is popped first.
            int first = sp;
            for (uint k = 0u; k < 4u; ++k) {
                uvec2 c = uvec2((k & 1u) != 0u ? xs.y : xs.x, (k & 2u) != 0u ? ys.y : ys.x);
                bool duplicate = ((k & 1u) != 0u && xs.x == xs.y) || ((k & 2u) != 0u && ys.x == ys.y);
                uvec2 kid = duplicate ? uvec2(0u, NO_BOUND)
                    : relaxed_kid(axes, child, c, prect, centre, hp, best);
                if (kid.y != NO_BOUND && sp < STACK) {
                    // Insertion: larger bounds deeper, so the nearest ends on top.
                    int at_k = sp++;
                    while (at_k > first && stack[at_k - 1].y < kid.y) {
                        stack[at_k] = stack[at_k - 1];
                        --at_k;
                    }
                    stack[at_k] = kid;
                }
            }
        }
    }
    float ratio = best < CONE_RATIO_MAX ? step_down(best, STEP_DOWN) : CONE_RATIO_MAX;
    cone_map[index].x = max(ratio, floor_ratio);
}

void main() {
    if (params.mode == MODE_REDUCE) {
        reduce();
    } else if (params.mode == MODE_REACH) {
        reach_texel();
    } else if (params.mode == MODE_REACH_REDUCE) {
        reach_reduce();
    } else {
        relaxed_texel();
    }
}
