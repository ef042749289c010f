// Per-draw push constants of the mesh passes (mesh.vert, surface.frag).
#ifndef DRAW_GLSL
#define DRAW_GLSL

layout(push_constant, std430) uniform Draw {
    mat4 model;
    vec4 base_color;
    vec4 material;     // x: depth scale (uv units, 0 = no relief), y: roughness, z: metallic
} draw;

#endif
