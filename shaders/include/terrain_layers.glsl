// Height-blended layers (Drobot, 1.7): what a layered material shows at the hit. The method
// has traced the blended surface itself (the height map of set 0 is the blend); here the layers'
// colours, normals and roughness are mixed by the blend mode's shading weights, the same as
// `terrain::BlendMode::shading_weights`: the splat weights for `alpha`, height times weight,
// normalised, for `height` and `height-intersect` (the higher layer shows: sand in the cracks
// between stones). Set 2 is bound by src/render/terrain/layer_set.rs.
#ifndef TERRAIN_LAYERS_GLSL
#define TERRAIN_LAYERS_GLSL

#include "interface.glsl"

// rgb: sRGB albedo; a: the layer's height times its depth.
layout(set = 2, binding = BINDING_LAYER_ALBEDO_HEIGHT) uniform sampler2DArray layer_albedo_height;
// rgb: tangent-space normal, OpenGL convention (+y toward image row 0); a: roughness.
layout(set = 2, binding = BINDING_LAYER_NORMAL_ROUGHNESS) uniform sampler2DArray layer_normal_roughness;
// The splat map: channel k weighs layer k; bilinear, clamped.
layout(set = 2, binding = BINDING_LAYER_WEIGHTS) uniform sampler2D layer_weights;
// Blend mode, layer count, tiling and height scales: `LayerUniform` in interface.glsl.
layout(set = 2, binding = BINDING_LAYER_PARAMS, std140) uniform LayerParams {
    LAYER_PARAMS_FIELDS
} layer_params;

struct LayerMix {
    vec4 weights;     // shading weight of each layer, summing to 1
    vec3 albedo;      // linear
    float roughness;
    vec3 normal;      // world space
};

// The vertex colour the material is tinted by: none when the colours are the layers' weights.
vec4 layer_vertex_tint(vec4 color) {
    return layer_params.info.w != 0u ? vec4(1.0) : color;
}

vec4 layer_shading_weights(vec4 h, vec4 w) {
    vec4 by = layer_params.info.x == 0u ? w : h * w;
    float sum = dot(by, vec4(1.0));
    if (sum > 0.0) {
        return by / sum;
    }
    float wsum = dot(w, vec4(1.0));
    return wsum > 0.0 ? w / wsum : vec4(0.0);
}

// The layers mixed at height uv `uv`. `relief_normal` is the blended surface's own normal (world),
// which a layer without a normal map shows; `f` carries the world directions of +u and +v.
LayerMix mix_layers(vec2 uv, vec3 relief_normal, vec3 t, vec3 b, vec3 n) {
    int count = int(layer_params.info.y);
    vec4 w = texture(layer_weights, uv);
    vec4 albedo[4];
    vec4 detail[4];
    vec4 h = vec4(0.0);
    for (int k = 0; k < 4; ++k) {
        if (k >= count) {
            w[k] = 0.0;
            albedo[k] = vec4(0.0);
            detail[k] = vec4(0.5, 0.5, 1.0, 1.0);
            continue;
        }
        vec3 at = vec3(uv * layer_params.tiling[k], float(k));
        albedo[k] = texture(layer_albedo_height, at);
        detail[k] = texture(layer_normal_roughness, at);
        h[k] = albedo[k].a;
    }
    LayerMix m;
    m.weights = layer_shading_weights(h, w);
    m.albedo = vec3(0.0);
    m.roughness = 0.0;
    m.normal = vec3(0.0);
    for (int k = 0; k < count; ++k) {
        float s = m.weights[k];
        m.albedo += s * albedo[k].rgb;
        m.roughness += s * detail[k].a;
        vec3 layer_normal = relief_normal;
        if ((layer_params.info.z & (1u << uint(k))) != 0u) {
            // +y of the map points toward row 0, against +v; a shallower layer tilts less.
            vec3 tn = detail[k].xyz * 2.0 - 1.0;
            tn.xy *= layer_params.depth[k];
            layer_normal = normalize(t * tn.x - b * tn.y + n * tn.z);
        }
        m.normal += s * layer_normal;
    }
    float len = length(m.normal);
    m.normal = len > 1e-6 ? m.normal / len : relief_normal;
    return m;
}

#endif
