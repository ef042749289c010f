// Relief mapping (Policarpo, Oliveira, Comba 2005; Drobot section 1.3.1): a linear search in
// equal depth steps brackets the first intersection, then a binary search over `refine_steps`
// halvings narrows the bracket; the answer is the bracket's lower end (the first point found
// at or below the surface).

Hit trace_relief(Ray ray, Budget budget) {
    uint n = max(budget.max_steps, 1u);
    float step_z = ray.depth_scale / float(n);
    if (depth_bilinear(ray.origin, ray.depth_scale) <= 0.0) {
        return Hit(0.0, 0u, false);
    }
    float above = 0.0;
    float below = ray.depth_scale;
    uint i = 1u;
    for (; i < n; ++i) {
        float z = float(i) * step_z;
        if (z >= depth_bilinear(ray_uv(ray, z), ray.depth_scale)) {
            below = z;
            break;
        }
        above = z;
    }
    for (uint k = 0u; k < budget.refine_steps; ++k) {
        float mid = 0.5 * (above + below);
        if (mid >= depth_bilinear(ray_uv(ray, mid), ray.depth_scale)) {
            below = mid;
        } else {
            above = mid;
        }
    }
    return Hit(below, min(i, n) + budget.refine_steps, false);
}
