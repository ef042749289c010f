#version 460
// One triangle covering the viewport; uv runs over [0,1]^2 across the visible part.
layout(location = 0) out vec2 out_uv;

void main() {
    vec2 corner = vec2(float((gl_VertexIndex << 1) & 2), float(gl_VertexIndex & 2));
    out_uv = corner;
    gl_Position = vec4(corner * 2.0 - 1.0, 0.0, 1.0);
}
