// Cone step mapping (Dummer 2006; papers 001 and 004) on a conservative cone map built by a
// pruned search over the max pyramid instead of the O(N^4) brute force: the ray advances to the
// edge of each texel's cone, which the surface stays outside of, so it never passes the first
// hit of the box surface. The boxes are those of the bilinear bound (cone.glsl), so the paper's
// leaf stops on a box at or above the bilinear surface; the exact leaf (the default) goes on to the
// bilinear surface itself.
#include "cone.glsl"

Hit trace_csm(Ray ray, Budget budget) {
    return cone_trace(ray, budget, false);
}
