#version 460
#extension GL_GOOGLE_include_directive : require
// The environment's irradiance map: each texel the cosine-weighted mean radiance around its
// direction, the sum of L cos(theta) dOmega over every texel of one source level (a level at
// most 64 texels wide: the cosine lobe is smooth) over the sum of cos(theta) dOmega alone, so a
// uniform environment comes back exactly. The CPU reference environment::reference::irradiance
// computes the same, and the tests compare the two.
layout(local_size_x = 8, local_size_y = 8) in;

#include "interface.glsl"
#include "equirect.glsl"

layout(set = 0, binding = BINDING_ENV_SOURCE) uniform sampler2D source;
layout(set = 0, binding = BINDING_ENV_OUT, rgba16f) uniform writeonly image2D irradiance;

// The fields: EnvironmentParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    ENVIRONMENT_PARAMS_FIELDS
} params;

void main() {
    uvec2 id = gl_GlobalInvocationID.xy;
    if (id.x >= params.out_width || id.y >= params.out_height) {
        return;
    }
    vec3 n = equirect_direction((vec2(id) + 0.5) / vec2(params.out_width, params.out_height));
    uint w = params.source_width;
    uint h = params.source_height;
    vec3 sum = vec3(0.0);
    float weight = 0.0;
    for (uint y = 0u; y < h; ++y) {
        float theta0 = EQUIRECT_PI * float(y) / float(h);
        float theta1 = EQUIRECT_PI * float(y + 1u) / float(h);
        float solid_angle = 2.0 * EQUIRECT_PI / float(w) * (cos(theta0) - cos(theta1));
        vec3 row = vec3(0.0);
        float row_weight = 0.0;
        for (uint x = 0u; x < w; ++x) {
            vec3 l = equirect_direction((vec2(x, y) + 0.5) / vec2(w, h));
            float c = dot(n, l);
            if (c > 0.0) {
                row += c * texelFetch(source, ivec2(x, y), int(params.source_level)).rgb;
                row_weight += c;
            }
        }
        sum += row * solid_angle;
        weight += row_weight * solid_angle;
    }
    imageStore(irradiance, ivec2(id), vec4(min(sum / max(weight, 1e-6), vec3(65504.0)), 1.0));
}
