#version 460
// The trace pass: one parallel ray per grid cell, entering at the cell centre, traced with the
// method this variant was compiled with; writes what `relief trace` dumps and the method's
// iteration count, and with a SHADOW_MODE the light's visible fraction at each hit (shadows.glsl).
// Same bindings as the surface pass, so the work per ray is the same.
#extension GL_GOOGLE_include_directive : require
#include "conventions.glsl"
#include "numeric.glsl"
#include "bindings.glsl"
#include "heightfield.glsl"
#include "method.glsl"
#include "shadows.glsl"

layout(local_size_x = 8, local_size_y = 8) in;

// One record per ray: u0 v0 dx dy dz u_hit v_hit z_hit (docs/conventions.md).
layout(set = 0, binding = BINDING_TRACE_HITS, std430) writeonly buffer Hits { float hits[]; };
// Per ray: steps used, and 1 if the method hit its iteration cap.
layout(set = 0, binding = BINDING_TRACE_STEPS, std430) writeonly buffer Steps { uvec2 steps[]; };
// Per ray: the light's visible fraction at the hit (1 when SHADOW_MODE is 0).
layout(set = 0, binding = BINDING_TRACE_VISIBLE, std430) writeonly buffer Visible { float visible[]; };
// Per ray, with COUNT_FETCHES set (heightfield.glsl): the method's texel fetches, then the shadow
// walk's. Without it nothing is written, and a one-entry stand-in is bound.
layout(set = 0, binding = BINDING_TRACE_FETCHES, std430) writeonly buffer Fetches { uvec2 fetches[]; };

// The fields: TraceParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform TraceParams {
    TRACE_PARAMS_FIELDS
} params;

void main() {
    uvec2 cell = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(cell, params.grid.xy))) {
        return;
    }
    vec2 origin = (vec2(cell) + 0.5) / vec2(params.grid.xy);
    Ray ray = Ray(origin, params.dir.xyz, params.dir.w);
    Hit hit = METHOD_TRACE(ray, ray_budget(ray));
    uint method_fetches = height_fetches;
    vec2 uv = ray_uv(ray, hit.z);
    uint k = cell.y * params.grid.x + cell.x;
    hits[8u * k + 0u] = origin.x;
    hits[8u * k + 1u] = origin.y;
    hits[8u * k + 2u] = ray.dir.x;
    hits[8u * k + 3u] = ray.dir.y;
    hits[8u * k + 4u] = ray.dir.z;
    hits[8u * k + 5u] = uv.x;
    hits[8u * k + 6u] = uv.y;
    hits[8u * k + 7u] = hit.z;
    steps[k] = uvec2(hit.steps, hit.capped ? 1u : 0u);
    visible[k] = light_visible(uv, hit.z, params.light.xyz, params.light.w, ray.depth_scale);
    if (COUNT_FETCHES != 0u) {
        fetches[k] = uvec2(method_fetches, height_fetches - method_fetches);
    }
}
