#version 460
#extension GL_GOOGLE_include_directive : require
// One level of the prefiltered specular map: each texel the environment averaged over the GGX
// lobe of the level's roughness around its direction, with the normal and the view along it
// (the split sum's first factor). GGX importance sampling with filtered lookups: each sample
// reads the source level whose texels cover the solid angle the sample stands for, so a few
// hundred samples give a smooth average. The CPU reference environment::reference::prefiltered
// computes the same, and the tests compare the two.
layout(local_size_x = 8, local_size_y = 8) in;

#include "interface.glsl"
#include "equirect.glsl"

layout(set = 0, binding = BINDING_ENV_SOURCE) uniform sampler2D source;
layout(set = 0, binding = BINDING_ENV_OUT, rgba16f) uniform writeonly image2D level;

// The fields: EnvironmentParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    ENVIRONMENT_PARAMS_FIELDS
} params;

void main() {
    uvec2 id = gl_GlobalInvocationID.xy;
    if (id.x >= params.out_width || id.y >= params.out_height) {
        return;
    }
    vec3 r = equirect_direction((vec2(id) + 0.5) / vec2(params.out_width, params.out_height));
    vec3 result;
    if (params.roughness <= 0.0) {
        result = textureLod(source, equirect_uv(r), params.base_lod).rgb;
    } else {
        vec3 up = abs(r.y) < 0.999 ? vec3(0.0, 1.0, 0.0) : vec3(1.0, 0.0, 0.0);
        vec3 t = normalize(cross(up, r));
        vec3 b = cross(r, t);
        float a = params.roughness * params.roughness;
        float a2 = a * a;
        // The solid angle of a level-0 texel, on average over the sphere.
        float texel_solid_angle =
            4.0 * EQUIRECT_PI / float(params.source_width * params.source_height);
        vec3 sum = vec3(0.0);
        float weight = 0.0;
        for (uint i = 0u; i < params.samples; ++i) {
            vec3 hl = ggx_half_vector(hammersley(i, params.samples), a2);
            vec3 h = t * hl.x + b * hl.y + r * hl.z;
            vec3 l = 2.0 * dot(r, h) * h - r;
            float nl = dot(r, l);
            if (nl <= 0.0) {
                continue;
            }
            float denom = hl.z * hl.z * (a2 - 1.0) + 1.0;
            float d = a2 / (EQUIRECT_PI * denom * denom);
            // With the view along the normal, the sample's pdf over directions is D / 4.
            float sample_solid_angle = 4.0 / (float(params.samples) * d);
            float lod = max(0.5 * log2(sample_solid_angle / texel_solid_angle), 0.0);
            sum += textureLod(source, equirect_uv(l), lod).rgb * nl;
            weight += nl;
        }
        result = sum / max(weight, 1e-6);
    }
    imageStore(level, ivec2(id), vec4(min(result, vec3(65504.0)), 1.0));
}
