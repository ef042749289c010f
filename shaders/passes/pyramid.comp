#version 460
// One level of the conservative max pyramid: each coarse texel takes the max of every texel of
// the finer level that it overlaps in uv, so odd sizes stay conservative. Must match
// heightfield::pyramid::covered_range: coarse i over fine length F and coarse length C covers
// fine texels floor(i*F/C) .. ceil((i+1)*F/C) - 1.
// HEIGHT_FORMAT (r16 or r32f) is set per variant by build.rs.
layout(local_size_x = 8, local_size_y = 8) in;

layout(set = 0, binding = 0, HEIGHT_FORMAT) uniform readonly image2D fine;
layout(set = 0, binding = 1, HEIGHT_FORMAT) uniform writeonly image2D coarse;

uvec2 covered_first(uvec2 i, uvec2 fine_len, uvec2 coarse_len) {
    return (i * fine_len) / coarse_len;
}

uvec2 covered_last(uvec2 i, uvec2 fine_len, uvec2 coarse_len) {
    return ((i + 1u) * fine_len + coarse_len - 1u) / coarse_len - 1u;
}

void main() {
    uvec2 coarse_len = uvec2(imageSize(coarse));
    uvec2 fine_len = uvec2(imageSize(fine));
    uvec2 i = gl_GlobalInvocationID.xy;
    if (any(greaterThanEqual(i, coarse_len))) {
        return;
    }
    uvec2 first = covered_first(i, fine_len, coarse_len);
    uvec2 last = covered_last(i, fine_len, coarse_len);
    float h = 0.0;
    for (uint y = first.y; y <= last.y; ++y) {
        for (uint x = first.x; x <= last.x; ++x) {
            h = max(h, imageLoad(fine, ivec2(x, y)).r);
        }
    }
    imageStore(coarse, ivec2(i), vec4(h));
}
