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
    return min(1, int(frame.height_info.z) - 1);
}

// Index of the coarsest level (1x1).
int pyramid_top() {
    return int(frame.height_info.z) - 1;
}

vec2 level_size(int level) {
    return vec2(textureSize(height_point, level));
}

// Depth of the top plane of the node containing uv at `level`.
float node_depth(vec2 uv, int level, float depth_scale) {
    return depth_scale * (1.0 - textureLod(height_point, uv, float(level)).r);
}

// Per unit of depth, how far the ray moves in uv.
vec2 ray_slope(Ray ray) {
    return ray.dir.xy / ray.dir.z;
}

// Depth at which the ray leaves the cell `cell` of a grid of `size` cells (per axis: the boundary
// ahead of the ray). Axes the ray does not move along never end the cell.
float cell_exit_depth(Ray ray, vec2 cell, vec2 size) {
    vec2 slope = ray_slope(ray);
    vec2 boundary = (cell + step(0.0, slope)) / size;
    vec2 z = vec2(
        slope.x == 0.0 ? 3.0e38 : (boundary.x - ray.origin.x) / slope.x,
        slope.y == 0.0 ? 3.0e38 : (boundary.y - ray.origin.y) / slope.y);
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

#endif
