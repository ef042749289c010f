// Quadtree displacement mapping (Drobot 2010; paper 001, Listings 1.2 and 1.3): from the top of
// the max pyramid, move the ray down to the node's plane when it is not blocked and descend;
// when the move would leave the node, stop at its boundary and ascend one level (the paper's
// convergence speed-up); at the leaf refine by linear interpolation of the bilinear surface at
// one-texel spacing (section 1.4.3). Boundary depths come from the ray's own parameterisation,
// not from the listing's ratio p2.z * b / a, which is 0/0 at the ray's start.
#include "pyramid.glsl"

Hit trace_qdm(Ray ray, Budget budget) {
    float s = ray.depth_scale;
    int top = pyramid_top();
    int leaf = pyramid_leaf();
    int level = top;
    float z = 0.0;
    float push = depth_per_texels(ray, CROSSING_TEXELS);
    float texel = depth_per_texels(ray, 1.0);
    for (uint i = 0u; i < budget.max_steps; ++i) {
        vec2 uv = ray_uv(ray, z);
        vec2 size = level_size(level);
        vec2 cell = floor(uv * size);
        float exit_z = cell_exit_depth(ray, cell, size);
        float d = node_depth(uv, level, s);
        if (d > z) {
            if (d >= exit_z) {
                z = min(exit_z + push, s);
                level = min(level + 1, top);
                continue;
            }
            z = d;
        }
        if (level > leaf) {
            level -= 1;
            continue;
        }
        float hit;
        if (leaf_search(ray, z, min(exit_z, s), texel, true, hit)) {
            return Hit(hit, i + 1u, false);
        }
        z = min(exit_z + push, s);
        level = min(level + 1, top);
    }
    return Hit(z, budget.max_steps, true);
}
