// Parallax occlusion mapping (Tatarchuk 2006; Drobot, Listing 1.1): a linear search in equal
// depth steps over the bilinear surface, then the hit of the ray with the segment joining the
// last two samples (one linear interpolation instead of relief mapping's binary search).

Hit trace_pom(Ray ray, Budget budget) {
    uint n = max(budget.max_steps, 1u);
    float step_z = ray.depth_scale / float(n);
    float prev_z = 0.0;
    // f = z - d(z): negative above the surface, >= 0 at or below it.
    float prev_f = -depth_bilinear(ray.origin, ray.depth_scale);
    if (prev_f >= 0.0) {
        return Hit(0.0, 0u, false);
    }
    for (uint i = 1u; i <= n; ++i) {
        float z = (i == n) ? ray.depth_scale : float(i) * step_z;
        float f = z - depth_bilinear(ray_uv(ray, z), ray.depth_scale);
        if (f >= 0.0) {
            float t = safe_div(-prev_f, f - prev_f);
            return Hit(mix(prev_z, z, clamp(t, 0.0, 1.0)), i, false);
        }
        prev_z = z;
        prev_f = f;
    }
    // Unreachable for a finite field: at z = depth_scale, f = depth_scale * h >= 0.
    return Hit(ray.depth_scale, n, false);
}
