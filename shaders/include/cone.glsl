// Cone stepping over texel boxes, shared by cone step mapping and relaxed cone stepping.
// method_map holds two channels per texel: r, the ratio (radius in uv per unit of normalised
// height) of the widest cone, apexed at the texel's box top, that the box surface stays outside of
// (conservative), or that a ray leaving it enters the solid at most once through (relaxed); g, the
// height of that box, the highest point of the bilinear surface over the texel (the bilinear bound;
// see heightfield::cone_map). The bound's boxes are on or above the bilinear surface everywhere, so
// stepping never passes the first bilinear hit. Each iteration takes the longer of the cone step
// (less the ray's offset from the texel centre, since the apex sits there) and the step to the
// cell's exit or floor. Where the ray reaches a box, the paper's leaf stops there (after the
// relaxed method's binary search); the exact leaf intersects the bilinear patches inside that box,
// from the last point known to be above the bound, and steps on from the box's exit if they are
// not hit there.
#ifndef CONE_GLSL
#define CONE_GLSL
#include "pyramid.glsl"

// Clamp addressing merges everything outside the map into one cell per side (-1 and n).
vec2 cone_cell_at(Ray ray, float z, vec2 size) {
    vec2 cell = floor(ray_uv(ray, z) * size);
    return HEIGHT_INFO.w > 0.5 ? cell : clamp(cell, vec2(-1.0), size);
}

bvec2 cone_outside(vec2 cell, vec2 size) {
    bool clamped = HEIGHT_INFO.w < 0.5;
    return bvec2(clamped && (cell.x < 0.0 || cell.x >= size.x), clamped && (cell.y < 0.0 || cell.y >= size.y));
}

// Depth of the bound's box top over `cell`.
float cone_floor(vec2 cell, vec2 size, float s) {
    return s * (1.0 - counted_texel(method_map, address_cell(cell, size), 0).g);
}

// Depths at which the ray leaves `cell` along u and v (never before z); a merged outside cell
// never ends in the outward direction.
vec2 cone_exits(Ray ray, vec2 cell, vec2 size, float z) {
    vec2 slope = ray_slope(ray);
    bvec2 out_cell = cone_outside(cell, size);
    vec2 result = vec2(3.0e38);
    for (int axis = 0; axis < 2; ++axis) {
        if (slope[axis] == 0.0) {
            continue;
        }
        float lo = cell[axis] / size[axis];
        float hi = (cell[axis] + 1.0) / size[axis];
        if (out_cell[axis]) {
            if ((cell[axis] < 0.0) == (slope[axis] < 0.0)) {
                continue;
            }
            lo = 1.0;
            hi = 0.0;
        }
        float bound = slope[axis] > 0.0 ? hi : lo;
        result[axis] = max((bound - ray.origin[axis]) / slope[axis], z);
    }
    return result;
}

float cone_step(Ray ray, vec2 cell, vec2 size, float z, float floor_z, bool relaxed) {
    bvec2 out_cell = cone_outside(cell, size);
    if (relaxed && any(out_cell)) {
        return 0.0;
    }
    float c = counted_texel(method_map, address_cell(cell, size), 0).r;
    vec2 offset = ray_uv(ray, z) - (cell + 0.5) / size;
    offset = mix(offset, vec2(0.0), vec2(out_cell));
    float s = ray.depth_scale;
    float num = c * (floor_z - z) - s * length(offset);
    float den = length(ray_slope(ray)) * s + c;
    return num > 0.0 && den > 0.0 ? num / den : 0.0;
}

// The cell after `cell` for a ray that leaves it at exit_z (across one boundary or both).
vec2 cone_next_cell(Ray ray, vec2 cell, vec2 exits, float exit_z) {
    return cell + mix(vec2(0.0), sign(ray_slope(ray)), vec2(lessThanEqual(exits, vec2(exit_z))));
}

// Binary search over the last step [lo, z], which enters the bound's solid once (relaxed cones):
// returns the inside end, with lo moved to the outside end.
float cone_refine(Ray ray, Budget budget, inout float lo, float z) {
    vec2 size = height_size();
    for (uint k = 0u; k < budget.refine_steps; ++k) {
        float mid = 0.5 * (lo + z);
        if (mid >= cone_floor(cone_cell_at(ray, mid, size), size, ray.depth_scale)) {
            z = mid;
        } else {
            lo = mid;
        }
    }
    return z;
}

// The march and the leaf are two loops, not one: lanes of a SIMD group land at different
// iterations, and a leaf inside the march would be paid by the whole group once per landing
// iteration; here landed lanes wait at the end of the march and take the leaf together.
Hit cone_trace(Ray ray, Budget budget, bool relaxed) {
    float s = ray.depth_scale;
    vec2 size = height_size();
    // An exact search covers at most this much travel at once: a merged outside cell (clamp) never
    // ends, and leaf_exact walks a bounded number of bilinear cells.
    float reach = depth_per_texels(ray, 2.0);
    float z = 0.0;
    float z_before = 0.0;
    vec2 cell = cone_cell_at(ray, z, size);
    vec2 cell_before = cell;
    uint i = 0u;
    while (i < budget.max_steps) {
        bool landed = false;
        for (; i < budget.max_steps; ++i) {
            // At the bottom plane every ray is at or below the surface (a flat 0 field, depth 0).
            if (z >= s) {
                return Hit(s, i, false);
            }
            float floor_z = cone_floor(cell, size, s);
            if (z >= floor_z) {
                landed = true;
                break;
            }
            z_before = z;
            cell_before = cell;
            float cone_z = z + cone_step(ray, cell, size, z, floor_z, relaxed);
            vec2 exits = cone_exits(ray, cell, size, z);
            float exit_z = min(exits.x, exits.y);
            if (cone_z > min(exit_z, floor_z)) {
                z = min(cone_z, floor_z);
                cell = cone_cell_at(ray, z, size);
            } else if (floor_z <= exit_z) {
                z = floor_z;
            } else {
                z = exit_z;
                cell = cone_next_cell(ray, cell, exits, exit_z);
            }
        }
        if (!landed) {
            break;
        }
        i += 1u;
        // The ray is in the bound's solid; before z_before it was above the bilinear surface,
        // and conservative steps never pass the bound's first hit, so z_before = z for them.
        float lo = relaxed ? z_before : z;
        if (relaxed) {
            z = cone_refine(ray, budget, lo, z);
        }
        if (!budget.exact_leaf) {
            return Hit(z, i, false);
        }
        vec2 leaf_cell = relaxed && lo > z_before ? cone_cell_at(ray, lo, size) : (relaxed ? cell_before : cell);
        vec2 exits = cone_exits(ray, leaf_cell, size, lo);
        float exit_z = min(exits.x, exits.y);
        float end = min(min(exit_z, lo + reach), s);
        float hit;
        if (leaf_exact(ray, lo, end, hit)) {
            return Hit(hit, i, false);
        }
        z = end;
        cell = end < exit_z ? cone_cell_at(ray, end, size) : cone_next_cell(ray, leaf_cell, exits, exit_z);
        z_before = z;
        cell_before = cell;
    }
    return Hit(z, budget.max_steps, true);
}

#endif
