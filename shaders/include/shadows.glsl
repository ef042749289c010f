// Self-shadowing of a relief hit by its own height field, toward a disk light (docs/conventions.md,
// "Light"): the visible fraction of the light's disk of directions. Every soft mode estimates the
// horizon of the field in the light's azimuth (the steepest rise of the surface seen from the hit,
// as a tangent) and takes the share of the disk above that edge; they differ in how they find it:
//   2 pom-soft  Tatarchuk 2006: SHADOW_STEPS bilinear samples in equal steps along the light ray
//               out to where the disk's lowest direction clears the top plane;
//   3 horizon   Drobot Listing 1.4: SHADOW_STEPS samples at growing distances, each read from the
//               max pyramid at the level whose node spans the gap since the previous sample;
//   4 cone      the light's cone walked through the max pyramid: nodes that cannot raise the horizon
//               above what already matters are skipped whole, the rest refined down to the leaf
//               level, where the bilinear surface's steepest rise is found in closed form. The
//               horizon it finds along the centre's azimuth is exact; the disk's other azimuths
//               are assumed to see the same horizon.
// 1 hard is Policarpo et al. 2005's ray from the top plane toward the hit, traced by the method.
// The includer provides conventions.glsl, heightfield.glsl and the method (METHOD_TRACE).
#ifndef SHADOWS_GLSL
#define SHADOWS_GLSL

// relief's own shaders read the specialization ids from the interface; the shader library's
// relief.glsl defines them from the includer's RELIEF_SPEC_ID_BASE instead.
#ifndef RELIEF_SHADER_LIBRARY
#include "interface.glsl"
#endif
#include "pyramid.glsl"

// One of SHADOW_MODE_NONE, _HARD, _POM_SOFT, _HORIZON, _CONE (interface.glsl).
layout(constant_id = SPEC_SHADOW_MODE) const uint SHADOW_MODE = 0u;
// Samples (pom-soft, horizon) or the iteration cap of the pyramid walk (cone).
layout(constant_id = SPEC_SHADOW_STEPS) const uint SHADOW_STEPS = 16u;
// Horizon mode: how far out its samples reach, as a multiple of the distance at which the disk's
// lowest direction clears the top plane (Drobot's light vector scale).
layout(constant_id = SPEC_SHADOW_REACH) const float SHADOW_REACH = 1.0;

const float SHADOW_PI = 3.14159265358979;
// Elevations are clamped below pi/2 before tan(): float's pi/2 lies past the pole, where tan() is
// hugely negative.
const float MAX_SHADOW_ELEVATION = 1.5707;

// How far (in texels, uv and depth together) a hard shadow ray's first hit must lie from the
// shaded point to count as a blocker rather than the point itself seen through the method's own
// error: set per method (`hard_shadow_texels` in src/render/kit/hard_shadow.rs), small for methods
// that meet the surface exactly, larger for fixed-step searches, whose shadow rays land short
// or long of the point.
layout(constant_id = SPEC_HARD_SHADOW_TEXELS) const float HARD_SHADOW_TEXELS = 0.25;

// Farthest the sampling modes (pom-soft, horizon) spread their samples, in uv units: one map
// width covers a repeating tile, and a clamped map is a plateau beyond its edge. The cone walk
// needs no such cap: it stops where nothing can matter any more, or at its budget.
const float SHADOW_MAX_REACH = 1.0;

// Share of a disk of angular radius r whose centre stands `delta` (radians) above a straight edge.
float disk_above_edge(float delta, float r) {
    if (r <= 0.0) {
        return delta > 0.0 ? 1.0 : 0.0;
    }
    float x = clamp(delta / r, -1.0, 1.0);
    return 0.5 + (x * sqrt(1.0 - x * x) + asin(x)) / SHADOW_PI;
}

// The light as the horizon searches see it, from a hit at height `zp` above the bottom plane.
struct ShadowQuery {
    vec2 uv;          // the hit
    float zp;         // the surface's height above the bottom plane there, uv units (s * h)
    vec2 d;           // unit uv direction toward the light
    float elevation;  // of the light's centre, radians
    float radius;     // angular radius, radians
    float s;          // depth scale
    float reach;      // how far along d a blocker can matter, uv units
    // Curved relief (curved.glsl): the curved top falls below the plane through the hit parallel
    // to the entry's tangent plane by bend_slope x + bend_curve x^2 at x uv units along d, and
    // the field hangs from it; both 0 under a flat polygon.
    float bend_slope;
    float bend_curve;
};

ShadowQuery shadow_query(vec2 uv_hit, float z_hit, vec3 l, float radius, float s, vec2 bend) {
    ShadowQuery q;
    q.bend_slope = bend.x;
    q.bend_curve = bend.y;
    q.uv = uv_hit;
    // The surface's own height at the hit, not the method's z: the searches below compare
    // heights with it, and a method's small depth error would otherwise read as a blocker.
    q.zp = s * height_bilinear_exact(uv_hit);
    float flat_len = length(l.xy);
    q.d = flat_len > 1e-7 ? l.xy / flat_len : vec2(1.0, 0.0);
    q.elevation = atan(l.z, flat_len);
    q.radius = radius;
    q.s = s;
    float lowest = q.elevation - radius;
    float rise = max(s - q.zp, 0.0);
    q.reach = lowest > 1e-4 ? rise / tan(min(lowest, MAX_SHADOW_ELEVATION)) : 3.0e38;
    // A hit on the top plane has nothing above it but still takes a sample or two.
    vec2 texel = 1.0 / height_size();
    q.reach = max(q.reach, min(texel.x, texel.y));
    return q;
}

// The lowest horizon there is: a flat top plane's, 0 (directions below the horizontal never
// leave it); a curved top's falls away with it, down to its tangent at the search's far end.
float horizon_floor(ShadowQuery q) {
    return -q.bend_slope - q.bend_curve * min(q.reach, SHADOW_MAX_REACH);
}

// A rise tangent `tau` seen at x along d, taken relative to the curved top (unchanged when flat).
float bent_tangent(ShadowQuery q, float x, float tau) {
    return tau - q.bend_slope - q.bend_curve * x;
}

// Visible share of the disk over a horizon of tangent `tau`, never below the top's own.
float visible_over(ShadowQuery q, float tau) {
    return clamp(disk_above_edge(q.elevation - atan(max(tau, horizon_floor(q))), q.radius), 0.0, 1.0);
}

// Gradient (dh/du, dh/dv) of the bilinear surface itself at uv, inside the cell holding it: the
// slope the exact reference sees at a point, unlike height_gradient's central differences.
vec2 bilinear_gradient(vec2 uv) {
    vec2 size = height_size();
    vec2 g = uv * size - 0.5;
    vec2 cell = floor(g);
    vec2 f = g - cell;
    vec4 h = bilinear_corners(cell);
    return vec2(mix(h.y - h.x, h.w - h.z, f.y), mix(h.z - h.x, h.w - h.y, f.x)) * size;
}

// The horizon right at the hit: the surface's own rise toward the light (its tangent plane), so
// a point on a slope facing away from the light is dark before any blocker is searched for.
float tangent_horizon(ShadowQuery q) {
    return bent_tangent(q, 0.0, q.s * dot(bilinear_gradient(q.uv), q.d));
}

// Tangent of the elevation of the bilinear surface at distance x along the query's direction.
float rise_tangent(ShadowQuery q, float x) {
    float h = q.s * height_bilinear_exact(q.uv + x * q.d);
    return bent_tangent(q, x, (h - q.zp) / x);
}

float shadow_pom_soft(ShadowQuery q) {
    uint n = max(SHADOW_STEPS, 1u);
    float tau = tangent_horizon(q);
    for (uint k = 1u; k <= n; ++k) {
        tau = max(tau, rise_tangent(q, min(q.reach, SHADOW_MAX_REACH) * float(k) / float(n)));
    }
    return visible_over(q, tau);
}

float shadow_horizon(ShadowQuery q) {
    uint n = max(SHADOW_STEPS, 1u);
    vec2 texels = height_size();
    float texels_per_uv = max(abs(q.d.x) * texels.x, abs(q.d.y) * texels.y);
    float reach = min(q.reach, SHADOW_MAX_REACH) * SHADOW_REACH;
    float top = float(pyramid_top());
    float tau = tangent_horizon(q);
    float prev = 0.0;
    for (uint k = 1u; k <= n; ++k) {
        // Geometric spacing: the near samples resolve the slope at the hit, the far ones are
        // coarse pyramid nodes standing for everything since the previous sample.
        float x = reach * exp2(float(k) - float(n));
        float gap_texels = (x - prev) * texels_per_uv;
        float level = clamp(floor(log2(max(gap_texels, 1.0))), 0.0, top);
        float h = level < 0.5 ? height_bilinear_exact(q.uv + x * q.d)
                              : height_max(q.uv + x * q.d, level);
        tau = max(tau, bent_tangent(q, x, (q.s * h - q.zp) / x));
        prev = x;
    }
    return visible_over(q, tau);
}

// Distance along the query's direction at which the point uv + x d leaves its cell at `level`.
float shadow_cell_exit(ShadowQuery q, float x, int level) {
    vec2 size = level_size(level);
    vec2 p = (q.uv + x * q.d) * size;
    vec2 cell = floor(p);
    float exit_x = 3.0e38;
    for (int axis = 0; axis < 2; ++axis) {
        float dv = q.d[axis] * size[axis];
        if (abs(dv) > 1e-12) {
            float line = cell[axis] + (dv > 0.0 ? 1.0 : 0.0);
            exit_x = min(exit_x, (line - p[axis]) / dv);
        }
    }
    return x + exit_x;
}

// Height of the max-pyramid node holding uv at `level`, fetched by integer texel (pyramid.glsl
// says why not through the sampler).
float node_height(vec2 uv, int level) {
    vec2 size = level_size(level);
    return counted_texel(height_point, address_cell(floor(uv * size), size), level).r;
}

// The largest rise tangent over [xa, xe] inside bilinear cell `cell`, where the ray's offset in
// cell units is f0 + x * df. `at_hit`: the span starts at the hit, which lies on this surface.
float cell_max_tangent(ShadowQuery q, vec2 cell, vec2 f0, vec2 df, float xa, float xe, bool at_hit) {
    vec4 h = bilinear_corners(cell);
    float a = h.y - h.x, b = h.z - h.x, c = h.w - h.y - h.z + h.x;
    float A = h.x + a * f0.x + b * f0.y + c * f0.x * f0.y;
    float B = a * df.x + b * df.y + c * (f0.x * df.y + f0.y * df.x);
    float C = c * df.x * df.y;
    float K = at_hit ? 0.0 : q.s * A - q.zp;
    // A curved top's fall adds to the linear and quadratic terms.
    float b1 = q.s * B - q.bend_slope;
    float c1 = q.s * C - q.bend_curve;
    float t = max(K / xa + b1 + c1 * xa, K / xe + b1 + c1 * xe);
    float r = abs(c1) > 1e-30 ? K / c1 : -1.0;
    if (r > 0.0) {
        float xs = sqrt(r);
        if (xs > xa && xs < xe) {
            t = max(t, K / xs + b1 + c1 * xs);
        }
    }
    return t;
}

// The largest rise tangent of the bilinear surface over [x0, x1] along the query's direction,
// exactly: inside one bilinear cell the height along a line is a quadratic A + B x + C x^2, so
// the tangent (s h - zp) / x = K / x + s B + s C x (K = s A - zp) peaks at an end or at
// x* = sqrt(K / (s C)). Walks the cells (lines through texel centres) the span crosses.
float segment_max_tangent(ShadowQuery q, float x0, float x1) {
    vec2 size = height_size();
    vec2 df = q.d * size;
    vec2 g0 = q.uv * size - 0.5;
    // The cells are stepped by index, not found again by floor() at each boundary: in float a
    // boundary point can floor back into the cell just left and stall the walk.
    vec2 cell = floor(g0 + x0 * df);
    vec2 ahead = step(0.0, df);
    float best = -3.0e38;
    float x = x0;
    for (int i = 0; i < 16 && x < x1; ++i) {
        vec2 exits = vec2(3.0e38);
        for (int axis = 0; axis < 2; ++axis) {
            if (abs(df[axis]) > 1e-12) {
                exits[axis] = (cell[axis] + ahead[axis] - g0[axis]) / df[axis];
            }
        }
        float xe = clamp(min(exits.x, exits.y), x, x1);
        best = max(best, cell_max_tangent(q, cell, g0 - cell, df, max(x, 1e-9), xe, x0 <= 0.0 && i == 0));
        int axis = exits.x <= exits.y ? 0 : 1;
        cell[axis] += df[axis] > 0.0 ? 1.0 : -1.0;
        x = xe;
    }
    return best;
}

// The least fall of a curved top over [a, b] along d (0 when flat).
float least_fall(ShadowQuery q, float a, float b) {
    float fall = min(a * (q.bend_slope + q.bend_curve * a), b * (q.bend_slope + q.bend_curve * b));
    if (q.bend_curve > 0.0) {
        float v = -q.bend_slope / (2.0 * q.bend_curve);
        if (v > a && v < b) {
            fall = min(fall, v * (q.bend_slope + q.bend_curve * v));
        }
    }
    return fall;
}

float shadow_cone(ShadowQuery q) {
    vec2 texels = height_size();
    float texels_per_uv = max(abs(q.d.x) * texels.x, abs(q.d.y) * texels.y);
    float nudge = CROSSING_TEXELS / max(texels_per_uv, 1e-30);
    float floor_tau = max(tan(clamp(q.elevation - q.radius, -MAX_SHADOW_ELEVATION, MAX_SHADOW_ELEVATION)),
                          horizon_floor(q));
    float tau = max(tangent_horizon(q), horizon_floor(q));
    bool bent = q.bend_slope != 0.0 || q.bend_curve != 0.0;
    int leaf = pyramid_leaf();
    int top = pyramid_top();
    int level = leaf;
    float x = 0.0;
    // Beyond where the highest point of the field, seen from the hit, stands below what already
    // matters, nothing can change the answer.
    float highest = q.s * node_height(q.uv, top) - q.zp;
    for (uint i = 0u; i < SHADOW_STEPS; ++i) {
        float matters = max(tau, floor_tau);
        if (x >= q.reach || (!bent && matters > 0.0 && highest <= matters * x)) {
            break;
        }
        float x_out = shadow_cell_exit(q, x, level);
        // Under a curved top a node stands lower by the top's fall, at least its least fall
        // over the node's span.
        float rise = q.s * node_height(q.uv + x * q.d, level) - q.zp - least_fall(q, x, x_out);
        bool can_matter = rise > 0.0 && (x <= 0.0 || rise > matters * x);
        if (!can_matter) {
            x = x_out + nudge;
            level = min(level + 1, top);
        } else if (level > leaf) {
            level -= 1;
        } else {
            // Leaf node: the bilinear surface across it, exactly.
            tau = max(tau, segment_max_tangent(q, x, x_out + nudge));
            x = x_out + nudge;
        }
    }
    return visible_over(q, tau);
}

// 1 when nothing of the field stands between the hit and the light's centre, else 0: a ray from
// the top plane toward the hit (Policarpo et al. 2005's self-shadowing), traced by the method.
float shadow_hard(ShadowQuery q, vec2 uv_hit, float z_hit, vec3 l, float s) {
    if (l.z <= 0.0 || l.z <= tangent_horizon(q) * length(l.xy)) {
        return 0.0;
    }
    vec3 dir = normalize(vec3(-l.xy, max(l.z, 1e-3 * length(l.xy))));
    Ray ray = Ray(uv_hit - (z_hit / dir.z) * dir.xy, dir, s);
    Hit hit = METHOD_TRACE(ray, ray_budget(ray));
    vec3 gap = vec3(ray_uv(ray, hit.z) - uv_hit, hit.z - z_hit) * height_size().x;
    return hit.z < z_hit && length(gap) > HARD_SHADOW_TEXELS ? 0.0 : 1.0;
}

// Hard self-shadowing under a curved top: the light ray from the hit, walked one texel at a time
// until it rises out of the curved shell (lit) or passes under the field (shadowed). The
// method's trace cannot take it: it runs straight rays under a plane.
float shadow_hard_bent(ShadowQuery q) {
    float rise = tan(clamp(q.elevation, -MAX_SHADOW_ELEVATION, MAX_SHADOW_ELEVATION));
    if (tangent_horizon(q) >= rise) {
        return 0.0;
    }
    vec2 texels = height_size();
    float texel = 1.0 / max(abs(q.d.x) * texels.x, abs(q.d.y) * texels.y);
    const uint samples = 256u;
    float step_x = max(texel, min(q.reach, SHADOW_MAX_REACH) / float(samples));
    for (uint k = 1u; k <= samples; ++k) {
        float x = float(k) * step_x;
        // Above the curved top: out of the shell.
        if (x * rise >= q.s - q.zp - x * (q.bend_slope + q.bend_curve * x)) {
            return 1.0;
        }
        if (rise_tangent(q, x) >= rise) {
            return 0.0;
        }
    }
    return 1.0;
}

// Visible fraction in [0, 1] of a light of angular radius `radius` (radians) in direction `l`
// (height space: uv per unit, up per unit of depth; need not be normalised) from the hit at
// (uv_hit, z_hit), by SHADOW_MODE.
float light_visible_bent(vec2 uv_hit, float z_hit, vec3 l, float radius, float depth_scale, vec2 bend) {
    if (SHADOW_MODE == SHADOW_MODE_NONE || depth_scale <= 0.0) {
        return 1.0;
    }
    ShadowQuery q = shadow_query(uv_hit, z_hit, l, radius, depth_scale, bend);
    if (q.elevation + q.radius <= atan(horizon_floor(q))) {
        return 0.0;
    }
    if (SHADOW_MODE == SHADOW_MODE_HARD) {
#if defined(CURVED) || defined(SHELLS)
        return shadow_hard_bent(q);
#else
        return shadow_hard(q, uv_hit, z_hit, l, depth_scale);
#endif
    }
    if (SHADOW_MODE == SHADOW_MODE_POM_SOFT) {
        return shadow_pom_soft(q);
    }
    if (SHADOW_MODE == SHADOW_MODE_HORIZON) {
        return shadow_horizon(q);
    }
    return shadow_cone(q);
}

// The same under a flat polygon.
float light_visible(vec2 uv_hit, float z_hit, vec3 l, float radius, float depth_scale) {
    return light_visible_bent(uv_hit, z_hit, l, radius, depth_scale, vec2(0.0));
}

#endif
