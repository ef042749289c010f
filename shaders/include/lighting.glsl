// GGX (Trowbridge-Reitz) specular with Smith-Schlick visibility and a Lambert diffuse.
#ifndef LIGHTING_GLSL
#define LIGHTING_GLSL

const float PI = 3.14159265358979;

vec3 shade_ggx(vec3 albedo, float roughness, float metallic, vec3 n, vec3 v, vec3 l, vec3 radiance) {
    vec3 h = normalize(v + l);
    float nl = max(dot(n, l), 0.0);
    float nv = max(dot(n, v), 1e-4);
    float nh = max(dot(n, h), 0.0);
    float a = max(roughness * roughness, 1e-3);
    float a2 = a * a;
    float denom = nh * nh * (a2 - 1.0) + 1.0;
    float d = a2 / (PI * denom * denom);
    float k = (roughness + 1.0) * (roughness + 1.0) / 8.0;
    float vis = 1.0 / ((nl * (1.0 - k) + k) * (nv * (1.0 - k) + k) * 4.0);
    vec3 f0 = mix(vec3(0.04), albedo, metallic);
    vec3 f = f0 + (1.0 - f0) * pow(1.0 - max(dot(h, v), 0.0), 5.0);
    vec3 diffuse = (1.0 - f) * (1.0 - metallic) * albedo / PI;
    return (diffuse + d * vis * f) * radiance * nl;
}

#endif
