// Quadtree displacement mapping (Drobot 2010; Drobot, Listings 1.2 and 1.3): from the top of
// the max pyramid, move the ray down to the node's plane when it is not blocked and descend;
// when the move would leave the node, stop at its boundary and ascend one level (the paper's
// convergence speed-up, "Level += 2" before the loop's "Level--"); at the leaf, refine by linear
// interpolation of the bilinear surface at one-texel spacing (section 1.4.3). Boundary depths
// come from the ray's own parameterisation, not from the listing's ratio p2.z * b / a, which is
// 0/0 at the ray's start. With the exact leaf (the default, budget.exact_leaf) the one-texel
// interpolation is replaced by the exact ray/bilinear-patch intersection in the node: the
// interpolation misses slivers of surface thinner than a texel, and the exact test does not.
#include "pyramid.glsl"

Hit trace_qdm(Ray ray, Budget budget) {
    return pyramid_trace(ray, budget, 1, budget.exact_leaf ? 2 : 0);
}
