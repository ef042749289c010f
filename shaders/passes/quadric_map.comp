#version 460
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_control_flow_attributes : require
// The quadric map on the GPU (heightfield::quadric_map, Kiglics et al.): per texel the profile
// [a, b, c, h] of a cone continued by a parabola and a flat cap, F(r) = b r / a up to a, then
// b + (r - a)(2c - r - a) up to c, then b + (c - a)^2, such that the bilinear surface B never
// rises above B(q) + F(|x - q|) for any q in the texel's footprint.
//
// The bound rests on the same radial facts as the CPU builder: per texel its least bilinear
// height h_lo on the footprint and its steepest bilinear gradient L within one texel; a group of
// texels at uv distance >= d (between the footprint and their bilinear supports) whose heights
// are <= m contributes the point (max(d, reach(m - h_lo)), m - h_lo), which dominates every one
// of them because F is non-decreasing. The CPU prunes a concave hull of such points through its
// pyramid; here every texel instead takes a fixed covering of the plane by pyramid nodes, a ring
// of nodes per level (those within ring_at(level) nodes of the texel's own node, Chebyshev, on
// the torus under Repeat, that have a child outside the ring of the level below), which covers
// each texel of the map at least once: a texel is in the node of the first level whose ring
// holds it. The rings need not nest, so the finest levels, whose nodes lie nearest, take wider
// rings. Nodes then lie at least about ring / 2 of their own sides away, so the points are the
// CPU's within a factor of about 1 + 2.8 / ring in distance.
//
// The profile is fitted to the points directly, with no hull: the cone's slope is the steepest
// value / r (a its r, the farthest among ties), and c the least value that lifts F above every
// point beyond a, exactly (for a point (r, v) with x = r - a, y = v - b > 0 that is
// a + x / 2 + y / (2 x) when y >= x^2, else a + sqrt(y), where the cap meets it); the two-branch
// threshold increases with y and decreases with x, so rounding y up and x down keeps it safe.
// The cone is fitted to the texels within NEAR_RING only, then one pass over all points finds c
// (see quadric()).
//
// Rounding (the guarantee: an upper bound despite f32): h_lo is lowered by 2^-22 unless the 3x3
// texels around are equal (then it is exact), L raised by 1e-5 relative, node distances and
// gradient reaches lowered by 1e-6 relative, b raised by 1.2e-4 relative (NEAR_CONE) and c by 1e-6, more than
// the few-ulp errors of the f32 arithmetic under the Vulkan precision rules. These margins lift
// the GPU profile a little above the exact one for the same points.
//
// Two modes, chosen per dispatch by params.mode:
//  REDUCE: level L of the max pyramid of the heights (buffer_pyramid.glsl) from level L - 1.
//  QUADRIC: one invocation per texel of rows [row0, row0 + rows): the near texels, then one
//    pass over its rings, at most about (levels) (2 RING + 5)^2 loop iterations (lavapipe ends every loop of
//    an invocation after 65535 iterations in all: 15 levels and ring 8 stay far below).
layout(local_size_x = 8, local_size_y = 8) in;

// MODE_REDUCE, MODE_SEARCH (the quadric fit), MAX_LEVELS and the bindings.
#include "interface.glsl"

// All pyramid levels back to back, level 0 (the heights, width x height) first.
layout(set = 0, binding = BINDING_SEARCH_PYRAMID, std430) buffer Pyramid {
    float pyramid[];
};

// Per texel [a, b, c, h] (QuadricMap's texel), row-major.
layout(set = 0, binding = BINDING_SEARCH_MAP, std430) writeonly buffer QuadricMap {
    vec4 quadric_map[];
};

// The fields: QuadricMapParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    QUADRIC_MAP_PARAMS_FIELDS
} params;

// Reads and writes `pyramid` above.
#include "buffer_pyramid.glsl"

bool repeat_address() {
    return params.repeat_address != 0u;
}

ivec2 level_nodes(uint level) {
    return ivec2(pyramid_level_size(uvec2(params.width, params.height), level));
}

// Height of texel q (any integers within two texels of the map), addressed. Wrapped by two
// conditional steps rather than `%`: llvmpipe has no vector integer division and splits one
// into a scalar division per lane.
float height_at(ivec2 q) {
    ivec2 n = ivec2(params.width, params.height);
    ivec2 t = q;
    if (repeat_address()) {
        t = mix(t, t + n, lessThan(t, ivec2(0)));
        t = mix(t, t + n, lessThan(t, ivec2(0)));
        t = mix(t, t - n, greaterThanEqual(t, n));
        t = mix(t, t - n, greaterThanEqual(t, n));
    } else {
        t = clamp(t, ivec2(0), n - 1);
    }
    return pyramid[t.y * n.x + t.x];
}

// What the radial bound of texel p rests on: x = h_lo (rounded down), y = L (rounded up). The
// 5x5 texels around p are read once (every bilinear cell within a texel of the footprint).
vec2 texel_bound(ivec2 p) {
    float t[5][5];
    [[unroll]] for (int l = 0; l < 5; ++l) {
        [[unroll]] for (int k = 0; k < 5; ++k) {
            ivec2 d = ivec2(k - 2, l - 2);
            t[l][k] = height_at(p + d);
        }
    }
    float c = t[2][2];
    float lo = c;
    bool flat3 = true;
    for (int d = -1; d <= 1; d += 2) {
        float hu = t[2][2 + d];
        float hv = t[2 + d][2];
        lo = min(lo, min(0.5 * (c + hu), 0.5 * (c + hv)));
        for (int e = -1; e <= 1; e += 2) {
            float he = t[2 + e][2];
            float hc = t[2 + e][2 + d];
            lo = min(lo, 0.25 * (c + hu + he + hc));
            flat3 = flat3 && hu == c && hv == c && hc == c;
        }
    }
    // The means round; equal heights give exact ones.
    lo = flat3 ? lo : lo - 1.0 / 4194304.0;
    float w = float(params.width);
    float h = float(params.height);
    float lip = 0.0;
    [[unroll]] for (int l = 0; l < 4; ++l) {
        [[unroll]] for (int k = 0; k < 4; ++k) {
            float h00 = t[l][k];
            float h10 = t[l][k + 1];
            float h01 = t[l + 1][k];
            float h11 = t[l + 1][k + 1];
            float gu = w * max(abs(h10 - h00), abs(h11 - h01));
            float gv = h * max(abs(h01 - h00), abs(h11 - h10));
            lip = max(lip, length(vec2(gu, gv)));
        }
    }
    return vec2(lo, lip * (1.0 + 1.0e-5));
}

// Torus (Repeat) or plain (Clamp) distance in nodes along one axis of `count` nodes.
int node_distance(int m, int n, int count) {
    int d = abs(m - n);
    return repeat_address() ? min(d, count - d) : d;
}

// Gap in texels between footprint [i, i + 1] and the supports (k0 - 1/2, k1 + 3/2) of texels
// k0..k1 along an axis of n texels, the shortest way round under Repeat (as PyramidAxis::gap).
float axis_gap(int i, int k0, int k1, int n) {
    float after = float(k0 - i) - 1.5;
    float before = float(i - k1) - 1.5;
    float gap = max(max(after, before), 0.0);
    if (repeat_address()) {
        float fn = float(n);
        gap = min(gap, max(max(after + fn, before - fn), 0.0));
        gap = min(gap, max(max(after - fn, before + fn), 0.0));
    }
    return gap;
}

// One point of the radial bound: r (uv, rounded down) and value (height above h_lo).
struct Point {
    float r;
    float value;
};

// The gap (uv) between texel i's footprint and the supports of node m of `level` along an axis
// of n texels.
float node_gap(int i, int m, uint level, int n) {
    int k0 = m << level;
    int k1 = min((m + 1) << level, n) - 1;
    // The reciprocal is uniform, so it is computed once; its rounding is within the margin on
    // the distance (radial_point).
    return axis_gap(i, k0, k1, n) * (1.0 / float(n));
}

// The point of a node with gaps gu, gv and maximum height `top`, for a texel with bound `tb`.
Point radial_point(float gu, float gv, float top, vec2 tb) {
    Point pt;
    pt.value = top - tb.x;
    // Within one texel of the footprint the surface rises at most L per uv.
    float lip_radius = 1.0 / float(max(params.width, params.height));
    // value / L, lowered past the rounding of the reciprocal and the product.
    float reach = tb.y * lip_radius <= pt.value ? lip_radius : pt.value * (1.0 / tb.y) * (1.0 - 1.0e-6);
    pt.r = max(length(vec2(gu, gv)) * (1.0 - 1.0e-6), reach);
    return pt;
}

// Nodes on each side of the texel's own node in every level's ring (the two finest levels add 2
// and 1): the points stand for their nodes from about 1 + 2.8 / RING times nearer than the
// nodes' farthest texels, and each texel visits about levels (2 RING + 1)^2 nodes. Grazing rays
// step by the far profile, which the coarse levels bound: at 5 degrees on fbm 1024^2, quadric
// tracing through this map takes 25.5 steps against csm's 28.6, where 3 on the levels from 3 up
// gave 26.3 (8% fewer, against the paper's 5-20% and the CPU map's 13%); it costs about 10% more
// build time, which passing over rows (row_under_parabola) pays back.
const int RING = 4;

// Level 0's ring in the main pass (ring_at(0)).
const int FINE_RING = RING + 2;

// Whether level 0 may be read as rows of texels around the texel (FOR_EACH_TEXEL_POINT): the map
// is wide enough that no two offsets within FINE_RING wrap onto one texel and every wrapped gap
// equals the plain one.
bool texel_rows_fit() {
    uint side = uint(2 * FINE_RING + 1);
    return params.width > side && params.height > side;
}

// When >= 0, the half width of level 0's ring instead of ring_at's (the first, near pass).
int near_ring = -1;

// The ring's half width at `level`: wider on the two finest levels, whose nodes are near the
// texel, so that they are refined about where the CPU's hull search refines them.
int ring_at(uint level) {
    if (level == 0u && near_ring >= 0) {
        return near_ring;
    }
    return RING + max(2 - int(level), 0);
}

// Node indices of `level`'s ring along one axis: `first` and `count` (wrapped when used).
ivec2 ring_span(int n, int nodes, uint level) {
    int k = ring_at(level);
    if (repeat_address() && nodes <= 2 * k + 1) {
        return ivec2(0, nodes);
    }
    if (repeat_address()) {
        return ivec2(n - k, 2 * k + 1);
    }
    int first = max(n - k, 0);
    return ivec2(first, min(n + k, nodes - 1) - first + 1);
}

// Whether node index m (a level above 0) has a child outside the ring of the level below, along
// one axis whose texel index is i.
bool child_outside(int m, int i, uint level, int fine_nodes) {
    int n = i >> (level - 1u);
    int c0 = 2 * m;
    int c1 = min(2 * m + 1, fine_nodes - 1);
    int k = ring_at(level - 1u);
    return node_distance(c0, n, fine_nodes) > k || node_distance(c1, n, fine_nodes) > k;
}

// Where a run of ring columns that the level below covers ends, as an offset from `first` (the
// ring's first column, unwrapped), for texel index i; -1 where torus distances could differ from
// plain ones (small Repeat levels), so that each column is tested on its own. Columns whose two
// children lie within the ring below form one run, from the first such column up to
// floor((n + k - 1) / 2) with n and k the finer level's node index and ring.
int covered_run_end(int i, int first, uint level, int fine_nodes) {
    int k = ring_at(level - 1u);
    if (repeat_address() && fine_nodes <= 4 * k + 4) {
        return -1;
    }
    return ((i >> (level - 1u)) + k - 1) / 2 - first;
}

int wrap_index(int m, int nodes) {
    return m < 0 ? m + nodes : (m >= nodes ? m - nodes : m);
}

// Calls VISIT(pt) for the point of every node of the covering of texel p (see the header), level
// by level from FIRST, until STOP(level) says no point of that level or above can matter,
// passing over the levels where SKIP(p, tb, level) says none can. Row quantities are computed
// once per row, and runs of covered columns are skipped at once.
#define FOR_EACH_POINT(p, tb, FIRST, STOP, SKIP, ROW_SKIP, VISIT)                           \
    for (uint level = FIRST; level <= params.top; ++level) {                                \
        if (STOP(level)) {                                                                  \
            break;                                                                          \
        }                                                                                   \
        float level_top = ring_max(p, level);                                               \
        if (SKIP(level_top, tb, level)) {                                                   \
            continue;                                                                       \
        }                                                                                   \
        ivec2 nodes = level_nodes(level);                                                   \
        ivec2 fine = level == 0u ? nodes : level_nodes(level - 1u);                         \
        ivec2 su = ring_span(p.x >> level, nodes.x, level);                                 \
        ivec2 sv = ring_span(p.y >> level, nodes.y, level);                                 \
        int run_end = level == 0u ? -1 : covered_run_end(p.x, su.x, level, fine.x);         \
        for (int dv = 0; dv < sv.y; ++dv) {                                                 \
            int mv = wrap_index(sv.x + dv, nodes.y);                                        \
            bool out_v = level == 0u || child_outside(mv, p.y, level, fine.y);              \
            float gv = node_gap(p.y, mv, level, int(params.height));                        \
            if (ROW_SKIP(gv, level_top)) {                                                  \
                continue;                                                                   \
            }                                                                               \
            uint row = params.offsets[level] + uint(mv * nodes.x);                          \
            for (int du = 0; du < su.y; ++du) {                                             \
                int mu = wrap_index(su.x + du, nodes.x);                                    \
                if (!out_v && !child_outside(mu, p.x, level, fine.x)) {                     \
                    du = max(du, run_end);                                                  \
                    continue;                                                               \
                }                                                                           \
                float top = pyramid[row + uint(mu)];                                        \
                if (top > tb.x) {                                                           \
                    float gu = node_gap(p.x, mu, level, int(params.width));                 \
                    Point pt = radial_point(gu, gv, top, tb);                               \
                    VISIT(pt)                                                               \
                }                                                                           \
            }                                                                               \
        }                                                                                   \
    }

// FOR_EACH_POINT's level 0 for a ring of k <= FINE_RING texels where texel_rows_fit(): the same
// points in the same order (node_gap of a texel offset d is then max(|d| - 3/2, 0) texels), but
// each row's texels are read first and visited after, both unrolled, with no coverage tests;
// on lavapipe that makes level 0, most of a texel's points, several times cheaper. Under Clamp
// the offsets outside the map are not in the ring.
#define FOR_EACH_TEXEL_POINT(p, tb, k, ROW_SKIP, VISIT)                                    \
    for (int dv = -k; dv <= k; ++dv) {                                                      \
        float gv = max(max(float(dv) - 1.5, float(-dv) - 1.5), 0.0) * (1.0 / float(params.height)); \
        bool in_v = repeat_address() || uint(p.y + dv) < params.height;                     \
        float row_tops[2 * k + 1];                                                          \
        float row_top = tb.x;                                                               \
        [[unroll]] for (int du = -k; du <= k; ++du) {                                       \
            row_tops[du + k] = height_at(p + ivec2(du, dv));                                \
            row_top = max(row_top, row_tops[du + k]);                                       \
        }                                                                                   \
        if (!in_v || ROW_SKIP(gv, row_top)) {                                               \
            continue;                                                                       \
        }                                                                                   \
        [[unroll]] for (int du = -k; du <= k; ++du) {                                       \
            float top = row_tops[du + k];                                                   \
            bool in_u = repeat_address() || uint(p.x + du) < params.width;                  \
            if (top > tb.x && in_u && in_v) {                                               \
                float gu = max(max(float(du) - 1.5, float(-du) - 1.5), 0.0) * (1.0 / float(params.width)); \
                Point pt = radial_point(gu, gv, top, tb);                                   \
                VISIT(pt)                                                                   \
            }                                                                               \
        }                                                                                   \
    }

// The steepest value / r, and the farthest r that reaches it (ties within 1e-6); compared by
// products, so that only a point that changes the slope pays a division.
#define VISIT_SLOPE(pt)                                                                     \
    float level_r = slope * pt.r;                                                           \
    if (pt.value > level_r * (1.0 + 1.0e-6)) {                                              \
        slope = pt.value / pt.r;                                                            \
        a = pt.r;                                                                           \
    } else if (pt.value >= level_r * (1.0 - 1.0e-6)) {                                      \
        slope = max(slope, pt.value / pt.r);                                                \
        a = max(a, pt.r);                                                                   \
    }

// Texels on each side of the texel's own that the cone is fitted to.
const int NEAR_RING = 4;

// Points with r in (a, a (1 + NEAR_CONE)] are left to the rim height b (see quadric()).
const float NEAR_CONE = 1.0e-4;

// The least c lifting the parabola above the point (see the header for the rounding). The
// threshold a + lift exceeds c, with m = c - a, only if y > m^2 (x >= m) or y > x (2m - x)
// (x < m): tested first, with a margin for its rounding, so that most points pay no sqrt or
// division.
#define APEX_TEST(pt, a, margin, raises)                                                    \
    float x = (pt.r - a) * (1.0 - 2.4e-7);                                                  \
    float y = (pt.value * (1.0 + 2.4e-7) - b) * (1.0 + 2.4e-7);                             \
    float m = c - a;                                                                        \
    float needs = x >= m ? m * m : x * (2.0 * m - x);                                       \
    bool raises = pt.r > a * (1.0 + NEAR_CONE) && y > 0.0 && y > needs * (1.0 - margin);

#define VISIT_APEX_OF(pt, a)                                                                \
    APEX_TEST(pt, a, 1.0e-5, raises)                                                        \
    if (raises) {                                                                           \
        float lift = y >= x * x ? 0.5 * x + y / (2.0 * x) * (1.0 + 4.0e-7) : sqrt(y);       \
        c = max(c, a + lift);                                                               \
    }

// The highest node of `level` that the ring of texel p can visit: the ring's span of 2k + 1
// nodes lies within at most two nodes per axis of the level `up` levels coarser (2k + 1
// consecutive nodes touch at most two aligned blocks of 2^up >= 2k), whose maximum bounds it;
// one wrap under Repeat reaches them, since 2^up > k.
float ring_max(ivec2 p, uint level) {
    int k = ring_at(level);
    uint up = 2 * k <= 8 ? 3u : 4u;
    if (level + up >= params.top) {
        // The top's single node.
        return pyramid[params.offsets[params.top]];
    }
    uint coarse = level + up;
    uint shift = up;
    ivec2 nodes = level_nodes(coarse);
    ivec2 first = (p >> level) - k;
    ivec2 last = (p >> level) + k;
    ivec2 lo = first >> shift;
    ivec2 hi = last >> shift;
    ivec2 fine = level_nodes(level);
    bool wraps = any(lessThan(first, ivec2(0))) || any(greaterThanEqual(last, fine));
    bool ragged = any(notEqual(fine & ((1 << shift) - 1), ivec2(0)));
    if (repeat_address() && wraps && ragged) {
        // A wrapped span may touch three coarse nodes where the last one is partial.
        return pyramid[params.offsets[params.top]];
    }
    if (repeat_address()) {
        lo = ivec2(wrap_index(lo.x, nodes.x), wrap_index(lo.y, nodes.y));
        hi = ivec2(wrap_index(hi.x, nodes.x), wrap_index(hi.y, nodes.y));
    } else {
        lo = clamp(lo, ivec2(0), nodes - 1);
        hi = clamp(hi, ivec2(0), nodes - 1);
    }
    uint base = params.offsets[coarse];
    float m = max(pyramid[base + uint(lo.y * nodes.x + lo.x)], pyramid[base + uint(lo.y * nodes.x + hi.x)]);
    return max(m, max(pyramid[base + uint(hi.y * nodes.x + lo.x)], pyramid[base + uint(hi.y * nodes.x + hi.x)]));
}

// Whether no point of `level` can change the profile [a, b, c] of texel p. A ring whose highest
// node is no higher than the texel's lowest point has no point at all (every node is dropped).
// Otherwise, above level 0, every node the covering visits has a child outside the ring of the
// level below, so its gap along one axis is at least (k - 1) 2^(level - 1) - 1/2 texels with k
// that ring's half width (its other child may lie just inside that ring); with the ring's
// highest value that gives one point dominating all of the level's points, and F is
// non-decreasing while the apex test's threshold grows with r and with c, so a level whose
// dominating point fails the test now fails it for every later c as well. Either way skipping
// the level leaves the map bit for bit unchanged.
bool level_under_parabola(float top, vec2 tb, uint level, float a, float b, float c) {
    if (top <= tb.x) {
        return true;
    }
    if (level == 0u) {
        return false;
    }
    int k = ring_at(level - 1u);
    float gap = float((k - 1) << (level - 1u)) - 0.5;
    float r_min = max(gap, 0.0) / float(max(params.width, params.height)) * (1.0 - 1.0e-5);
    if (!(r_min > a * (1.0 + NEAR_CONE))) {
        return false;
    }
    Point pt;
    pt.r = r_min;
    pt.value = top - tb.x;
    // A wider margin than the visit's: the rounded threshold may dip an ulp as x grows.
    APEX_TEST(pt, a, 2.0e-5, raises)
    return !raises;
}

// Whether no texel of a level-0 row at gap gv (uv, across rows) whose highest texel is row_top can
// change the profile: as level_under_parabola, with the row's gap for the dominating point's r
// (a texel's r is at least its gap's length, which is at least gv).
bool row_under_parabola(float gv, float row_top, vec2 tb, float a, float b, float c) {
    if (row_top <= tb.x) {
        return true;
    }
    Point pt;
    pt.r = gv * (1.0 - 1.0e-6) * (1.0 - 1.0e-6);
    pt.value = row_top - tb.x;
    if (!(pt.r > a * (1.0 + NEAR_CONE))) {
        return false;
    }
    APEX_TEST(pt, a, 2.0e-5, raises)
    return !raises;
}

// Whether the near pass can pass over level 0, whose ring's highest node is `top`: no texel of
// it rises above the texel's lowest point, so no slope.
bool ring_below_texel(float top, vec2 tb, uint level) {
    return top <= tb.x;
}

void quadric() {
    ivec2 p = ivec2(gl_GlobalInvocationID.x, gl_GlobalInvocationID.y + params.row0);
    bool texel_rows = texel_rows_fit();
    if (p.x >= int(params.width) || p.y >= int(params.height)) {
        return;
    }
    vec2 tb = texel_bound(p);
    uint index = uint(p.y) * params.width + uint(p.x);
    float h = pyramid[index];
    // The cone is fitted to the texels within NEAR_RING (its slope the steepest of theirs, a the
    // farthest r reaching it); every point beyond a then goes to the parabola, however steep
    // (c lifts F above it), and a point at or inside the cone's end steeper than the near texels
    // (rare) makes the cone steeper after the pass: a larger b only lowers the thresholds c was
    // fitted to, so c stays valid. One pass over the rings, with no second pass.
    float slope = 0.0;
    float a = 0.0;
#define FINEST_ONLY(level) level > 0u
#define ROW_BELOW_TEXEL(gv, row_top) (row_top <= tb.x)
#define NO_ROW_SKIP(gv, level_top) false
    near_ring = NEAR_RING;
    if (!texel_rows) {
        FOR_EACH_POINT(p, tb, 0u, FINEST_ONLY, ring_below_texel, NO_ROW_SKIP, VISIT_SLOPE)
    } else if (!ring_below_texel(ring_max(p, 0u), tb, 0u)) {
        FOR_EACH_TEXEL_POINT(p, tb, NEAR_RING, ROW_BELOW_TEXEL, VISIT_SLOPE)
    }
    near_ring = -1;
    // Nothing near rises above the texel's lowest point: any short cone will do.
    a = slope > 0.0 ? a : 0.5 / float(max(params.width, params.height));
    // Points within NEAR_CONE of a (relative) lie under b, so c never divides by a tiny x.
    float b = slope * a * (1.0 + NEAR_CONE + 2.0e-5);
    float c = a;
    float steep = 0.0;
#define NEVER(level) false
#define ROW_UNDER_PARABOLA(gv, row_top) row_under_parabola(gv, row_top, tb, a, b, c)
#define LEVEL_UNDER_PARABOLA(level_top, tb, level)                                          \
    level_under_parabola(level_top, tb, level, a, b, c)
#define VISIT_MAIN(pt)                                                                      \
    if (pt.r <= a * (1.0 + NEAR_CONE)) {                                                    \
        steep = max(steep, pt.value / pt.r);                                                \
    } else {                                                                                \
        VISIT_APEX_OF(pt, a)                                                                \
    }
    if (texel_rows && !level_under_parabola(ring_max(p, 0u), tb, 0u, a, b, c)) {
        FOR_EACH_TEXEL_POINT(p, tb, FINE_RING, ROW_UNDER_PARABOLA, VISIT_MAIN)
    }
    // Level 0 came from the texel rows above where they fit.
    FOR_EACH_POINT(p, tb, texel_rows ? 1u : 0u, NEVER, LEVEL_UNDER_PARABOLA, ROW_UNDER_PARABOLA, VISIT_MAIN)
    b = max(b, steep * a * (1.0 + NEAR_CONE + 2.0e-5));
    if (!(b > 0.0) && !(c > a)) {
        // Nothing rises above the texel's lowest point: the flat profile, as on the CPU.
        quadric_map[index] = vec4(1.0, 0.0, 1.0, h);
        return;
    }
    c = c > a ? c * (1.0 + 1.0e-6) : a;
    quadric_map[index] = vec4(a, b, c, h);
}

void main() {
    if (params.mode == MODE_REDUCE) {
        uint level = params.level;
        pyramid_reduce(uvec2(params.width, params.height), level, params.offsets[level - 1u],
                       params.offsets[level], gl_GlobalInvocationID.xy);
    } else {
        quadric();
    }
}
