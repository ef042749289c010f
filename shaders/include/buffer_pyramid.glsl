// A max pyramid kept in one float storage buffer, for the map builders (cone_map.comp,
// quadric_map.comp). The includer declares `float pyramid[]` in a buffer block. Node (i, j) of
// level L covers the level-0 texels [i, i + 1) * 2^L (clipped to the map) along each axis and
// levels shrink to 1x1; not the Vulkan mip rule of the height image: aligned power-of-two spans
// give the searches exact node rectangles with no tables.

// Nodes of `level` for a level-0 size of `size`.
uvec2 pyramid_level_size(uvec2 size, uint level) {
    uint n = 1u << level;
    return (size + n - 1u) >> level;
}

// Writes node `at` of `level` (starting at `base` in the buffer) as the maximum of its children on
// the level below (starting at `fine_base`); invocations outside the level do nothing.
void pyramid_reduce(uvec2 size, uint level, uint fine_base, uint base, uvec2 at) {
    uvec2 nodes = pyramid_level_size(size, level);
    if (any(greaterThanEqual(at, nodes))) {
        return;
    }
    uvec2 fine = pyramid_level_size(size, level - 1u);
    uvec2 first = at * 2u;
    uvec2 last = min(first + 1u, fine - 1u);
    float h = 0.0;
    for (uint y = first.y; y <= last.y; ++y) {
        for (uint x = first.x; x <= last.x; ++x) {
            h = max(h, pyramid[fine_base + y * fine.x + x]);
        }
    }
    pyramid[base + at.y * nodes.x + at.x] = h;
}
