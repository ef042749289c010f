#version 460
// The example's quad: two triangles in the XZ plane facing +Y, made from the vertex index, with
// u along +x and v along +z (relief's `quad_mesh` with its texture once across it).
layout(push_constant, std430) uniform Push {
    mat4 view_proj;
    vec4 eye;         // xyz: the camera
    vec4 forward;     // xyz: the camera's axis
    vec4 quad;        // x: half the side, y: depth scale (uv units)
    vec4 height_info; // width, height, mip levels, 1 for repeat
} push;

layout(location = 0) out vec3 out_world;
layout(location = 1) out vec2 out_uv;

const vec2 CORNERS[6] = vec2[](vec2(-1, -1), vec2(1, 1), vec2(1, -1),
                               vec2(-1, -1), vec2(-1, 1), vec2(1, 1));

void main() {
    vec2 c = CORNERS[gl_VertexIndex];
    out_world = vec3(c.x, 0.0, c.y) * push.quad.x;
    out_uv = (c + 1.0) * 0.5;
    gl_Position = push.view_proj * vec4(out_world, 1.0);
}
