// Relaxed cone stepping (Policarpo & Oliveira 2007, GPU Gems 3 ch. 18; papers 001 and 004):
// wider cones through which a ray enters the solid at most once, so stepping may overshoot into
// it, then a binary search over the last step finds the entry. Relief's relaxed map keeps that
// guarantee strictly for the box surface (heightfield::cone_map), which makes its cones only a
// little wider than the conservative ones on rough fields. The boxes are those of the bilinear
// bound (cone.glsl): the paper's leaf ends on the box the binary search finds; the exact leaf (the
// default) intersects the bilinear surface from the search's outside end.
#include "cone.glsl"

Hit trace_rcsm(Ray ray, Budget budget) {
    return cone_trace(ray, budget, true);
}
