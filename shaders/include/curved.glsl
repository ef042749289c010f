// Curved relief (Oliveira and Policarpo 2005): the relief shell follows the mesh's curvature
// instead of the polygon's plane. Near a point the surface drops below its tangent plane by
// (k_t x_t^2 + k_b x_b^2) / 2, with k_t and k_b its normal curvatures along the tangent and the
// bitangent and x_t, x_b the world distances along them; a view ray is traced against the height
// field hung from that curved top, so a ray that rises out of the shell before meeting the
// surface misses it, which cuts the silhouette at the displaced surface's outline.
// Needs relief_frame.glsl and heightfield.glsl.
#ifndef CURVED_GLSL
#define CURVED_GLSL

// The largest curvature used, in inverse world units per depth unit of the shell: beyond it the
// screen derivatives are noise (a triangle seen edge-on).
const float CURVED_MAX_BEND = 64.0;

// Normal curvatures along f.t and f.b from two steps across the surface, `dpx` and `dpy`, and
// how the unit normal changes over them, `dnx` and `dny`: for a direction w in the tangent plane,
// the combination (a, b) of the steps that moves the point by w (least squares), and
// dn = a dnx + b dny along it.
vec2 curvature_along(vec3 dpx, vec3 dpy, vec3 dnx, vec3 dny, ReliefFrame f) {
    mat2 gram = mat2(dot(dpx, dpx), dot(dpx, dpy), dot(dpx, dpy), dot(dpy, dpy));
    float det = determinant(gram);
    if (abs(det) < 1e-30) {
        return vec2(0.0);
    }
    mat2 inv = inverse(gram);
    vec2 at = inv * vec2(dot(dpx, f.t), dot(dpy, f.t));
    vec2 ab = inv * vec2(dot(dpx, f.b), dot(dpy, f.b));
    float kt = dot(at.x * dnx + at.y * dny, f.t);
    float kb = dot(ab.x * dnx + ab.y * dny, f.b);
    float limit = CURVED_MAX_BEND / max(f.depth_len, 1e-12);
    return clamp(vec2(kt, kb), vec2(-limit), vec2(limit));
}

// Normal curvatures along f.t and f.b, from how the interpolated unit normal `n` changes across
// the screen against the world position (one pixel's steps).
vec2 surface_curvature(vec3 world, vec3 n, ReliefFrame f) {
    return curvature_along(dFdx(world), dFdy(world), dFdx(n), dFdy(n), f);
}

// How far below the tangent plane the curved top lies at the height-uv offset `d` from the
// entry, in depth units.
float curved_drop(ReliefFrame f, vec2 curvature, vec2 d) {
    vec3 w = height_offset_to_world(f, d);
    float xt = dot(w, f.t);
    float xb = dot(w, f.b);
    return 0.5 * (curvature.x * xt * xt + curvature.y * xb * xb) / f.depth_len;
}

// How the curved top falls along the light's uv direction `toward` from the hit at offset `e`
// from the entry, relative to the plane through the hit parallel to the entry's tangent plane:
// the drop at e + x d less the drop at e is x (slope) + x^2 (curve), d the unit direction; the
// self-shadow searches (shadows.glsl) hang the field from that.
vec2 curved_bend(ReliefFrame f, vec2 curvature, vec2 e, vec2 toward) {
    float len = length(toward);
    vec2 d = len > 1e-7 ? toward / len : vec2(1.0, 0.0);
    vec3 we = height_offset_to_world(f, e);
    vec3 wd = height_offset_to_world(f, d);
    float et = dot(we, f.t), eb = dot(we, f.b);
    float dt = dot(wd, f.t), db = dot(wd, f.b);
    float slope = (curvature.x * et * dt + curvature.y * eb * db) / f.depth_len;
    float curve = 0.5 * (curvature.x * dt * dt + curvature.y * db * db) / f.depth_len;
    return vec2(slope, curve);
}

// Relief mapping's linear then binary search along the straight ray (depth z below the tangent
// plane), each sample compared with the surface hung from the curved top: below it when
// z - drop >= the field's depth there. A sample above the curved top (z < drop) after the entry
// means the ray left the shell: a miss, returned as z = -1. The linear search steps depth_scale / n
// and may go past depth_scale (the curved shell's bottom lies deeper where the mesh bends away),
// for at most four times its steps.
Hit trace_curved(Ray ray, Budget budget, ReliefFrame f, vec2 curvature) {
    uint n = max(budget.max_steps, 1u);
    float step_z = ray.depth_scale / float(n);
    if (depth_bilinear(ray.origin, ray.depth_scale) <= 0.0) {
        return Hit(0.0, 0u, false);
    }
    float above = 0.0;
    float below = -1.0;
    uint i = 1u;
    for (; i < 4u * n; ++i) {
        float z = float(i) * step_z;
        vec2 uv = ray_uv(ray, z);
        float relative = z - curved_drop(f, curvature, uv - ray.origin);
        if (relative < 0.0) {
            return Hit(-1.0, i, false);
        }
        if (relative >= depth_bilinear(uv, ray.depth_scale)) {
            below = z;
            break;
        }
        above = z;
    }
    if (below < 0.0) {
        return Hit(-1.0, i, true);
    }
    for (uint k = 0u; k < budget.refine_steps; ++k) {
        float mid = 0.5 * (above + below);
        vec2 uv = ray_uv(ray, mid);
        if (mid - curved_drop(f, curvature, uv - ray.origin) >= depth_bilinear(uv, ray.depth_scale)) {
            below = mid;
        } else {
            above = mid;
        }
    }
    return Hit(below, i + budget.refine_steps, false);
}

#endif
