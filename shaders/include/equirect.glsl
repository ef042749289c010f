// Equirectangular directions, +Y up: u turns around the up axis from +X toward +Z, v runs from
// straight up (0) to straight down (1): the convention of src/environment/mod.rs (direction,
// equirect_uv), whose CPU lookups the tests compare with.
#ifndef EQUIRECT_GLSL
#define EQUIRECT_GLSL

const float EQUIRECT_PI = 3.14159265358979;

vec3 equirect_direction(vec2 uv) {
    float theta = EQUIRECT_PI * uv.y;
    float phi = 2.0 * EQUIRECT_PI * uv.x;
    return vec3(sin(theta) * cos(phi), cos(theta), sin(theta) * sin(phi));
}

// `d` must not be zero. u is left in [-1/2, 1/2]; the samplers repeat along u.
vec2 equirect_uv(vec3 d) {
    d = normalize(d);
    return vec2(atan(d.z, d.x) / (2.0 * EQUIRECT_PI), acos(clamp(d.y, -1.0, 1.0)) / EQUIRECT_PI);
}

// The Hammersley point i of n: evenly spread, the same for every texel, so the maps are smooth.
vec2 hammersley(uint i, uint n) {
    return vec2((float(i) + 0.5) / float(n), float(bitfieldReverse(i)) * 2.3283064365386963e-10);
}

// A half vector of the GGX distribution of alpha^2 `a2` around +Z, from a uniform point `xi`:
// its pdf is D(h) cos(theta_h).
vec3 ggx_half_vector(vec2 xi, float a2) {
    float cos_h = sqrt((1.0 - xi.x) / (1.0 + (a2 - 1.0) * xi.x));
    float sin_h = sqrt(max(1.0 - cos_h * cos_h, 0.0));
    float phi = 2.0 * EQUIRECT_PI * xi.y;
    return vec3(sin_h * cos(phi), sin_h * sin(phi), cos_h);
}

#endif
