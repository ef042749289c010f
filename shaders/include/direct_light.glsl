// The direct light a shaded point receives, one light at a time: the forward surface pass adds
// it per fragment, the deferred lighting pass (lighting.comp) per pixel, with the same sums.
// Needs bindings.glsl (the frame block) and lighting.glsl first.
#ifndef DIRECT_LIGHT_GLSL
#define DIRECT_LIGHT_GLSL

// The radiance the lights add, and the G-buffer's shadow share: each light facing the surface
// weighed by its luminance, attenuation and cosine, unshadowed and as it arrives.
struct DirectSum {
    vec3 radiance;
    float unshadowed;
    float arriving;
};

// Where the scene's shadow maps are looked up for light direction l: where the ray from the hit
// toward the light leaves the relief's top plane (`lift` below it along the polygon's normal n),
// since the maps hold the polygons and the height field answers for the path below them.
vec3 map_shadow_point(vec3 world, vec3 n, vec3 l, float lift) {
    float rise = dot(n, l);
    return rise > 1e-3 ? world + l * (lift / rise) : world;
}

// Adds light i, arriving with `attenuation` and the share `lit` of it no shadow blocked, to sum.
void add_direct_light(inout DirectSum sum, int i, float attenuation, float lit, vec3 albedo,
                      float roughness, float metallic, vec3 normal, vec3 v, vec3 l) {
    vec3 radiance = frame.lights[i].color.rgb * (attenuation * lit);
    sum.radiance += shade_ggx(albedo, roughness, metallic, normal, v, l, radiance);
    float weight = dot(frame.lights[i].color.rgb, vec3(0.2126, 0.7152, 0.0722)) * attenuation
                 * max(dot(normal, l), 0.0);
    sum.unshadowed += weight;
    sum.arriving += weight * lit;
}

// The share of the direct light that arrived, 1 where no light faces the surface.
float direct_lit_share(DirectSum sum) {
    return sum.unshadowed > 0.0 ? sum.arriving / sum.unshadowed : 1.0;
}

#endif
