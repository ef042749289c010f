#version 460
#extension GL_GOOGLE_include_directive : require
// Level L of the max pyramid the cone and quadric map searches read (buffer_pyramid.glsl), from
// level L - 1: one invocation per node of level L. One dispatch per level, a barrier between.
layout(local_size_x = 8, local_size_y = 8) in;

// MAX_LEVELS and the bindings; the map (BINDING_SEARCH_MAP) is in the set but not read here.
#include "interface.glsl"

// All pyramid levels back to back, level 0 (width x height) first.
layout(set = 0, binding = BINDING_SEARCH_PYRAMID, std430) buffer Pyramid {
    float pyramid[];
};

// The fields: PyramidReduceParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    PYRAMID_REDUCE_PARAMS_FIELDS
} params;

#include "buffer_pyramid.glsl"

void main() {
    uint level = params.level;
    pyramid_reduce(uvec2(params.width, params.height), level, params.offsets[level - 1u],
                   params.offsets[level], gl_GlobalInvocationID.xy);
}
