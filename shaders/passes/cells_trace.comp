#version 460
// Rays through a cubic cell complex (Apaza and Andujar) on the GPU: one invocation per ray marches it
// (cells_march.glsl) and writes the hit's t (-1 for a miss) and the samples it took.
#extension GL_GOOGLE_include_directive : require
#include "interface.glsl"
layout(local_size_x = 64) in;

// The grid and the batch: `CellsTraceParams` in interface.glsl.
layout(push_constant, std430) uniform CellsTraceParams {
    CELLS_TRACE_PARAMS_FIELDS
} params;

#define CELLS_GRID params
#include "cells_march.glsl"

struct Ray {
    vec4 origin;
    vec4 dir;
};

layout(set = 0, binding = BINDING_CELLS_RAYS, std430) readonly buffer Rays {
    Ray rays[];
};

// Per ray: t (-1: no hit) and samples.
layout(set = 0, binding = BINDING_CELLS_HITS, std430) writeonly buffer Hits {
    vec2 hits[];
};

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.ray_count) {
        return;
    }
    hits[i] = cells_march(rays[i].origin.xyz, rays[i].dir.xyz, 0.0);
}
