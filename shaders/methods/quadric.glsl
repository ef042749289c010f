// Quadratic displacement maps (Kiglics, Valasek, Balint, Ban; paper 004, Algorithm 1 with the
// stable solver of Algorithm 2): each texel stores an unbounding profile above the surface point
// under the ray, a cone out to radius a (rim height b) then a revolved parabola peaking at radius
// c, flat beyond c (heightfield::quadric_map documents where and why this departs from the
// paper). Each step moves the ray to where it meets the profile of the texel it is over, so it
// never passes the first hit; rays still above the surface when the budget ends are refined by
// bisection over the last texel of travel. Near a surface the ray grazes, the steps shrink
// geometrically and the budget runs out short of the hit, and a ray that passes within eps of
// the surface stops there although it goes on (gross misses at low angles). With the exact leaf
// (the default, budget.exact_leaf) a step shorter than a quarter texel of travel, or one that
// starts within eps, is replaced by the exact ray/bilinear-patch intersection over the next
// texel of travel, and the final refinement is exact too.
#include "pyramid.glsl"

// The exact leaf over the next `texel_z` of depth from z: true with the hit, or false with z
// moved to the end of that span.
bool quadric_leaf(Ray ray, inout float z, float texel_z, out float hit) {
    float end = min(z + texel_z, ray.depth_scale);
    if (leaf_exact(ray, z, end, hit)) {
        return true;
    }
    z = end;
    return false;
}

Hit trace_quadric(Ray ray, Budget budget) {
    float s = ray.depth_scale;
    vec2 size = height_size();
    vec2 slope = ray.dir.xy / ray.dir.z;
    float lambda = length(slope);
    float n = max(size.x, size.y);
    float eps = max(1.0e-3 / (n * max(1.0, lambda)), 1.0e-6 * s);
    float texel_z = depth_per_texels(ray, 1.0);
    float z = 0.0;
    float gap = 0.0;
    uint steps = 0u;
    bool capped = true;
    for (uint i = 0u; i <= budget.max_steps; ++i) {
        // Steps never pass the first hit, and nothing lies below the bottom plane: a ray that
        // reached it (a flat floor, a zero depth scale) hit there. Without this the leaf over
        // the zero span left would be retried until the budget ran out.
        if (z >= s) {
            return Hit(s, steps, false);
        }
        vec2 uv = ray.origin + z * slope;
        gap = s * (1.0 - height_bilinear_exact(uv)) - z;
        if (gap <= eps && !budget.exact_leaf) {
            capped = false;
            break;
        }
        if (i == budget.max_steps) {
            break;
        }
        float hit;
        if (gap <= eps) {
            steps += 1u;
            if (quadric_leaf(ray, z, texel_z, hit)) {
                return Hit(hit, steps, false);
            }
            continue;
        }
        vec4 m = texelFetch(method_map, address_cell(floor(uv * size), size), 0);
        float a = m.x, b = m.y, c = m.z;
        float rim = a + s * b * lambda;
        float dz;
        if (lambda * gap <= rim) {
            dz = min(gap * a / max(rim, 1.0e-30), gap);
        } else {
            // Algorithm 2: the smaller root of A r^2 + B r + C without cancellation.
            float qa = s * lambda * lambda;
            float half_b = -0.5 * (1.0 + 2.0 * s * c * lambda);
            float qc = gap - s * (b + a * a - 2.0 * a * c);
            float disc = half_b * half_b - qa * qc;
            float r = disc >= 0.0 ? qc / (sqrt(disc) - half_b) : 3.0e38;
            dz = lambda * r <= c ? r : max(gap - s * (b + (c - a) * (c - a)), 0.0);
        }
        steps += 1u;
        if (budget.exact_leaf && dz < 0.25 * texel_z) {
            if (quadric_leaf(ray, z, texel_z, hit)) {
                return Hit(hit, steps, false);
            }
            continue;
        }
        z = min(z + dz, s);
    }
    if (capped && budget.refine_steps > 0u) {
        float lo = z;
        float hi = min(s, z + max(gap, 0.0) + 1.0 / (n * max(lambda, 1.0e-12)));
        float hit;
        if (budget.exact_leaf) {
            z = leaf_exact(ray, lo, hi, hit) ? hit : z;
        } else if (hi >= s * (1.0 - height_bilinear_exact(ray.origin + hi * slope))) {
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
    }
    return Hit(z, steps, capped);
}
