// Max-pyramid helpers shared by the hierarchical methods (qrm, pdm, qdm, maxmip). A node at level
// L is a texel of mip L: uv cell [i/wL, (i+1)/wL) with wL = textureSize(height_point, L); it holds
// the max height of every finer texel it overlaps (heightfield::pyramid), so the plane at its
// depth is never below the surface inside the cell.
#ifndef PYRAMID_GLSL
#define PYRAMID_GLSL

// Level 1 nodes are built one texel wider on each side (MaxPyramid::build_bilinear_bound), so
// they bound the bilinear surface; level 0 texels bound only the box surface. Traversals stop at
// this leaf level and search the bilinear surface inside the leaf node. A 1x1 map has no level 1
// and a constant surface, which its single texel bounds.
int pyramid_leaf() {
    return min(1, int(HEIGHT_INFO.z) - 1);
}

// Index of the coarsest level (1x1).
int pyramid_top() {
    return int(HEIGHT_INFO.z) - 1;
}

// Vulkan's mip size rule, computed rather than queried: lavapipe (Mesa 22.3) answers
// textureSize with one lane's level for its whole SIMD group, which is wrong as soon as rays in
// the group sit at different levels (measured: 3% gross misses at 30 degrees from that alone).
vec2 level_size(int level) {
    return max(floor(height_size() / exp2(float(level))), vec2(1.0));
}

// Depth of the top plane of node `cell` at `level`. Fetched by integer texel, not through the
// sampler: a sampler resolves coordinates to its sub-texel precision (8 bits on most GPUs), so
// just past a coarse node's boundary it may still return the node the ray has left.
float node_depth_cell(vec2 cell, int level, float depth_scale) {
    ivec2 texel = address_cell(cell, level_size(level));
    return depth_scale * (1.0 - counted_texel(height_point, texel, level).r);
}

// Per unit of depth, how far the ray moves in uv.
vec2 ray_slope(Ray ray) {
    return ray.dir.xy / ray.dir.z;
}

// The cell of a grid of `size` cells that the ray occupies just past depth z. On a line, floor()
// names the cell above it, which a ray moving toward lower indices is leaving: the traversal
// would judge the ray by the plane of a node it never crosses, and when that plane lies below the
// exit, skip the node it does cross and report a hit on the far boundary, below the surface.
// Rays stand exactly on node boundaries more often than chance suggests: entering at the centres
// of a ray grid four times coarser than the map, or moved down to a plane whose depth is a whole
// number of texels of travel.
vec2 ray_cell(Ray ray, float z, vec2 size) {
    vec2 p = ray_uv(ray, z) * size;
    vec2 cell = floor(p);
    return cell - vec2(equal(cell, p)) * vec2(lessThan(ray_slope(ray), vec2(0.0)));
}

// Per axis, the depth at which the ray reaches the next line of a grid of `size` cells ahead of
// depth z_now; the lines sit at (k + offset) / size (offset 0: texel edges, 0.5: texel centres).
// `cell` is the cell holding the ray at z_now. A ray exactly on a line it is leaving (an xy
// component of zero or 1e-16 keeps it there) gets the line after. Axes the ray does not move
// along never end a cell.
vec2 next_line_depths(Ray ray, vec2 cell, vec2 size, float offset, float z_now) {
    vec2 slope = ray_slope(ray);
    vec2 ahead = step(0.0, slope);
    vec2 z = vec2(3.0e38);
    for (int axis = 0; axis < 2; ++axis) {
        if (slope[axis] == 0.0) {
            continue;
        }
        float line = (cell[axis] + ahead[axis] + offset) / size[axis];
        float depth = (line - ray.origin[axis]) / slope[axis];
        if (depth <= z_now) {
            line += sign(slope[axis]) / size[axis];
            depth = (line - ray.origin[axis]) / slope[axis];
        }
        z[axis] = depth;
    }
    return z;
}

// Depth at which the ray, at depth z_now in cell `cell`, leaves it.
float cell_exit_depth(Ray ray, vec2 cell, vec2 size, float z_now) {
    vec2 z = next_line_depths(ray, cell, size, 0.0, z_now);
    return min(z.x, z.y);
}

// Depth the ray needs to move `texels` finest-level texels along its dominant axis; huge for
// (near-)vertical rays, which never cross cells sideways.
float depth_per_texels(Ray ray, float texels) {
    vec2 travel = abs(ray_slope(ray)) * height_size();
    return texels / max(max(travel.x, travel.y), 1e-30);
}

// After a cell crossing the ray is pushed this many finest texels past the boundary: enough that
// floor() lands in the next cell even at 8192^2 (7.6e-6 uv against float's 6e-8 near 1), small
// enough that a feature it steps over is a sixteenth of a texel, never a gross miss.
const float CROSSING_TEXELS = 1.0 / 16.0;

// Searches the bilinear surface along the ray from z0 to z1 in steps of `step` depth; on the first
// sample at or below the surface returns true with `hit` where the line through the last two
// samples crosses it (`interpolate`), or the sample itself.
bool leaf_search(Ray ray, float z0, float z1, float step_z, bool interpolate, out float hit) {
    float s = ray.depth_scale;
    float za = z0;
    float fa = za - depth_bilinear(ray_uv(ray, za), s);
    hit = z1;
    if (fa >= 0.0) {
        hit = za;
        return true;
    }
    // A leaf node spans at most 3 texels of travel, so 8 half-texel steps always reach z1.
    for (int k = 0; k < 8 && za < z1; ++k) {
        float zb = min(za + step_z, z1);
        float fb = zb - depth_bilinear(ray_uv(ray, zb), s);
        if (fb >= 0.0) {
            hit = interpolate ? mix(za, zb, clamp(-fa / (fb - fa), 0.0, 1.0)) : zb;
            return true;
        }
        za = zb;
        fa = fb;
    }
    return false;
}

// The exact first hit of the bilinear surface on the ray between depths z0 and z1: walks the
// bilinear cells (squares between texel centres) the ray crosses and solves each cell's
// quadratic in closed form, as the CPU reference does.
bool leaf_exact(Ray ray, float z0, float z1, out float hit) {
    float s = ray.depth_scale;
    vec2 size = height_size();
    vec2 slope = ray_slope(ray);
    vec2 a = slope * size;
    float nudge = depth_per_texels(ray, 1.0e-3);
    float z = z0;
    hit = z1;
    // A leaf node spans at most 3 texels per axis: at most 8 bilinear cells along a ray.
    for (int k = 0; k < 8 && z < z1; ++k) {
        vec2 g = ray_uv(ray, z) * size - 0.5;
        vec2 cell = floor(ray_uv(ray, min(z + nudge, z1)) * size - 0.5);
        vec2 f0 = g - cell;
        vec2 lines = next_line_depths(ray, cell, size, 0.5, z);
        float z_exit = min(z1, min(lines.x, lines.y));
        vec4 corners = bilinear_corners(cell);
        float h00 = corners.x, h10 = corners.y, h01 = corners.z, h11 = corners.w;
        float p = h10 - h00, q = h01 - h00, r = h00 - h10 - h01 + h11;
        float hc = h00 + p * f0.x + q * f0.y + r * f0.x * f0.y;
        float A = s * r * a.x * a.y;
        float B = 1.0 + s * (p * a.x + q * a.y + r * (f0.x * a.y + f0.y * a.x));
        float C = z - s + s * hc;
        if (C >= 0.0) {
            hit = z;
            return true;
        }
        float root;
        if (first_root(A, B, C, max(z_exit - z, 0.0), root)) {
            hit = z + root;
            return true;
        }
        z = max(z_exit, z + nudge);
    }
    return false;
}

// The traversal QDM, PDM and maxmip share: from the top, move down to each node's plane and
// descend; a move that would leave the node stops at its boundary plus CROSSING_TEXELS and climbs
// `ascent` levels; at the leaf, search the bilinear surface inside the node (`leaf_mode` 0: linear
// interpolation at one-texel spacing, 1: at half-texel spacing, 2: exact) and move on to the next
// node if it is not hit there. The traversal and the leaf are two loops, not one: lanes of a SIMD
// group reach leaves at different iterations, and a leaf inside the traversal would be paid by the
// whole group once per such iteration; here they wait for each other and search together.
Hit pyramid_trace(Ray ray, Budget budget, int ascent, int leaf_mode) {
    float s = ray.depth_scale;
    int top = pyramid_top();
    int leaf = pyramid_leaf();
#ifdef LOD_MEAN_PYRAMID
    // Level of detail (lod.glsl): descend no further than the pixel's stop level.
    int full_leaf = leaf;
    leaf = lod_stop_level(leaf);
#endif
    int level = top;
    float z = 0.0;
    float push = depth_per_texels(ray, CROSSING_TEXELS);
    float spacing = depth_per_texels(ray, leaf_mode == 0 ? 1.0 : 0.5);
    uint i = 0u;
    while (i < budget.max_steps) {
        bool at_leaf = false;
        float exit_z = s;
        for (; i < budget.max_steps; ++i) {
            // At the bottom plane every ray is at or below the surface (a flat 0 field, depth 0).
            if (z >= s) {
                return Hit(s, i, false);
            }
            vec2 size = level_size(level);
            vec2 cell = ray_cell(ray, z, size);
            exit_z = cell_exit_depth(ray, cell, size, z);
            float d = node_depth_cell(cell, level, s);
#ifdef LOD_MEAN_PYRAMID
            d = lod_node_depth(d, cell, level, full_leaf, s);
#endif
            bool crossing = d > z && d >= exit_z;
            if (d > z && !crossing) {
                z = d;
            }
            if (crossing) {
                z = min(exit_z + push, s);
                level = min(level + ascent, top);
            } else if (level > leaf) {
                level -= 1;
            } else {
                at_leaf = true;
                break;
            }
        }
        if (!at_leaf) {
            break;
        }
        i += 1u;
#ifdef LOD_MEAN_PYRAMID
        // Stopped above the full-detail leaf: the ray is on the node's (blended) plane or wall.
        if (leaf > full_leaf) {
            return Hit(z, i, false);
        }
#endif
        // The exact test starts `push` back: the ray is known to be above the surface up to
        // there (every move ends on a node's plane or `push` past a searched boundary), so
        // the sliver a crossing steps over is searched too.
        float hit;
        bool found = leaf_mode == 2 ? leaf_exact(ray, max(z - push, 0.0), min(exit_z, s), hit)
                                    : leaf_search(ray, z, min(exit_z, s), spacing, true, hit);
        if (found) {
            return Hit(hit, i, false);
        }
        z = min(exit_z + push, s);
        level = min(level + ascent, top);
    }
    return Hit(z, budget.max_steps, true);
}

#endif
