// What the mesh passes (mesh.vert, surface.frag) read per draw: the model matrix and its normal
// matrix as push constants (made once per object on the CPU, not per vertex), and the material's
// parameters and textures in set 1.
#ifndef DRAW_GLSL
#define DRAW_GLSL

#include "interface.glsl"

// The model matrix, its normal matrix and the draw's ids: `DrawPush` in interface.glsl.
layout(push_constant, std430) uniform Draw {
    DRAW_FIELDS
} draw;

// Texture slots (SLOT_BASE_COLOR ... SLOT_HEIGHT) are in interface.glsl.
// Not a texture slot: bit 6 of `textures.x` says the relief's AO map is bound (its binding's number).
const int SLOT_RELIEF_AO = BINDING_MATERIAL_RELIEF_AO;

// The material's factors, texture bits and uv transforms: `MaterialUniform` in interface.glsl.
layout(set = 1, binding = BINDING_MATERIAL_PARAMS, std140) uniform MaterialParams {
    MATERIAL_PARAMS_FIELDS
} material;

layout(set = 1, binding = BINDING_MATERIAL_BASE_COLOR) uniform sampler2D tex_base_color;
layout(set = 1, binding = BINDING_MATERIAL_METALLIC_ROUGHNESS) uniform sampler2D tex_metallic_roughness;
layout(set = 1, binding = BINDING_MATERIAL_NORMAL) uniform sampler2D tex_normal;
layout(set = 1, binding = BINDING_MATERIAL_OCCLUSION) uniform sampler2D tex_occlusion;
layout(set = 1, binding = BINDING_MATERIAL_EMISSIVE) uniform sampler2D tex_emissive;
// The relief's texture-space AO map (one value per height texel, read at the hit's height uv).
layout(set = 1, binding = BINDING_MATERIAL_RELIEF_AO) uniform sampler2D tex_relief_ao;

bool has_texture(int slot) {
    return (material.textures.x & (1u << uint(slot))) != 0u;
}

// The texture coordinate set a slot reads (0 or 1).
int slot_set(int slot) {
    return material.uv_rows[2 * slot].w > 0.5 ? 1 : 0;
}

// The slot's transformed uv from the two coordinate sets.
vec2 slot_uv(int slot, vec2 uv0, vec2 uv1) {
    vec3 tc = vec3(slot_set(slot) == 1 ? uv1 : uv0, 1.0);
    return vec2(dot(material.uv_rows[2 * slot].xyz, tc), dot(material.uv_rows[2 * slot + 1].xyz, tc));
}

// The linear part of a slot's transform.
mat2 slot_linear(int slot) {
    vec4 r0 = material.uv_rows[2 * slot];
    vec4 r1 = material.uv_rows[2 * slot + 1];
    return mat2(r0.x, r1.x, r0.y, r1.y);  // columns
}

#endif
