#version 460
#extension GL_GOOGLE_include_directive : require
// One level of the averaged (mean) height pyramid of Ki and Oh section 2.5: each coarse texel is
// the mean of the finer level's texels it covers in uv, the same covered range as the max
// pyramid (heightfield::pyramid::covered_range) without its bilinear widening, so odd sizes
// average every texel once. Read by LOD surface variants below their stop level
// (shaders/include/lod.glsl). HEIGHT_FORMAT (r16 or r32f) is set per variant by build.rs.
layout(local_size_x = 8, local_size_y = 8) in;

#include "interface.glsl"

layout(set = 0, binding = BINDING_PYRAMID_FINE, HEIGHT_FORMAT) uniform readonly image2D fine;
layout(set = 0, binding = BINDING_PYRAMID_COARSE, HEIGHT_FORMAT) uniform writeonly image2D coarse;

void main() {
    uvec2 coarse_len = uvec2(imageSize(coarse));
    uvec2 fine_len = uvec2(imageSize(fine));
    uvec2 i = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(i, coarse_len))) {
        return;
    }
    ivec2 first = ivec2((i * fine_len) / coarse_len);
    ivec2 last = ivec2(((i + 1u) * fine_len + coarse_len - 1u) / coarse_len - 1u);
    float sum = 0.0;
    for (int y = first.y; y <= last.y; ++y) {
        for (int x = first.x; x <= last.x; ++x) {
            sum += imageLoad(fine, ivec2(x, y)).r;
        }
    }
    ivec2 count = last - first + 1;
    imageStore(coarse, ivec2(i), vec4(sum / float(count.x * count.y)));
}
