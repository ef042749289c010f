// The rays from a point toward a light of some size, as the exact shadow reference casts them
// (src/shadow_reference/light_samples.rs): an n x n grid of strata on the unit square, carried by
// the concentric square-to-disk map and the equal-area disk-to-cap map onto the cone the light
// fills, so every ray stands for the same solid angle; one ray to the centre for a light of
// radius 0 (exactly the reference's). The strata's jitter is a 32-bit hash here, not the
// reference's 64-bit one: soft shadows agree in distribution, hard ones ray for ray.
// Needs bindings.glsl (the frame block) first.
#ifndef LIGHT_RAYS_GLSL
#define LIGHT_RAYS_GLSL

// Where a ray toward the light may end when the light is infinitely far.
const float LIGHT_RAY_FAR = 1e30;

struct LightCone {
    vec3 axis;         // unit, toward the light's centre
    float half_angle;  // radians; 0 for a light without size
    vec3 side;         // with `up`, an orthonormal pair across the axis
    float one_minus_cos;
    vec3 up;
    float radius;      // the sphere's (point and spot lights)
    vec3 centre;
    bool reachable;    // false inside a point or spot light's sphere: nothing fits between
    bool sphere;       // a point or spot light: its rays end at its sphere
};

LightCone light_cone(int i, vec3 p) {
    LightData light = frame.lights[i];
    LightCone c;
    c.reachable = true;
    c.sphere = int(light.position.w) != 0;
    c.radius = 0.0;
    c.centre = vec3(0.0);
    if (int(light.position.w) == 0) {
        c.axis = -normalize(light.direction.xyz);
        c.half_angle = clamp(light.cone.z, 0.0, PI);
    } else {
        vec3 to = light.position.xyz - p;
        float distance = length(to);
        c.reachable = distance > light.cone.z && distance > 0.0;
        c.axis = to / max(distance, 1e-30);
        c.half_angle = asin(clamp(light.cone.z / max(distance, 1e-30), 0.0, 1.0));
        c.radius = light.cone.z;
        c.centre = light.position.xyz;
    }
    // Duff et al.'s branchless orthonormal basis, as glam's any_orthonormal_pair.
    float s = c.axis.z >= 0.0 ? 1.0 : -1.0;
    float a = -1.0 / (s + c.axis.z);
    float b = c.axis.x * c.axis.y * a;
    c.side = vec3(1.0 + s * c.axis.x * c.axis.x * a, s * b, -s * c.axis.x);
    c.up = vec3(b, s + c.axis.y * c.axis.y * a, -c.axis.y);
    // 2 sin^2(r/2) rather than 1 - cos(r): a small light keeps its precision.
    float h = sin(0.5 * c.half_angle);
    c.one_minus_cos = 2.0 * h * h;
    return c;
}

// A hash of a stratum's indices to [0, 1).
float stratum_jitter(uint i, uint j, uint n, uint axis) {
    uint h = i * 0x9e3779b9u ^ (j + 0x7f4a7c15u) * 0x85ebca6bu ^ (n * 2u + axis) * 0xc2b2ae35u;
    h ^= h >> 16;
    h *= 0x7feb352du;
    h ^= h >> 15;
    h *= 0x846ca68bu;
    h ^= h >> 16;
    return float(h >> 8) / 16777216.0;
}

// Shirley and Chiu's concentric map from [-1, 1]^2 onto the unit disk.
vec2 concentric_disk(vec2 q) {
    if (q.x == 0.0 && q.y == 0.0) {
        return vec2(0.0);
    }
    float rho;
    float phi;
    if (abs(q.x) > abs(q.y)) {
        rho = q.x;
        phi = 0.25 * PI * (q.y / q.x);
    } else {
        rho = q.y;
        phi = 0.5 * PI - 0.25 * PI * (q.x / q.y);
    }
    return rho * vec2(cos(phi), sin(phi));
}

// Ray (i, j) of the n x n grid toward the light of `c` from p: its unit direction in `dir`;
// returns how far it may go before it reaches the light.
float light_ray(LightCone c, vec3 p, uint i, uint j, uint n, out vec3 dir) {
    vec2 cell = vec2(0.5);
    if (n > 1u) {
        cell = vec2(stratum_jitter(i, j, n, 0u), stratum_jitter(i, j, n, 1u));
    }
    vec2 q = (vec2(i, j) + cell) / float(n) * 2.0 - 1.0;
    vec2 d = concentric_disk(q);
    float rho2 = dot(d, d);
    float cos_t = 1.0 - rho2 * c.one_minus_cos;
    float sin_t = sqrt(max(1.0 - cos_t * cos_t, 0.0));
    float scale = rho2 > 0.0 ? sin_t / sqrt(rho2) : 0.0;
    dir = normalize(c.axis * cos_t + c.side * (d.x * scale) + c.up * (d.y * scale));
    if (!c.sphere) {
        return LIGHT_RAY_FAR;
    }
    // To the near side of the sphere, or its closest approach when rounding at the silhouette
    // makes the ray just miss.
    vec3 to = c.centre - p;
    float b = dot(dir, to);
    float disc = b * b - (dot(to, to) - c.radius * c.radius);
    return max(b - sqrt(max(disc, 0.0)), 0.0);
}

#endif
