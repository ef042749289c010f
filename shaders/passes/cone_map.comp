#version 460
// The conservative cone map on the GPU (heightfield::cone_map, "Conservative cone"): per texel p
// of the bilinear bound's box surface (level 0 of `pyramid`, computed exactly on the CPU),
//   c(p) = min over texels q with h(q) > h(p) of dist(p_c, box(q)) / (h(q) - h(p)),
// distances in uv between p's centre and q's closed box, over the 3x3 tiles around the map under
// Repeat (farther tiles are at least 1 uv away while the global maximum always has a copy within
// sqrt(0.5) uv, so they never hold the minimum) and over the map alone under Clamp (the border's
// copies are never nearer than the border texels). Capped at CONE_RATIO_MAX.
//
// Two modes, chosen per dispatch by params.mode:
//  REDUCE: level L of a max pyramid from level L - 1, where node (i, j) of level L covers the
//    level-0 texels [i, i + 1) * 2^L (clipped to the map) along each axis; levels shrink to 1x1.
//    (Not the Vulkan mip rule of the height image: aligned power-of-two spans give the search
//    exact node rectangles with no tables.)
//  CONE: one invocation per texel of rows [row0, row0 + rows): a depth-first search of each
//    tile's pyramid, nearest child first, skipping every node whose bound (its rectangle's
//    distance over its maximum's rise) is no lower than the best found. The search itself is
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

const uint MODE_REDUCE = 0u;
const uint MODE_CONE = 1u;
const float CONE_RATIO_MAX = 64.0;
// Entries a search stack can hold: a pop pushes at most 4 children, so a depth-first search over
// L levels holds at most 3 L + 1; 64 covers maps up to 2^21 texels a side.
const int STACK = 64;
const uint MAX_LEVELS = 22u;
const uint STEP_DOWN = 128u;

// All pyramid levels back to back, level 0 (the bound heights, width x height) first.
layout(set = 0, binding = 0, std430) buffer Pyramid {
    float pyramid[];
};

// Per texel of level 0: the ratio and the bound height (MapData's two channels), row-major.
layout(set = 0, binding = 1, std430) writeonly buffer ConeMap {
    vec2 cone_map[];
};

layout(push_constant, std430) uniform Params {
    uint mode;
    // Level 0 size in texels.
    uint width;
    uint height;
    // 1 for Repeat, 0 for Clamp.
    uint repeat_address;
    // REDUCE: the level written. CONE: the first row of this dispatch.
    uint level;
    uint row0;
    // width / height rounded to f32: the v distance in u-texel units is dy * aspect.
    float aspect;
    uint pad;
} params;

uvec2 level_size(uint level) {
    uint n = 1u << level;
    return uvec2((params.width + n - 1u) >> level, (params.height + n - 1u) >> level);
}

uint level_offset(uint level) {
    uint offset = 0u;
    for (uint l = 0u; l < level; ++l) {
        uvec2 s = level_size(l);
        offset += s.x * s.y;
    }
    return offset;
}

// The level whose single node covers the whole map.
uint top_level() {
    uint largest = max(params.width, params.height);
    uint level = 0u;
    while ((1u << level) < largest) {
        ++level;
    }
    return level;
}

void reduce() {
    uvec2 size = level_size(params.level);
    uvec2 at = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(at, size))) {
        return;
    }
    uvec2 fine = level_size(params.level - 1u);
    uint base = level_offset(params.level - 1u);
    uvec2 first = at * 2u;
    uvec2 last = min(first + 1u, fine - 1u);
    float h = 0.0;
    for (uint y = first.y; y <= last.y; ++y) {
        for (uint x = first.x; x <= last.x; ++x) {
            h = max(h, pyramid[base + y * fine.x + x]);
        }
    }
    pyramid[level_offset(params.level) + at.y * size.x + at.x] = h;
}

// The computed value of a node: its rectangle [lo, hi] (u-texels, v-texels; closed) seen from
// the centre c over the rise of its maximum. dx and dy are exact (half-integers below 2^22); the
// error is one rounding each for dx^2, aspect, dy * aspect, its square, the sum, rise, w * rise,
// plus sqrt (5 ULP) and the division (2.5 ULP): about 12.5 units of 2^-23, so EPS_ULPS = 16.
// STEP_DOWN ulps of the result are at least STEP_DOWN * 2^-24 relative, 4x that error.
float cone_map_value(vec2 c, vec2 lo, vec2 hi, float rise) {
    float dx = max(max(lo.x - c.x, c.x - hi.x), 0.0);
    float dy = max(max(lo.y - c.y, c.y - hi.y), 0.0) * params.aspect;
    float den = float(params.width) * rise;
    // Division has no precision guarantee below 2^-126; there the true value (at least half a
    // texel over den) is far above the cap anyway, so the candidate is dropped.
    if (!(den > 1.0e-30)) {
        return 3.0e38;
    }
    return sqrt(dx * dx + dy * dy) / den;
}

struct Node {
    // Level-0 rectangle of the node in its tile, in texels (lo inclusive, hi exclusive edges).
    vec2 lo;
    vec2 hi;
};

Node node_rect(uint level, uvec2 at, vec2 tile) {
    uint n = 1u << level;
    uvec2 lo = at * n;
    uvec2 hi = min(lo + n, uvec2(params.width, params.height));
    Node node;
    node.lo = vec2(lo) + tile;
    node.hi = vec2(hi) + tile;
    return node;
}

// Largest f32 at least `ulps` ulps below a positive finite x (stays positive: bits only shrink).
float step_down(float x, uint ulps) {
    uint bits = floatBitsToUint(x);
    return uintBitsToFloat(bits > ulps ? bits - ulps : 0u);
}

void cone() {
    uvec2 p = uvec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y + params.row0);
    if (p.x >= params.width || p.y >= params.height) {
        return;
    }
    uint index = p.y * params.width + p.x;
    float hp = pyramid[index];
    uint top = top_level();
    uint top_offset = level_offset(top);
    float best = CONE_RATIO_MAX;
    // Centre in texels; the v axis is scaled to u-texel units only inside cone_map_value.
    vec2 centre = vec2(p) + 0.5;
    uint offsets[MAX_LEVELS];
    for (uint l = 0u; l <= top; ++l) {
        offsets[l] = level_offset(l);
    }
    // Stack entries: (level, i | j << 16) (maps are at most 65535 texels a side) and the bound,
    // re-checked on pop since the best may have improved after the push.
    uvec2 stack_node[STACK];
    float stack_bound[STACK];
    int tiles = params.repeat_address != 0u ? 9 : 1;
    for (int t = 0; t < tiles && pyramid[top_offset] > hp; ++t) {
        // Tile (a, b) of the 3x3 block, the map itself (slot 4) first so the ring starts pruned.
        int slot = (t + 4) % 9;
        int a = slot % 3 - 1;
        int b = slot / 3 - 1;
        vec2 tile = vec2(float(a) * float(params.width), float(b) * float(params.height));
        int sp = 0;
        Node root = node_rect(top, uvec2(0u), tile);
        float root_rise = pyramid[top_offset] - hp;
        float root_bound = cone_map_value(centre, root.lo, root.hi, root_rise);
        if (root_bound < best) {
            stack_node[0] = uvec2(top, 0u);
            stack_bound[0] = root_bound;
            sp = 1;
        }
        while (sp > 0) {
            --sp;
            if (!(stack_bound[sp] < best)) {
                continue;
            }
            uint level = stack_node[sp].x;
            uvec2 at = uvec2(stack_node[sp].y & 0xffffu, stack_node[sp].y >> 16);
            if (level == 0u) {
                best = stack_bound[sp];
                continue;
            }
            // The children on the level below, clipped to it, with their bounds.
            uint child = level - 1u;
            uvec2 size = level_size(child);
            uvec2 first = at * 2u;
            uvec2 last = min(first + 1u, size - 1u);
            uvec2 kid_node[4];
            float kid_bound[4];
            int kids = 0;
            for (uint y = first.y; y <= last.y; ++y) {
                for (uint x = first.x; x <= last.x; ++x) {
                    float h = pyramid[offsets[child] + y * size.x + x];
                    if (!(h > hp)) {
                        continue;
                    }
                    Node n = node_rect(child, uvec2(x, y), tile);
                    float bound = cone_map_value(centre, n.lo, n.hi, h - hp);
                    if (bound < best) {
                        kid_node[kids] = uvec2(child, x | (y << 16));
                        kid_bound[kids] = bound;
                        ++kids;
                    }
                }
            }
            // Farthest first onto the stack, so the nearest is searched next (insertion sort by
            // descending bound; at most four).
            for (int k = 1; k < kids; ++k) {
                uvec2 node = kid_node[k];
                float bound = kid_bound[k];
                int m = k - 1;
                while (m >= 0 && kid_bound[m] < bound) {
                    kid_node[m + 1] = kid_node[m];
                    kid_bound[m + 1] = kid_bound[m];
                    --m;
                }
                kid_node[m + 1] = node;
                kid_bound[m + 1] = bound;
            }
            // sp < STACK always holds (see STACK); the test only keeps the access in bounds.
            for (int k = 0; k < kids && sp < STACK; ++k) {
                stack_node[sp] = kid_node[k];
                stack_bound[sp] = kid_bound[k];
                ++sp;
            }
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
