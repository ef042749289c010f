#version 460
#extension GL_GOOGLE_include_directive : require
// The environment seen behind the scene: each pixel's view direction, from the inverse of the
// camera's view-projection, looked up in the environment image.

#include "equirect.glsl"
#include "interface.glsl"

layout(set = 0, binding = 0) uniform sampler2D environment;

layout(push_constant, std430) uniform BackgroundPush {
    BACKGROUND_PUSH_FIELDS
} bg;

layout(location = 0) in vec2 ndc;
layout(location = 0) out vec4 out_color;

void main() {
    vec4 near = bg.inverse_view_proj * vec4(ndc, 0.0, 1.0);
    vec4 far = bg.inverse_view_proj * vec4(ndc, 1.0, 1.0);
    vec3 dir = far.xyz / far.w - near.xyz / near.w;
    out_color = vec4(textureLod(environment, equirect_uv(dir), 0.0).rgb, 1.0);
}
