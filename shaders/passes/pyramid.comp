#version 460
#extension GL_GOOGLE_include_directive : require
// One level of the conservative max pyramid: each coarse texel takes the max of every texel of
// the finer level that it overlaps in uv (widened by a texel for level 1), so odd sizes and the
// bilinear surface stay bounded. Must match
// heightfield::pyramid::covered_range: coarse i over fine length F and coarse length C covers
// fine texels floor(i*F/C) .. ceil((i+1)*F/C) - 1.
// HEIGHT_FORMAT (r16 or r32f, or rgba16 or rgba32f for a terrain's four layers or weights, one
// pyramid per channel) is set per variant by build.rs.
layout(local_size_x = 8, local_size_y = 8) in;

// The bindings and the push-constant fields.
#include "interface.glsl"

layout(set = 0, binding = BINDING_PYRAMID_FINE, HEIGHT_FORMAT) uniform readonly image2D fine;
layout(set = 0, binding = BINDING_PYRAMID_COARSE, HEIGHT_FORMAT) uniform writeonly image2D coarse;

// The fields: PyramidParams in src/render/shader_interface/push_constants.rs (the widening is
// heightfield::pyramid::build_bilinear_bound's, the regions terrain::coarse_span's).
layout(push_constant, std430) uniform Params {
    PYRAMID_PARAMS_FIELDS
} params;

// k lies at most one texel outside [0, len); GLSL leaves % of negatives undefined, so wrap by hand.
int fine_index(int k, int len) {
    if (params.flags.y != 0u) {
        return k < 0 ? k + len : (k >= len ? k - len : k);
    }
    return clamp(k, 0, len - 1);
}

uvec2 covered_first(uvec2 i, uvec2 fine_len, uvec2 coarse_len) {
    return (i * fine_len) / coarse_len;
}

uvec2 covered_last(uvec2 i, uvec2 fine_len, uvec2 coarse_len) {
    return ((i + 1u) * fine_len + coarse_len - 1u) / coarse_len - 1u;
}

void main() {
    uvec2 coarse_len = uvec2(imageSize(coarse));
    uvec2 fine_len = uvec2(imageSize(fine));
    uvec2 i = gl_GlobalInvocationID.xy + params.region.xy;
    if (any(greaterThanEqual(gl_GlobalInvocationID.xy, params.region.zw))
        || any(greaterThanEqual(i, coarse_len))) {
        return;
    }
    int margin = params.flags.x != 0u ? 1 : 0;
    ivec2 first = ivec2(covered_first(i, fine_len, coarse_len)) - margin;
    ivec2 last = ivec2(covered_last(i, fine_len, coarse_len)) + margin;
    ivec2 len = ivec2(fine_len);
    vec4 h = vec4(0.0);
    for (int y = first.y; y <= last.y; ++y) {
        for (int x = first.x; x <= last.x; ++x) {
            h = max(h, imageLoad(fine, ivec2(fine_index(x, len.x), fine_index(y, len.y))));
        }
    }
    imageStore(coarse, ivec2(i), h);
}
