// The glTF metallic-roughness material at a surface point: what surface.frag and cells.frag read
// from the material's factors and textures (draw.glsl's set 1) before lighting it.
#ifndef MATERIAL_SAMPLE_GLSL
#define MATERIAL_SAMPLE_GLSL

// How a slot's texture is read at uv: with the fragment's own derivatives, unless the includer
// supplies its own (cells.frag, whose uvs jump across texture seams).
#ifndef MATERIAL_TEXTURE
#define MATERIAL_TEXTURE(slot, tex, uv) texture(tex, uv)
#endif

struct MaterialSample {
    vec4 base;
    float roughness;
    float metallic;
    // The glTF occlusion texture's, weighted by its strength.
    float occlusion;
    vec3 emissive;
};

MaterialSample sample_material(vec2 uv0, vec2 uv1, vec4 vertex_color) {
    MaterialSample m;
    m.base = material.base_color * vertex_color;
    if (has_texture(SLOT_BASE_COLOR)) {
        m.base *= MATERIAL_TEXTURE(SLOT_BASE_COLOR, tex_base_color, slot_uv(SLOT_BASE_COLOR, uv0, uv1));
    }
    m.roughness = material.pbr.x;
    m.metallic = material.pbr.y;
    if (has_texture(SLOT_METALLIC_ROUGHNESS)) {
        vec4 mr = MATERIAL_TEXTURE(SLOT_METALLIC_ROUGHNESS, tex_metallic_roughness,
                                   slot_uv(SLOT_METALLIC_ROUGHNESS, uv0, uv1));
        m.roughness *= mr.g;
        m.metallic *= mr.b;
    }
    m.occlusion = 1.0;
    if (has_texture(SLOT_OCCLUSION)) {
        float ao = MATERIAL_TEXTURE(SLOT_OCCLUSION, tex_occlusion, slot_uv(SLOT_OCCLUSION, uv0, uv1)).r;
        m.occlusion = mix(1.0, ao, material.pbr.w);
    }
    m.emissive = material.emissive.rgb;
    if (has_texture(SLOT_EMISSIVE)) {
        m.emissive *= MATERIAL_TEXTURE(SLOT_EMISSIVE, tex_emissive, slot_uv(SLOT_EMISSIVE, uv0, uv1)).rgb;
    }
    return m;
}

// Whether alpha-mask mode cuts the point away.
bool material_cut(MaterialSample m) {
    float cutoff = material.emissive.w;
    return cutoff >= 0.0 && m.base.a < cutoff;
}

// The normal map's normal around n, in the frame of `tangent` (xyz, w: the bitangent's sign).
vec3 tangent_frame_normal(vec3 n, vec4 tangent, vec2 uv0, vec2 uv1) {
    vec3 t = normalize(tangent.xyz - n * dot(n, tangent.xyz));
    vec3 b = cross(n, t) * (tangent.w < 0.0 ? -1.0 : 1.0);
    vec3 m = MATERIAL_TEXTURE(SLOT_NORMAL, tex_normal, slot_uv(SLOT_NORMAL, uv0, uv1)).xyz * 2.0 - 1.0;
    m.xy *= material.pbr.z;
    return normalize(t * m.x + b * m.y + n * m.z);
}

#endif
