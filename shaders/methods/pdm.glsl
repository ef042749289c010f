// Pyramidal displacement mapping (Oh et al. 2006, as written up by Ki & Oh; paper 003): from the
// top of the max pyramid the ray advances to each node's plane and descends; a move that would
// leave the node stops at its boundary plus a small offset and stays on that level (node
// crossing, section 2.3); at the leaf the ray advances half a texel at a time while it is above
// the bilinear surface, and the hit is interpolated between the last points behind and ahead by
// their distances to the surface (linear filtering, section 2.4). The LOD switch to averaged
// mips (section 2.5) needs an averaged pyramid relief does not build; traces run at full detail.
#include "pyramid.glsl"

Hit trace_pdm(Ray ray, Budget budget) {
    float s = ray.depth_scale;
    int leaf = pyramid_leaf();
    int level = pyramid_top();
    float z = 0.0;
    float push = depth_per_texels(ray, CROSSING_TEXELS);
    float half_texel = depth_per_texels(ray, 0.5);
    for (uint i = 0u; i < budget.max_steps; ++i) {
        vec2 uv = ray_uv(ray, z);
        vec2 size = level_size(level);
        vec2 cell = floor(uv * size);
        float exit_z = cell_exit_depth(ray, cell, size);
        float d = node_depth(uv, level, s);
        if (d > z) {
            if (d >= exit_z) {
                z = min(exit_z + push, s);
                continue;
            }
            z = d;
        }
        if (level > leaf) {
            level -= 1;
            continue;
        }
        float hit;
        if (leaf_search(ray, z, min(exit_z, s), half_texel, true, hit)) {
            return Hit(hit, i + 1u, false);
        }
        z = min(exit_z + push, s);
    }
    return Hit(z, budget.max_steps, true);
}
