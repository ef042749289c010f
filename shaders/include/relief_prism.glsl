// A relief triangle's solid as a ray query meets it (src/render/traced): the height field under
// the triangle, between its displaced surface and its bottom plane, over the triangle's footprint.
// The same object the surface and shadow passes draw and the exact CPU reference traces
// (src/shadow_reference/relief_shell.rs): a ray that crosses the triangle's top plane over its
// footprint is traced down from there with the max-pyramid walk and its exact bilinear leaf
// (maxmip), and blocked where it first dips below the field, if that point lies on the queried
// segment; a ray that meets the solid only from the side is not. Parallel rays are sampled.
#ifndef RELIEF_PRISM_GLSL
#define RELIEF_PRISM_GLSL

#include "interface.glsl"
#include "pyramid.glsl"

// One relief triangle's frame is a `PrismRecord` (interface.glsl).

// Barycentric slack on the footprint: two coplanar triangles that share an edge and its uvs trace
// a ray crossing that edge alike, so counting it in both closes the crack rounding would open.
const float PRISM_FOOTPRINT_SLACK = 1e-5;
// Horizontal uv per unit of depth beyond which a ray counts as parallel to the plane
// (relief_shell.rs's MAX_SLOPE).
const float PRISM_MAX_SLOPE = 1e4;
// Samples per texel along a parallel ray, and their most.
const float PRISM_PARALLEL_SAMPLES = 8.0;
const float PRISM_MAX_SAMPLES = 4096.0;

vec3 prism_point(PrismRecord p, vec3 world) {
    vec4 h = vec4(world, 1.0);
    return vec3(dot(p.to_local[0], h), dot(p.to_local[1], h), dot(p.to_local[2], h));
}

vec3 prism_vector(PrismRecord p, vec3 world) {
    return vec3(dot(p.to_local[0].xyz, world), dot(p.to_local[1].xyz, world),
                dot(p.to_local[2].xyz, world));
}

vec3 prism_bary(PrismRecord p, vec2 uv) {
    vec2 w = mat2(p.to_bary.xy, p.to_bary.zw) * (uv - p.anchor.xy);
    return vec3(1.0 - w.x - w.y, w.x, w.y);
}

bool prism_holds(PrismRecord p, vec2 uv) {
    return all(greaterThanEqual(prism_bary(p, uv), vec3(-PRISM_FOOTPRINT_SLACK)));
}

bool uv_in_map(vec2 uv) {
    return all(greaterThanEqual(uv, vec2(0.0))) && all(lessThanEqual(uv, vec2(1.0)));
}

// Narrows [ta, tb] to where a + t b >= floor_value.
void prism_keep_above(inout float ta, inout float tb, float a, float b, float floor_value) {
    if (b == 0.0) {
        if (a < floor_value) {
            ta = 1.0 / 0.0;
        }
        return;
    }
    float t = (floor_value - a) / b;
    if (b > 0.0) {
        ta = max(ta, t);
    } else {
        tb = min(tb, t);
    }
}

// A ray parallel to the plane: its first sample inside the solid over [t0, t1], clipped to the
// prism; `steps` counts the samples taken.
bool prism_scan(PrismRecord p, vec3 q0, vec3 dq, float t0, float t1, inout uint steps,
                out float t) {
    float s = p.anchor.z;
    float ta = t0;
    float tb = t1;
    prism_keep_above(ta, tb, q0.z, dq.z, 0.0);
    prism_keep_above(ta, tb, -q0.z, -dq.z, -s);
    vec3 b0 = prism_bary(p, q0.xy);
    vec3 b1 = prism_bary(p, q0.xy + dq.xy);
    for (int k = 0; k < 3; ++k) {
        prism_keep_above(ta, tb, b0[k], b1[k] - b0[k], -PRISM_FOOTPRINT_SLACK);
    }
    if (!(ta <= tb)) {
        return false;
    }
    vec2 size = height_size();
    float texels = (tb - ta) * length(dq.xy) * max(size.x, size.y);
    float n = clamp(ceil(texels * PRISM_PARALLEL_SAMPLES), 1.0, PRISM_MAX_SAMPLES);
    for (float k = 0.0; k <= n; k += 1.0) {
        float tk = ta + (tb - ta) * k / n;
        vec3 q = q0 + dq * tk;
        steps += 1u;
        if (q.z >= s * (1.0 - height_bilinear_exact(q.xy))) {
            t = tk;
            return true;
        }
    }
    return false;
}

// Whether the segment origin + t dir, t in [t0, t1], meets prism p's solid, and where (t).
// `steps` gains the walk's iterations; `capped` is set when the walk ran out of budget.
bool prism_blocks(PrismRecord p, vec3 origin, vec3 dir, float t0, float t1, inout uint steps,
                  inout bool capped, out float t) {
    t = 0.0;
    vec3 q0 = prism_point(p, origin);
    vec3 dq = prism_vector(p, dir);
    if (length(dq.xy) >= PRISM_MAX_SLOPE * abs(dq.z)) {
        return prism_scan(p, q0, dq, t0, t1, steps, t);
    }
    vec3 entry = q0 + dq * (-q0.z / dq.z);
    if (!prism_holds(p, entry.xy)) {
        return false;
    }
    Ray ray = Ray(entry.xy, dq * sign(dq.z), p.anchor.z);
    Hit hit = pyramid_trace(ray, ray_budget(ray), 1, 2);
    steps += hit.steps;
    capped = capped || hit.capped;
    // Clamp addressing: a ray that entered the map and leaves it before meeting the field
    // passes beside the object (the silhouette of a clamped map).
    if (HEIGHT_INFO.w < 0.5 && uv_in_map(entry.xy) && !uv_in_map(ray_uv(ray, hit.z))) {
        return false;
    }
    t = (hit.z - q0.z) / dq.z;
    return t >= t0 && t <= t1;
}

#endif
