#version 460
#extension GL_GOOGLE_include_directive : require
// One level of a terrain's blended height pyramid (src/terrain, Drobot section 1.7) from the
// same level of its layers' and weights' max pyramids (pyramid.comp's rgba variants, one layer per
// channel). Level 0 is the blended surface itself, BlendMode::surface in src/terrain/blend.rs;
// levels 1 up are the conservative bound of src/terrain/blended_pyramid.rs. Both must match the
// CPU: the sums run in layer order and `precise` keeps the compiler from fusing them, so a
// one-hot weight returns its layer's height exactly.
// HEIGHT_FORMAT (r16 or r32f) is set per variant by build.rs.
layout(local_size_x = 8, local_size_y = 8) in;

// The bindings, the blend modes and the push-constant fields.
#include "interface.glsl"

// The layers' and the weights' pyramids, read texel by texel at the level built.
layout(set = 0, binding = BINDING_BLEND_LAYER_HEIGHTS) uniform sampler2D layer_heights;
layout(set = 0, binding = BINDING_BLEND_LAYER_WEIGHTS) uniform sampler2D layer_weights;
// The level of the blended pyramid being written.
layout(set = 0, binding = BINDING_BLEND_OUT, HEIGHT_FORMAT) uniform writeonly image2D blended;
// The max pyramid of 1 - min(sum of weights, 1): 1 minus it is a node's least weight sum
// (terrain::least_sum_slack).
layout(set = 0, binding = BINDING_BLEND_SLACK) uniform sampler2D least_sum_slack;

// Relative margin on the convex blends' weighted bound (WEIGHTED_MARGIN in blended_pyramid.rs).
const float WEIGHTED_MARGIN = 1.0 + 8.0 * 1.1920929e-7;

// The fields: BlendParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    BLEND_PARAMS_FIELDS
} params;

const uint HEIGHT_INTERSECT = BLEND_HEIGHT_INTERSECT;

// max(w h): the height-intersect surface at a texel, and its bound over a node from the maxima.
float highest_weighted(vec4 h, vec4 w) {
    precise vec4 hw = h * w;
    return max(max(max(hw.x, hw.y), hw.z), hw.w);
}

float surface(vec4 h, vec4 w) {
    if (params.flags.x == HEIGHT_INTERSECT) {
        return highest_weighted(h, w);
    }
    precise float sum = ((w.x + w.y) + w.z) + w.w;
    if (!(sum > 0.0)) {
        return 0.0;
    }
    precise float weighted = ((w.x * h.x + w.y * h.y) + w.z * h.z) + w.w * h.w;
    return min(weighted / sum, 1.0);
}

// terrain::node_bound: the node's bound from its layers' height and weight maxima and its least
// weight sum.
float bound(vec4 h, vec4 w, float least_sum) {
    if (params.flags.x == HEIGHT_INTERSECT) {
        return highest_weighted(h, w);
    }
    // A convex blend never rises above the highest layer it weighs, nor above the weighted sum of
    // the maxima over the least weight sum.
    vec4 weighed = mix(vec4(0.0), h, greaterThan(w, vec4(0.0)));
    float highest = max(max(max(weighed.x, weighed.y), weighed.z), weighed.w);
    if (least_sum > 0.0) {
        precise float weighted = ((w.x * h.x + w.y * h.y) + w.z * h.z) + w.w * h.w;
        return min(highest, weighted / least_sum * WEIGHTED_MARGIN);
    }
    return highest;
}

void main() {
    if (any(greaterThanEqual(gl_GlobalInvocationID.xy, params.region.zw))) {
        return;
    }
    ivec2 i = ivec2(gl_GlobalInvocationID.xy + params.region.xy);
    if (any(greaterThanEqual(i, imageSize(blended)))) {
        return;
    }
    int level = int(params.flags.y);
    vec4 h = texelFetch(layer_heights, i, level);
    vec4 w = texelFetch(layer_weights, i, level);
    float value;
    if (level == 0) {
        value = surface(h, w);
    } else {
        value = bound(h, w, 1.0 - texelFetch(least_sum_slack, i, level).r);
        if (params.flags.z != 0u) {
            // Stored to the nearest step, a bound could land below what it bounds.
            value = min(ceil(value * 65535.0) / 65535.0, 1.0);
        }
    }
    imageStore(blended, i, vec4(value));
}
