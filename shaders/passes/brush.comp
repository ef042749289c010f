#version 460
// One brush stroke on a terrain's elevation (level 0 of its height image), over the texels of the
// stroke's rectangle: the formulas of terrain::Stroke::apply in src/terrain/brush.rs, in the same
// order. HEIGHT_FORMAT (r16 or r32f) is set per variant by build.rs.
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, HEIGHT_FORMAT) uniform image2D heights;

// stroke: centre x, y (texels), radius (texels), strength; shape: target, kind (0 raise, 1 lower,
// 2 flatten, 3 crater); region: the texels to visit (x0, y0, width, height).
layout(push_constant, std430) uniform Params {
    vec4 stroke;
    vec4 shape;
    uvec4 region;
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
    if (kind == 0u) {
        out_h = h + strength * falloff;
    } else if (kind == 1u) {
        out_h = h - strength * falloff;
    } else if (kind == 2u) {
        out_h = h + (params.shape.x - h) * (clamp(strength, 0.0, 1.0) * falloff);
    } else {
        float bowl = 1.0 - (r / 0.8) * (r / 0.8);
        float rim = max(1.0 - abs((r - 0.8) / 0.2), 0.0);
        out_h = h - strength * max(bowl, 0.0) + 0.25 * strength * rim;
    }
    imageStore(heights, i, vec4(clamp(out_h, 0.0, 1.0)));
}
