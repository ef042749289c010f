// Pyramidal displacement mapping (Oh et al. 2006, as written up by Ki & Oh; Ki and Oh): from the
// top of the max pyramid the ray advances to each node's plane and descends; a move that would
// leave the node stops at its boundary plus a small offset and stays on that level (node
// crossing, section 2.3: "level++" undone by the loop's "level--"); at the leaf the ray advances
// half a texel at a time while it is above the bilinear surface, and the hit is interpolated
// between the last points behind and ahead by their distances to the surface (linear filtering,
// section 2.4). The LOD switch to averaged mips (section 2.5) needs an averaged pyramid relief
// does not build; traces run at full detail. With the exact leaf (the default, budget.exact_leaf)
// the half-texel search is replaced by the exact ray/bilinear-patch intersection in the node: the
// search misses slivers of surface thinner than its spacing, and the exact test does not.
#include "pyramid.glsl"

Hit trace_pdm(Ray ray, Budget budget) {
    return pyramid_trace(ray, budget, 0, budget.exact_leaf ? 2 : 1);
}
