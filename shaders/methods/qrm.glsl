// Quadtree relief mapping (Schroders & van Gulik 2006; Schroders and van Gulik, Algorithm 1 findIntersect):
// descend from the root; in each node the cursor moves to the nearer of the node's plane and
// the node boundary ahead (the paper's quadrant trick; here next_line_depths) plus `delta`,
// half a texel of the full map; it never moves back and never ascends; when the plane lies
// inside the node the search descends. The paper's last level bounds the box surface; relief's leaf is the
// bilinear-bounding level 1, stepped through by the same delta against the bilinear surface, and
// the first point found below it is the hit (no refinement, as in the paper). With the exact leaf
// (the default, budget.exact_leaf) the half-texel stepping is replaced by the exact
// ray/bilinear-patch intersection, started `delta` before the cursor: every move ends at most
// `delta` past a point the ray is known to be above the surface at (a node's plane, or a boundary
// up to which the leaf was searched), so nothing before that start can hold the first hit.
// With level of detail (LOD_MEAN_PYRAMID, lod.glsl) the descent ends at the pixel's stop level.
#include "pyramid.glsl"

Hit trace_qrm(Ray ray, Budget budget) {
    float s = ray.depth_scale;
    float delta = depth_per_texels(ray, 0.5);
    int leaf = pyramid_leaf();
    int level = pyramid_top();
    float cursor = 0.0;
    // Descent and leaf are two loops so a SIMD group's lanes search their leaves together
    // (pyramid_trace says why).
    uint i = 0u;
    while (i < budget.max_steps) {
        bool at_leaf = false;
        float t = s;
        float tmin = s;
        for (; i < budget.max_steps; ++i) {
            if (cursor >= s) {
                return Hit(s, i, false);
            }
            vec2 size = level_size(level);
            // The node the ray moves through, not the quadrant trick's floor(): on a boundary
            // crossed toward lower indices that names the node behind (ray_cell says why).
            vec2 cell = ray_cell(ray, cursor, size);
            t = node_depth_cell(cell, level, s);
            vec2 tb = next_line_depths(ray, cell, size, 0.0, cursor);
            tmin = min(tb.x, tb.y);
#ifdef LOD_MEAN_PYRAMID
            // Level of detail (lod.glsl): at the pixel's stop level the node's (blended) plane is
            // the hit if the ray meets it inside the node.
            t = lod_node_depth(t, cell, level, leaf, s);
            if (level > leaf && level == lod_stop && t < tmin + delta) {
                return Hit(max(cursor, t), i + 1u, false);
            }
#endif
            if (level <= leaf && t < tmin + delta) {
                at_leaf = true;
                break;
            }
            cursor = min(max(cursor, min(t, tmin + delta)), s);
            if (t < tmin + delta) {
                level -= 1;
            }
        }
        if (!at_leaf) {
            break;
        }
        i += 1u;
        float hit;
        bool found = budget.exact_leaf ? leaf_exact(ray, max(cursor - delta, 0.0), min(tmin, s), hit)
                                       : leaf_search(ray, max(cursor, t), min(tmin, s), delta, false, hit);
        if (found) {
            return Hit(hit, i, false);
        }
        cursor = min(tmin + delta, s);
    }
    return Hit(cursor, budget.max_steps, true);
}
