// What the mesh passes (mesh.vert, surface.frag) read per draw: the model matrix and its normal
// matrix as push constants (made once per object on the CPU, not per vertex), and the material's
// parameters and textures in set 1.
#ifndef DRAW_GLSL
#define DRAW_GLSL

#include "interface.glsl"

// Mirrors `DrawPush` in src/render/kit/draw_push.rs.
layout(push_constant, std430) uniform Draw {
    mat4 model;
    // Columns of the inverse transpose of the model's linear part; normal[0].w is -1 when the
    // model mirrors (negative determinant), else 1.
    vec4 normal[3];
    uvec4 extra;  // x: the shadow view a caster draw renders into (shadow pass only); y: the
                  // scene mesh index + 1 (the G-buffer's mesh channel)
} draw;

// Texture slots; mirrors `TextureSlot` in src/scene/material.rs, plus the height map's uv.
const int SLOT_BASE_COLOR = 0;
const int SLOT_METALLIC_ROUGHNESS = 1;
const int SLOT_NORMAL = 2;
const int SLOT_OCCLUSION = 3;
const int SLOT_EMISSIVE = 4;
const int SLOT_HEIGHT = 5;
// Not a texture slot: bit 6 of `textures.x` says the relief's AO map is bound (its binding's number).
const int SLOT_RELIEF_AO = BINDING_MATERIAL_RELIEF_AO;

// Mirrors `MaterialUniform` in src/render/frame/material_set.rs.
layout(set = 1, binding = BINDING_MATERIAL_PARAMS, std140) uniform MaterialParams {
    vec4 base_color;
    vec4 emissive;     // rgb: emissive factor; w: alpha cutoff (mask mode), -1 otherwise
    vec4 pbr;          // x: roughness, y: metallic, z: normal scale, w: occlusion strength
    vec4 relief;       // x: depth scale (uv units of the height map, 0 = none); y: 1 if blended
    uvec4 textures;    // x: bit k set when slot k has a texture
    // Per slot, KHR_texture_transform as two rows of a 2x3 matrix; row 0's w: texCoord set.
    vec4 uv_rows[12];
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
