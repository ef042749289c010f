// Maximum-mipmap traversal (Tevs, Ihrke, Seidel 2008; beyond the papers): the same max-pyramid
// descent with a one-level ascent after each node crossing, and at the leaf the exact
// intersection of the ray with the bilinear patches inside the node, so the hit is exact for
// the bilinear surface up to float rounding. The exact leaf is this method's own, so it ignores
// budget.exact_leaf.
#include "pyramid.glsl"

Hit trace_maxmip(Ray ray, Budget budget) {
    return pyramid_trace(ray, budget, 1, 2);
}
