#version 460
// The exact-horizon AO map by line sweeps (Timonen and Westerholm 2010), one dispatch per azimuth:
// every texel centre lies on exactly one line of lattice step `walk` (a primitive integer vector,
// so each line passes through texel centres at every step), and one invocation walks one line.
// Walking it, the points behind (toward the horizon direction -walk) are kept as their upper
// convex hull on a stack: the point being visited pops every hull point that the one below it
// hides, and its horizon is then the slope toward the top. Each point is pushed and popped at most
// once, so a dispatch is linear in the points walked.
//
// The profile is the bilinear surface along the line: each texel centre on it plus every crossing
// of a texel-centre grid line between two of them, where the bilinear surface is linear along the
// crossed edge and so exact. (Between crossings it is a quadratic; its bulge above the chord is
// the only thing the hull misses.) At each recorded texel the horizon also takes the surface's
// tangent toward it, the limit at distance 0 that the reference includes and no chord reaches.
//
// Addressing, as the CPU reference's: under repeat a line is an orbit of `walk` on the torus, of
// `period` steps; it is walked twice and recorded on the second turn, when the hull holds a whole
// period behind every point, which is all a repeating profile can add (a copy farther away of the
// same height is seen lower). (Orbits longer than 4 map sides, from sizes with few common factors,
// are cut into segments warmed by 4 sides of profile: there a horizon more than 4 sides away is
// missed, which is at most atan(s / 4) high.) Under clamp a line starts where both coordinates have left the map
// behind (from there on backward the clamped extension is constant, so one point stands for all
// of it) and ends at its last texel inside the map.
//
// Walks are resumable: one dispatch walks at most `chunk_steps` lattice steps of every line and
// saves where it stopped (lattice point, hull extent) after the line's hull entries (the hull
// itself stays in its ring); the host dispatches each azimuth until its longest line is done. Lavapipe (llvmpipe's
// gallivm) gives an invocation 65535 loop iterations in all, shared by every loop in the shader,
// and then silently ends every loop: whole walks of the steepest azimuths (a dozen profile points
// a step, each a pop loop and a crossing loop iteration) ran out at about 360 steps, so long
// repeat orbits lost the occlusion of their last texels (a row pattern at 192^2 and above). For
// the same reason the addressing below wraps with conditionals, not loops.
//
// Modes: UNPACK copies level 0 of the height image into `field`; SWEEP adds
// weight * (slice occlusion) to each texel of the direction's lines in `accum` (directions run as
// successive dispatches with a barrier between, so no two invocations ever write one texel at
// once); RESOLVE writes ao = clamp(1 - accum, 0, 1) into the AO image, exactly 1 where nothing
// occludes (every slope 0).
#extension GL_GOOGLE_include_directive : require
#include "ao.glsl"

layout(local_size_x = 64) in;

// MODE_SWEEP, MODE_RESOLVE, MODE_UNPACK, the bindings and the push-constant fields come with
// ao.glsl's include of interface.glsl.
// Hull entries kept per line (a power of two). A fuller stack forgets its oldest, farthest entry:
// only a horizon seen more than AO_HULL_CAPACITY (128) hull vertices away, always a very flat
// one, can be lost.
const uint HULL_CAPACITY = AO_HULL_CAPACITY;
// Slots per line after the ring.
const uint STATE_SLOTS = AO_STATE_SLOTS;

// Per line, a ring of hull entries: (lattice step, fraction of the step, height), then two slots
// of walk state saved between dispatches (STATE_SLOTS): (next step, lattice point, hull top) and
// (hull base); the newest hull entry is the ring's at top - 1. Steps, points and counts are plain
// floats, exact below 2^24 (walks are far shorter): their int bits would be denormals, which
// implementations may flush to zero on the way through memory.
layout(set = 0, binding = BINDING_AO_HULLS, std430) buffer Hulls {
    vec4 hulls[];
};

// Per texel (row-major), the weighted occlusion summed over the directions done so far.
layout(set = 0, binding = BINDING_AO_ACCUM, std430) buffer Accum {
    float accum[];
};

// Level 0 of the height image, row-major, unpacked once: the walks read it at every profile
// point, and a buffer load is far cheaper than a texel fetch on software rasterisers.
layout(set = 0, binding = BINDING_AO_FIELD, std430) buffer Field {
    float field[];
};

// The grid-line crossings inside one lattice step, per azimuth (render::ao_sweep::Crossing):
// the crossed edge's lower end from the step's start, the edge's direction, and the fractions
// along the step and along the edge. Listed by the host, so the walks divide no integers (a
// vector integer division is a loop of scalar ones on CPU implementations).
struct Crossing {
    ivec2 offset;
    ivec2 along;
    vec2 fractions;
};

layout(set = 0, binding = BINDING_AO_CROSSINGS, std430) readonly buffer Crossings {
    Crossing crossings[];
};

// The fields: AoSweepParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    AO_SWEEP_PARAMS_FIELDS
} params;

// floor(a / b) for b != 0, whatever the signs.
int floor_div(int a, int b) {
    int q = a / b;
    return (q * b != a && ((a < 0) != (b < 0))) ? q - 1 : q;
}

// The lattice steps k at which coordinate p0 + k * rate lies in [0, n - 1]: (lo, hi), empty when
// lo > hi; every k when rate is 0 and p0 is inside.
ivec2 inside_steps(int p0, int rate, int n) {
    if (rate == 0) {
        return (p0 >= 0 && p0 < n) ? ivec2(-2147483647, 2147483647) : ivec2(1, 0);
    }
    int a = rate > 0 ? -p0 : n - 1 - p0;
    int b = rate > 0 ? n - 1 - p0 : -p0;
    // ceil(a / rate) .. floor(b / rate), for rate of either sign (a and b swap with it).
    return ivec2(-floor_div(-a, rate), floor_div(b, rate));
}

// The most a wrapped coordinate is ever off the map: a lattice step (|walk| <= 12, ao_sweep's
// MAX_STEP) plus a neighbour.
const int NEAR_REACH = 16;

// Index k of an axis of n texels under the addressing, for k within NEAR_REACH of [0, n): the
// walks keep their lattice point inside the map, so a wrap is one conditional add or subtract,
// not a `%` (nor a loop, see the lavapipe note above); only maps narrower than that take the `%`.
int near_address(int k, int n, bool repeat) {
    if (!repeat) {
        return clamp(k, 0, n - 1);
    }
    if (n < NEAR_REACH) {
        return ao_address(k, n, true);
    }
    k += k < 0 ? n : 0;
    return k >= n ? k - n : k;
}

// The height of texel t (near the map) under the map's addressing.
float height(ivec2 t, bool repeat) {
    int x = near_address(t.x, params.size.x, repeat);
    int y = near_address(t.y, params.size.y, repeat);
    return field[y * params.size.x + x];
}

// A line's hull: entries [base, top) of its ring at `at`, the newest also kept in registers, so
// a visit that pops nothing reads one entry from memory.
struct Hull {
    uint base;
    uint top;
    uint at;
    vec4 last;
};

vec4 hull_get(Hull hull, uint i) {
    return hulls[hull.at + (i & (HULL_CAPACITY - 1u))];
}

// Visits profile point (step k + fraction f, height h): pops the hull points it hides and returns
// the tangent of the horizon behind it (0 when nothing is above), then pushes it.
float visit(inout Hull hull, int k, float f, float h) {
    while (hull.top - hull.base >= 2u) {
        vec4 b = hull_get(hull, hull.top - 2u);
        float dt = (float(k) - hull.last.x) + (f - hull.last.y);
        float db = (float(k) - b.x) + (f - b.y);
        // The newest lies on or below the line from this point to b: no horizon, now or later.
        if ((b.z - h) * dt < (hull.last.z - h) * db) {
            break;
        }
        hull.top -= 1u;
        hull.last = b;
    }
    float tau = 0.0;
    if (hull.top > hull.base) {
        float dt = (float(k) - hull.last.x) + (f - hull.last.y);
        tau = max(params.depth_scale * (hull.last.z - h) / (dt * params.step_uv), 0.0);
    }
    if (hull.top - hull.base == HULL_CAPACITY) {
        hull.base += 1u;
    }
    hull.last = vec4(float(k), f, h, 0.0);
    hulls[hull.at + (hull.top & (HULL_CAPACITY - 1u))] = hull.last;
    hull.top += 1u;
    return tau;
}

// Visits the crossings of grid lines strictly between lattice points p and p + walk, in order.
// The bilinear surface is linear along the crossed edge, so each height is exact. Under clamp, a
// crossing of a column (row) outside the map lies where the extension is linear along the line
// between the row (column) crossings around it: it can never be a hull vertex, so it is skipped,
// which makes the long walks through the clamped extension one point per step.
void visit_crossings(inout Hull hull, ivec2 p, int k, bool repeat) {
    for (uint c = 0u; c < params.crossing_count; ++c) {
        Crossing x = crossings[params.crossing_base + c];
        ivec2 at = p + x.offset;
        int across = x.along.y != 0 ? at.x : at.y;
        int n = x.along.y != 0 ? params.size.x : params.size.y;
        if (!repeat && (across < 0 || across >= n)) {
            continue;
        }
        float h0 = height(p + x.offset, repeat);
        float h1 = height(p + x.offset + x.along, repeat);
        visit(hull, k, x.fractions.x, h0 + x.fractions.y * (h1 - h0));
    }
}

// The line's first lattice point, the step to start at and the steps [first, last] to record.
void line_span(uint l, bool repeat, out ivec2 p0, out int start, out ivec2 record) {
    if (repeat) {
        uint orbit = l / params.segments;
        int first = int((l % params.segments) * params.segment_steps);
        int count = min(int(params.segment_steps), int(params.period) - first);
        int warm = int(params.warm_steps);
        // The orbit's start moved on to `first - warm` steps (an exact wrap of a bounded product).
        ivec2 from = ivec2(int(orbit % params.g_a), int(orbit / params.g_a)) + (first - warm) * params.walk;
        p0 = ivec2(ao_address(from.x, params.size.x, true), ao_address(from.y, params.size.y, true));
        start = 0;
        record = ivec2(warm, warm + count - 1);
        return;
    }
    int c = params.c_min + int(l);
    ivec2 origin = c * params.euclid;
    ivec2 ix = inside_steps(origin.x, params.walk.x, params.size.x);
    ivec2 iy = inside_steps(origin.y, params.walk.y, params.size.y);
    record = ivec2(max(ix.x, iy.x), min(ix.y, iy.y));
    // Back to where every moving coordinate is outside the map, the clamped extension constant.
    int before_x = params.walk.x != 0 ? ix.x - 1 : 2147483647;
    int before_y = params.walk.y != 0 ? iy.x - 1 : 2147483647;
    start = min(before_x, before_y);
    p0 = origin + start * params.walk;
    record -= start;
    start = 0;
}

// The tangent of the surface's slope at texel centre p (height hp) toward the horizon: the
// derivative of the bilinear cell behind p along -walk, per uv. The reference's horizon includes
// this limit of the slope as the distance goes to 0, which no chord to a later point reaches
// where the profile bulges up.
float tangent(ivec2 p, float hp, bool repeat) {
    ivec2 back = -sign(params.walk);
    ivec2 w = abs(params.walk);
    float rise = float(w.x) * (height(p + ivec2(back.x, 0), repeat) - hp)
               + float(w.y) * (height(p + ivec2(0, back.y), repeat) - hp);
    return params.depth_scale * rise / params.step_uv;
}

void sweep() {
    uint l = gl_GlobalInvocationID.x;
    if (l >= params.lines) {
        return;
    }
    bool repeat = params.repeat_address != 0u;
    ivec2 p;
    int start;
    ivec2 record;
    line_span(l, repeat, p, start, record);
    if (record.x > record.y) {
        return;
    }
    int first = start + int(params.chunk * params.chunk_steps);
    int last = min(record.y, first + int(params.chunk_steps) - 1);
    if (first > last) {
        return;
    }
    uint at = l * (HULL_CAPACITY + STATE_SLOTS);
    uint state = at + HULL_CAPACITY;
    Hull hull = Hull(0u, 0u, at, vec4(0.0));
    if (params.chunk > 0u) {
        // Resume where the previous dispatch stopped (at step `first`, which it saved).
        vec4 s = hulls[state];
        p = ivec2(s.yz);
        hull.top = uint(s.w);
        hull.base = uint(hulls[state + 1u].x);
        hull.last = hull_get(hull, hull.top - 1u);
    }
    for (int k = first; k <= last; ++k) {
        float hp = height(p, repeat);
        float tau = visit(hull, k, 0.0, hp);
        if (k >= record.x) {
            tau = max(tau, tangent(p, hp, repeat));
            vec3 n = ao_normal_of(height(p - ivec2(1, 0), repeat), height(p + ivec2(1, 0), repeat),
                                  height(p - ivec2(0, 1), repeat), height(p + ivec2(0, 1), repeat),
                                  params.size, params.depth_scale);
            uint index = uint(p.y * params.size.x + p.x);
            accum[index] += params.weight * ao_slice_occlusion(n, params.dir, tau);
        }
        if (k < record.y) {
            visit_crossings(hull, p, k, repeat);
        }
        p += params.walk;
        if (repeat) {
            p = ivec2(near_address(p.x, params.size.x, true), near_address(p.y, params.size.y, true));
        }
    }
    if (last < record.y) {
        hulls[state] = vec4(float(last + 1), vec2(p), float(hull.top));
        hulls[state + 1u] = vec4(float(hull.base), 0.0, 0.0, 0.0);
    }
}

void resolve() {
    // Dispatched as rows of 64-texel groups (x) by rows (y), within the group count limits.
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (t.x >= params.size.x || t.y >= params.size.y) {
        return;
    }
    float ao = clamp(1.0 - accum[t.y * params.size.x + t.x], 0.0, 1.0);
    imageStore(ao_out, t, vec4(ao));
}

void unpack() {
    // Dispatched as rows of 64-texel groups (x) by rows (y), within the group count limits.
    ivec2 t = ivec2(gl_GlobalInvocationID.xy);
    if (t.x >= params.size.x || t.y >= params.size.y) {
        return;
    }
    field[t.y * params.size.x + t.x] = texelFetch(heights, t, 0).r;
}

void main() {
    if (params.mode == MODE_SWEEP) {
        sweep();
    } else if (params.mode == MODE_RESOLVE) {
        resolve();
    } else {
        unpack();
    }
}
