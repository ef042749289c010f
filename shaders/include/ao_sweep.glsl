// What the exact-horizon AO kernels share: the sweep is ao_sweep.comp, one dispatch per chunk
// of an azimuth's lines; ao_sweep_unpack.comp copies level 0 of the height image into `field`
// before it, and ao_sweep_resolve.comp writes ao = clamp(1 - accum, 0, 1) into the AO image
// after every direction, exactly 1 where nothing occludes (every slope 0).
//
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
// the same reason the addressing (ao_sweep.comp) wraps with conditionals, not loops.
#ifndef AO_SWEEP_GLSL
#define AO_SWEEP_GLSL

#include "ao.glsl"

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

#endif
