#version 460
// The timed pass of `relief bench`: a full-screen quad whose every pixel traces one parallel ray
// (entering at the pixel's uv) with this variant's method, through the same bindings as the
// surface pass. The hit is written out so the work cannot be skipped.
#extension GL_GOOGLE_include_directive : require
#include "conventions.glsl"
#include "numeric.glsl"
#include "bindings.glsl"
#include "heightfield.glsl"
#include "method.glsl"

layout(location = 0) in vec2 in_uv;
layout(location = 0) out vec4 out_hit;  // z, steps, capped, unused

layout(push_constant, std430) uniform BenchParams {
    vec4 dir;  // xyz: ray direction (dz > 0), w: depth scale
} params;

void main() {
    Ray ray = Ray(in_uv, params.dir.xyz, params.dir.w);
    Hit hit = METHOD_TRACE(ray, default_budget());
    out_hit = vec4(hit.z, float(hit.steps), hit.capped ? 1.0 : 0.0, 0.0);
}
