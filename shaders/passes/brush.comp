#version 460
#extension GL_GOOGLE_include_directive : require
// One brush stroke on a terrain's elevation (level 0 of its height image), over the texels of the
// stroke's rectangle: the formulas of terrain::Stroke::apply in src/terrain/brush.rs, in the same
// order. HEIGHT_FORMAT (r16 or r32f) is set per variant by build.rs.
layout(local_size_x = 8, local_size_y = 8) in;

// The binding, the kinds and the push-constant fields.
#include "interface.glsl"

layout(set = 0, binding = BINDING_BRUSH_HEIGHTS, HEIGHT_FORMAT) uniform image2D heights;

// The fields: BrushParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    BRUSH_PARAMS_FIELDS
} params;

void main() {
    if (any(greaterThanEqual(gl_GlobalInvocationID.xy, params.region.zw))) {
        return;
    }
    ivec2 i = ivec2(gl_GlobalInvocationID.xy + params.region.xy);
    float h = imageLoad(heights, i).r;
    vec2 d = vec2(i) + 0.5 - params.stroke.xy;
    float r = sqrt(d.x * d.x + d.y * d.y) / params.stroke.z;
    if (r >= 1.0) {
        return;
    }
    float t = 1.0 - r;
    float falloff = t * t * (3.0 - 2.0 * t);
    float strength = params.stroke.w;
    uint kind = uint(params.shape.y);
    float out_h;
    if (kind == BRUSH_RAISE) {
        out_h = h + strength * falloff;
    } else if (kind == BRUSH_LOWER) {
        out_h = h - strength * falloff;
    } else if (kind == BRUSH_FLATTEN) {
        out_h = h + (params.shape.x - h) * (clamp(strength, 0.0, 1.0) * falloff);
    } else {
        float bowl = 1.0 - (r / 0.8) * (r / 0.8);
        float rim = max(1.0 - abs((r - 0.8) / 0.2), 0.0);
        out_h = h - strength * max(bowl, 0.0) + 0.25 * strength * rim;
    }
    imageStore(heights, i, vec4(clamp(out_h, 0.0, 1.0)));
}
