#version 460
#extension GL_GOOGLE_include_directive : require
// The split sum's second factor: the GGX lobe's directional albedo at (view cosine, roughness),
// as a scale and a bias on F0 (Schlick's Fresnel, Smith's visibility with k = alpha / 2), by
// importance sampling. The CPU reference environment::reference::brdf_scale_bias computes the
// same table, and the tests compare the two.
layout(local_size_x = 8, local_size_y = 8) in;

#include "interface.glsl"
#include "equirect.glsl"

layout(set = 0, binding = BINDING_ENV_OUT, rgba16f) uniform writeonly image2D table;

// The fields: EnvironmentParams in src/render/shader_interface/push_constants.rs.
layout(push_constant, std430) uniform Params {
    ENVIRONMENT_PARAMS_FIELDS
} params;

void main() {
    uvec2 id = gl_GlobalInvocationID.xy;
    if (id.x >= params.out_width || id.y >= params.out_height) {
        return;
    }
    float nv = (float(id.x) + 0.5) / float(params.out_width);
    float roughness = (float(id.y) + 0.5) / float(params.out_height);
    vec3 v = vec3(sqrt(1.0 - nv * nv), 0.0, nv);
    float a = max(roughness * roughness, 1e-4);
    float a2 = a * a;
    float k = a / 2.0;
    float scale = 0.0;
    float bias = 0.0;
    for (uint i = 0u; i < params.samples; ++i) {
        vec3 h = ggx_half_vector(hammersley(i, params.samples), a2);
        float vh = dot(v, h);
        vec3 l = 2.0 * vh * h - v;
        if (l.z <= 0.0 || vh <= 0.0) {
            continue;
        }
        float g = (l.z / (l.z * (1.0 - k) + k)) * (nv / (nv * (1.0 - k) + k));
        float g_vis = g * vh / (h.z * nv);
        float fc = pow(1.0 - vh, 5.0);
        scale += (1.0 - fc) * g_vis;
        bias += fc * g_vis;
    }
    imageStore(table, ivec2(id), vec4(scale, bias, 0.0, 1.0) / vec4(vec3(params.samples), 1.0));
}
