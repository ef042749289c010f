// Units and types every method shares (docs/conventions.md).
// Texture space: u, v in [0,1]; depth z grows downward from the top plane (z = 0, height 1) to the
// bottom plane (z = depth_scale, height 0), in the same units as u.
#ifndef CONVENTIONS_GLSL
#define CONVENTIONS_GLSL

// relief's own shaders read the specialization ids from the interface; the shader library's
// relief.glsl defines them from the includer's RELIEF_SPEC_ID_BASE instead.
#ifndef RELIEF_SHADER_LIBRARY
#include "interface.glsl"
#endif

// A ray entering the top plane at (origin, 0) going along dir (dir.z > 0), parameterised by
// depth: p(z) = origin + z * dir.xy / dir.z.
struct Ray {
    vec2 origin;
    vec3 dir;
    float depth_scale;
};

// A method's answer: the depth z of its hit on the ray, and how hard it worked.
struct Hit {
    float z;
    uint steps;
    bool capped;
};

// Iteration cap and refinement steps: specialization constants, so each pipeline is tuned without
// recompiling SPIR-V. Defaults suit the renderer; the bench sweeps them.
layout(constant_id = SPEC_BUDGET_MAX_STEPS) const uint BUDGET_MAX_STEPS = 32;
layout(constant_id = SPEC_BUDGET_REFINE_STEPS) const uint BUDGET_REFINE_STEPS = 5;
// How methods with a leaf stage (qrm, pdm, qdm, csm, rcsm, quadric) finish: 1 = the exact
// intersection of the ray with the bilinear patches it crosses, 0 = the paper's own refinement
// (linear search or interpolation, binary search, or stopping on the box surface). Methods
// without a leaf stage ignore it. The default is exact because the surface pass sets only
// constants 0 and 1, and the renderer wants the accurate answer.
layout(constant_id = SPEC_BUDGET_LEAF_EXACT) const uint BUDGET_LEAF_EXACT = 1;
// 0: BUDGET_MAX_STEPS is the cap. Otherwise each ray's cap grows by the texels its path crosses,
// up to this many steps (`ray_budget` in heightfield.glsl; Budget::extent_limit in Rust).
layout(constant_id = SPEC_BUDGET_EXTENT_LIMIT) const uint BUDGET_EXTENT_LIMIT = 0;

struct Budget {
    uint max_steps;
    uint refine_steps;
    bool exact_leaf;
};

Budget default_budget() {
    return Budget(BUDGET_MAX_STEPS, BUDGET_REFINE_STEPS, BUDGET_LEAF_EXACT != 0u);
}

// Vertical rays (dir.xy = 0) are fine; dir.z is kept away from 0 by the caller (ray_from_view).
vec2 ray_delta(Ray ray) {
    return ray.depth_scale * ray.dir.xy / ray.dir.z;
}

// The uv where the ray reaches depth z.
vec2 ray_uv(Ray ray, float z) {
    return ray.origin + (z / ray.dir.z) * ray.dir.xy;
}

#endif
