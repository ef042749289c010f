// Steep parallax mapping (McGuire 2005, papers 000 and 003): a linear search in equal depth
// steps that stops at the first sample at or below the bilinear surface and returns it as is.

Hit trace_steep(Ray ray, Budget budget) {
    uint n = max(budget.max_steps, 1u);
    float step_z = ray.depth_scale / float(n);
    if (depth_bilinear(ray.origin, ray.depth_scale) <= 0.0) {
        return Hit(0.0, 0u, false);
    }
    for (uint i = 1u; i < n; ++i) {
        float z = float(i) * step_z;
        if (z >= depth_bilinear(ray_uv(ray, z), ray.depth_scale)) {
            return Hit(z, i, false);
        }
    }
    // Every ray is at or below the surface at the bottom plane.
    return Hit(ray.depth_scale, n, false);
}
