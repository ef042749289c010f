#version 460
// Occlusion by ray query (src/render/traced): per ray, whether anything of the scene's
// acceleration structure lies on the segment. Triangles are opaque and commit themselves; a
// relief prism's box is a candidate that relief_prism.glsl resolves with the exact height-field
// walk. Any hit ends the query: a shadow ray needs no nearest one.
#extension GL_GOOGLE_include_directive : require
#extension GL_EXT_ray_query : require
#include "conventions.glsl"
#include "numeric.glsl"
#include "bindings.glsl"
#include "heightfield.glsl"
#include "relief_prism.glsl"

layout(local_size_x = 64) in;

layout(set = 0, binding = BINDING_OCCLUSION_SCENE) uniform accelerationStructureEXT scene;
layout(set = 0, binding = BINDING_OCCLUSION_PRISMS, std430) readonly buffer Prisms {
    PrismRecord prisms[];
};
// Per ray: xyz origin, w its first t; xyz direction, w its last t.
layout(set = 0, binding = BINDING_OCCLUSION_RAYS, std430) readonly buffer Rays { vec4 rays[]; };
// Per ray: 1 if blocked, prisms tested, walk steps, 1 if a walk ran out of budget.
layout(set = 0, binding = BINDING_OCCLUSION_RESULTS, std430) writeonly buffer Results {
    uvec4 results[];
};

#include "traced_query.glsl"

// The fields: OcclusionParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform OcclusionParams {
    OCCLUSION_PARAMS_FIELDS
} params;

void main() {
    uint k = gl_GlobalInvocationID.x;
    if (k >= params.count.x) {
        return;
    }
    vec4 o = rays[2u * k];
    vec4 d = rays[2u * k + 1u];
    uint tested = 0u;
    uint steps = 0u;
    bool capped = false;
    bool blocked = segment_blocked(o.xyz, o.w, d.xyz, d.w, tested, steps, capped);
    results[k] = uvec4(blocked ? 1u : 0u, tested, steps, capped ? 1u : 0u);
}
