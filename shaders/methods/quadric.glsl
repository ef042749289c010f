// Quadratic displacement maps (Kiglics, Valasek, Balint, Ban; Kiglics et al., Algorithm 1 with the
// stable solver of Algorithm 2): each texel stores an unbounding profile above the surface point
// under the ray, a cone out to radius a (rim height b) then a revolved parabola peaking at radius
// c, flat beyond c (heightfield::quadric_map documents where and why this departs from the
// paper). Each step moves the ray to where it meets the profile of the texel it is over, so it
// never passes the first hit.
//
// With the paper's leaf (budget.exact_leaf false) that is the whole method: a ray within eps of
// the surface has hit, and rays still above it when the budget ends are refined by bisection
// over the last texel of travel. Near a surface the ray grazes, the steps shrink geometrically
// and the budget runs out short of the hit, and a ray that passes within eps of the surface stops
// there although it goes on (gross misses at low angles).
//
// With the exact leaf (the default) a step shorter than half a texel of travel, or a ray within
// eps, lands; the landed rays of a SIMD group then take the exact ray/bilinear-patch
// intersection over the next two texels of travel together and march on from its end if it
// misses. The march and the leaf are two loops, as in cone.glsl: a leaf inside the march would
// be paid by the whole group at every iteration in which one of its rays lands. Two texels is
// also the most a cone-stepping leaf covers, so both count a leaf as one step of equal reach.
#include "pyramid.glsl"

// How far one step of Algorithm 1 takes a ray `gap` (depth) above the profile's apex, moving
// lambda uv sideways per unit of depth: to the cone, else by Algorithm 2 to the rising part of
// the parabola, else to the flat cap. Never more than gap.
float quadric_step(float gap, float lambda, float s, vec4 m) {
    float a = m.x, b = m.y, c = m.z;
    float rim = a + s * b * lambda;
    if (lambda * gap <= rim) {
        return min(gap * a / max(rim, 1.0e-30), gap);
    }
    // The smaller root of A r^2 + B r + C without cancellation; the discriminant is tested
    // before sqrt, as GLSL leaves a negative root undefined.
    float qa = s * lambda * lambda;
    float half_b = -0.5 * (1.0 + 2.0 * s * c * lambda);
    float qc = gap - s * (b + a * a - 2.0 * a * c);
    float disc = half_b * half_b - qa * qc;
    float r = disc >= 0.0 ? qc / (sqrt(disc) - half_b) : 3.0e38;
    return lambda * r <= c ? r : max(gap - s * (b + (c - a) * (c - a)), 0.0);
}

// The smallest gap (depth) that still counts as above the surface: the rest of the way is under
// 1e-3 texel down and sideways, or under what f32 resolves of the depth scale.
float quadric_epsilon(Ray ray, float lambda) {
    vec2 size = height_size();
    float n = max(size.x, size.y);
    return max(1.0e-3 / (n * max(1.0, lambda)), 1.0e-6 * ray.depth_scale);
}

vec4 quadric_texel(vec2 cell) {
    return counted_texel(method_map, address_cell(cell, height_size()), 0);
}

// Algorithm 1 as the paper has it, with bisection for capped rays.
Hit trace_quadric_paper(Ray ray, Budget budget) {
    float s = ray.depth_scale;
    vec2 size = height_size();
    vec2 slope = ray_slope(ray);
    float lambda = length(slope);
    float eps = quadric_epsilon(ray, lambda);
    float z = 0.0;
    float gap = 0.0;
    uint steps = 0u;
    for (;;) {
        // Nothing lies below the bottom plane: a ray that reached it hit there.
        if (z >= s) {
            return Hit(s, steps, false);
        }
        vec2 uv = ray.origin + z * slope;
        gap = s * (1.0 - height_bilinear_exact(uv)) - z;
        if (gap <= eps) {
            return Hit(z, steps, false);
        }
        if (steps == budget.max_steps) {
            break;
        }
        z = min(z + quadric_step(gap, lambda, s, quadric_texel(floor(uv * size))), s);
        steps += 1u;
    }
    float lo = z;
    float hi = min(s, z + max(gap, 0.0) + depth_per_texels(ray, 1.0));
    if (budget.refine_steps > 0u && hi >= s * (1.0 - height_bilinear_exact(ray.origin + hi * slope))) {
        for (uint k = 0u; k < budget.refine_steps; ++k) {
            float mid = 0.5 * (lo + hi);
            if (mid >= s * (1.0 - height_bilinear_exact(ray.origin + mid * slope))) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        z = hi;
    }
    return Hit(z, steps, true);
}

// The march and the exact leaf (see the header).
Hit trace_quadric_exact(Ray ray, Budget budget) {
    float s = ray.depth_scale;
    vec2 size = height_size();
    vec2 slope = ray_slope(ray);
    float lambda = length(slope);
    float eps = quadric_epsilon(ray, lambda);
    float short_step = depth_per_texels(ray, 0.5);
    float leaf_span = depth_per_texels(ray, 2.0);
    float z = 0.0;
    uint steps = 0u;
    while (steps < budget.max_steps) {
        bool landed = false;
        for (; steps < budget.max_steps; ++steps) {
            if (z >= s) {
                return Hit(s, steps, false);
            }
            vec2 uv = ray_uv(ray, z);
            float gap = s * (1.0 - height_bilinear_exact(uv)) - z;
            float dz = gap > eps ? quadric_step(gap, lambda, s, quadric_texel(floor(uv * size))) : 0.0;
            if (dz < short_step) {
                landed = true;
                break;
            }
            z = min(z + dz, s);
        }
        if (!landed) {
            break;
        }
        steps += 1u;
        float end = min(z + leaf_span, s);
        float hit;
        if (leaf_exact(ray, z, end, hit)) {
            return Hit(hit, steps, false);
        }
        z = end;
    }
    // Capped: the exact leaf over the next span, which may still find the hit.
    float hit;
    bool found = leaf_exact(ray, z, min(z + leaf_span, s), hit);
    return Hit(found ? hit : z, steps, !found);
}

Hit trace_quadric(Ray ray, Budget budget) {
    return budget.exact_leaf ? trace_quadric_exact(ray, budget) : trace_quadric_paper(ray, budget);
}
