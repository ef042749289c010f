// Ambient light: the frame's flat ambient colour, or the environment's image-based light when
// the frame has one (frame.counts.z = 1): diffuse from the irradiance map, specular from the
// prefiltered map and the BRDF table (the split sum), both darkened by the surface's occlusion.
// Needs bindings.glsl (the frame block) first.
#ifndef ENVIRONMENT_LIGHT_GLSL
#define ENVIRONMENT_LIGHT_GLSL

#include "equirect.glsl"

layout(set = 0, binding = BINDING_ENV_IRRADIANCE) uniform sampler2D env_irradiance;
layout(set = 0, binding = BINDING_ENV_SPECULAR) uniform sampler2D env_specular;
layout(set = 0, binding = BINDING_ENV_BRDF) uniform sampler2D env_brdf;

// Lagarde and de Rousiers' specular occlusion: ambient occlusion darkens a glossy reflection
// less at grazing views and more the smoother the surface.
float specular_occlusion(float nv, float occlusion, float roughness) {
    return clamp(pow(nv + occlusion, exp2(-16.0 * roughness - 1.0)) - 1.0 + occlusion, 0.0, 1.0);
}

vec3 ambient_light(vec3 albedo, float roughness, float metallic, vec3 n, vec3 v, float occlusion) {
    if (frame.counts.z == 0) {
        return frame.ambient.rgb * albedo * occlusion;
    }
    float nv = clamp(dot(n, v), 1e-4, 1.0);
    vec3 f0 = mix(vec3(0.04), albedo, metallic);
    vec2 scale_bias = texture(env_brdf, vec2(nv, roughness)).rg;
    vec3 specular_albedo = f0 * scale_bias.x + scale_bias.y;
    vec3 irradiance = textureLod(env_irradiance, equirect_uv(n), 0.0).rgb;
    // frame.ambient.w: the prefiltered map's last level (roughness 1).
    float lod = clamp(roughness, 0.0, 1.0) * frame.ambient.w;
    vec3 prefiltered = textureLod(env_specular, equirect_uv(reflect(-v, n)), lod).rgb;
    // What the specular lobe reflects is not there to scatter diffusely: in a uniform white
    // environment a white dielectric returns exactly the environment's radiance.
    vec3 diffuse = (1.0 - specular_albedo) * (1.0 - metallic) * albedo * irradiance * occlusion;
    return diffuse + specular_albedo * prefiltered * specular_occlusion(nv, occlusion, roughness);
}

#endif
