#version 460
// The cells pass's geometry: the faces of a complex's grey cells that border its outside, in world
// space, handed on to cells.frag, which marches the view ray through the complex from there.
#extension GL_GOOGLE_include_directive : require
#define PLAIN_SURFACE
#include "bindings.glsl"

layout(location = LOCATION_POSITION) in vec3 in_position;

layout(location = 0) out vec3 out_world;

void main() {
    out_world = in_position;
    gl_Position = frame.view_proj * vec4(in_position, 1.0);
}
