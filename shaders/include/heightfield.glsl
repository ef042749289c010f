// Texel maths and height fetches over the two samplers (DESIGN.md section 2).
#ifndef HEIGHTFIELD_GLSL
#define HEIGHTFIELD_GLSL

vec2 height_size() {
    return frame.height_info.xy;
}

// Bilinear height at uv (level 0): the true surface.
float height_bilinear(vec2 uv) {
    return textureLod(height_linear, uv, 0.0).r;
}

// Height of the texel containing uv at pyramid level `level` (level 0: the box surface).
float height_max(vec2 uv, float level) {
    return textureLod(height_point, uv, level).r;
}

// Depth below the top plane of the bilinear surface, in uv units.
float depth_bilinear(vec2 uv, float depth_scale) {
    return depth_scale * (1.0 - height_bilinear(uv));
}

// Surface gradient (dh/du, dh/dv) by central differences one texel apart.
vec2 height_gradient(vec2 uv) {
    vec2 texel = 1.0 / height_size();
    float hx = height_bilinear(uv + vec2(texel.x, 0.0)) - height_bilinear(uv - vec2(texel.x, 0.0));
    float hy = height_bilinear(uv + vec2(0.0, texel.y)) - height_bilinear(uv - vec2(0.0, texel.y));
    return vec2(hx, hy) / (2.0 * texel);
}

#endif
