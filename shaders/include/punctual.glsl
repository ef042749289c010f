// Punctual lights (KHR_lights_punctual): direction toward the light and its falloff at a point.
#ifndef PUNCTUAL_GLSL
#define PUNCTUAL_GLSL

// Direction toward light `i` from `world`, and in `attenuation` its distance and cone falloff.
vec3 light_toward(int i, vec3 world, out float attenuation) {
    LightData light = frame.lights[i];
    attenuation = 1.0;
    int kind = int(light.position.w);
    if (kind == 0) {
        return -light.direction.xyz;
    }
    vec3 d = light.position.xyz - world;
    float dist2 = max(dot(d, d), 1e-8);
    vec3 l = d * inversesqrt(dist2);
    attenuation = 1.0 / dist2;
    float range = light.direction.w;
    if (range > 0.0) {
        // The extension's recommended window: smooth to zero at the range.
        float r = dist2 / (range * range);
        float window = clamp(1.0 - r * r, 0.0, 1.0);
        attenuation *= window * window;
    }
    if (kind == 2) {
        float cd = dot(light.direction.xyz, -l);
        float spread = max(light.cone.y - light.cone.x, 1e-4);
        float t = clamp((cd - light.cone.x) / spread, 0.0, 1.0);
        attenuation *= t * t;
    }
    return l;
}

// Angular radius (radians) of light `i` seen from `world`: a directional light's own, or the
// angle its sphere subtends.
float light_angular_radius(int i, vec3 world) {
    LightData light = frame.lights[i];
    if (int(light.position.w) == 0) {
        return light.cone.z;
    }
    float dist = max(length(light.position.xyz - world), 1e-8);
    return asin(min(light.cone.z / dist, 1.0));
}

#endif
