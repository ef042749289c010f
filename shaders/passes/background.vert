#version 460
// The background's geometry: one triangle covering the frame at the far plane (depth 1), drawn
// after the opaque surfaces: the less-or-equal depth test passes only where none was drawn.

layout(location = 0) out vec2 ndc;

void main() {
    vec2 corner = vec2((gl_VertexIndex << 1) & 2, gl_VertexIndex & 2);
    ndc = corner * 2.0 - 1.0;
    gl_Position = vec4(ndc, 1.0, 1.0);
}
