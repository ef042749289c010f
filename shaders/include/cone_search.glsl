// What the cone-map builders' per-texel searches share (cone_map.comp, relaxed_cone.glsl): a
// candidate's value, node rectangles of the buffer pyramid, and the packed stack entries with their
// ordering. The includer declares a push-constant block `params` with `width`, `height` (level 0
// in texels) and `aspect` (width / height rounded to f32: a v distance in u-texel units is
// dy * aspect).

const float CONE_RATIO_MAX = 64.0;
// Entries a search stack can hold: a pop pushes at most 4 children, so a depth-first search over
// L levels holds at most 3 L + 1; 48 covers the 15 levels of maps up to 16384 texels a side.
const int STACK = 48;
const uint STEP_DOWN = 128u;

// The computed value of a node: its rectangle [lo, hi] (u-texels, v-texels; closed) seen from
// the centre c, plus `extra` u-texels, over the rise of its maximum. dx and dy are exact
// (half-integers below 2^22); the error is one rounding each for dx^2, aspect, dy * aspect, its
// square, the sum, rise, w * rise, plus sqrt (5 ULP) and the division (2.5 ULP): about 12.5
// units of 2^-23 with extra = 0 (adding extra exactly leaves the sum exact), a few more for the
// relaxed cone's extra, so EPS_ULPS = 20. STEP_DOWN ulps of the result are at least
// STEP_DOWN * 2^-24 relative, more than 3x that error.
float cone_map_value(vec2 c, vec2 lo, vec2 hi, float rise, float extra) {
    float dx = max(max(lo.x - c.x, c.x - hi.x), 0.0);
    float dy = max(max(lo.y - c.y, c.y - hi.y), 0.0) * params.aspect;
    float den = float(params.width) * rise;
    // Division has no precision guarantee below 2^-126; there the true value (at least half a
    // texel over den) is far above the cap anyway, so the candidate is dropped.
    if (!(den > 1.0e-30)) {
        return 3.0e38;
    }
    return (sqrt(dx * dx + dy * dy) + extra) / den;
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

// A stack entry: level | i << 4 | j << 18 (sides below 2^14, levels below 16) and the bound's bits,
// re-checked on pop since the best may have improved after the push.
uvec2 entry(uint level, uint i, uint j, float bound) {
    return uvec2(level | (i << 4) | (j << 18), floatBitsToUint(bound));
}

uint entry_level(uint packed) {
    return packed & 15u;
}

uvec2 entry_at(uint packed) {
    return uvec2((packed >> 4) & 0x3fffu, packed >> 18);
}

// The bits of a bound no candidate has: above every finite float.
const uint NO_BOUND = 0xffffffffu;

// Puts the larger bound first (NO_BOUND counts as the largest).
void order(inout uvec2 a, inout uvec2 b) {
    if (a.y < b.y) {
        uvec2 t = a;
        a = b;
        b = t;
    }
}

// The depth-first search's stack: one array of packed entries (private arrays indexed at run
// time are costly on some implementations; lavapipe spills them to memory, so a search keeps just
// this one).
uvec2 search_stack[STACK];

// Pushes a node's children (entries, NO_BOUND for none) sorted by a fixed network of swaps, the
// nearest last so it is searched next. sp < STACK always holds (see STACK); the check only keeps
// the accesses in bounds.
void push_children(inout int sp, uvec2 e0, uvec2 e1, uvec2 e2, uvec2 e3) {
    // Descending by bound (positive floats order as their bits).
    order(e0, e1);
    order(e2, e3);
    order(e0, e2);
    order(e1, e3);
    order(e1, e2);
    if (e0.y != NO_BOUND && sp < STACK) { search_stack[sp++] = e0; }
    if (e1.y != NO_BOUND && sp < STACK) { search_stack[sp++] = e1; }
    if (e2.y != NO_BOUND && sp < STACK) { search_stack[sp++] = e2; }
    if (e3.y != NO_BOUND && sp < STACK) { search_stack[sp++] = e3; }
}
