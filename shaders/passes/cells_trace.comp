#version 460
// Rays through a cubic cell complex (paper 002) on the GPU: the march of src/cells/trace.rs, in f32,
// over the arrays of src/cells/packed.rs. One invocation per ray; each writes the hit's t (-1 for a
// miss) and the samples it took. The module docs of trace.rs say what white and black cells mean,
// how grey cells are sampled and where a ray stops; this file follows them step for step.
layout(local_size_x = 64) in;

// Per grid cell (x fastest): colour in bits 0-1 (0 white, 1 grey, 2 black), grey slot above.
layout(set = 0, binding = 0, std430) readonly buffer Cells {
    uint cells[];
};

// GreyRecord in packed.rs.
struct GreyCell {
    vec4 param;
    uint kind;
    uint axis;
    uint positive;
    uint pad;
    int layers[6];
    int pad2[2];
};

layout(set = 0, binding = 1, std430) readonly buffer Grey {
    GreyCell grey[];
};

// 16-bit texels, two per word: distance (top 15 bits, over sqrt 3) and inside-at-face (bit 0).
layout(set = 0, binding = 2, std430) readonly buffer Maps {
    uint maps[];
};

struct Ray {
    vec4 origin;
    vec4 dir;
};

layout(set = 0, binding = 3, std430) readonly buffer Rays {
    Ray rays[];
};

// Per ray: t (-1: no hit) and samples.
layout(set = 0, binding = 4, std430) writeonly buffer Hits {
    vec2 hits[];
};

layout(push_constant, std430) uniform Params {
    // The grid's low corner and its cell side.
    vec4 origin_size;
    uint n;
    uint resolution;
    uint ray_count;
    uint refinements;
    float samples_per_texel;
} params;

const uint WHITE = 0u;
const uint BLACK = 2u;
const uint PERSPECTIVE = 0u;
const uint AXIAL = 1u;
const uint PLANAR = 2u;
const float DISTANCE_RANGE = 1.7320508;
const float DISTANCE_STEPS = 32767.0;

uint cell_word(ivec3 c) {
    int n = int(params.n);
    return cells[(c.z * n + c.y) * n + c.x];
}

// The projection's direction at cell-local p (not normalized), zero where it has none.
vec3 projection_direction(GreyCell g, vec3 p) {
    vec3 d = vec3(0.0);
    if (g.kind == PERSPECTIVE) {
        d = p - g.param.xyz;
    } else if (g.kind == AXIAL) {
        d = p - g.param.xyz;
        d[g.axis] = 0.0;
    } else if (g.kind == PLANAR) {
        d[g.axis] = p[g.axis] >= g.param.w ? 1.0 : -1.0;
    } else {
        d[g.axis] = g.positive != 0u ? 1.0 : -1.0;
    }
    return d;
}

// The 16-bit texel `index` of the maps.
uint texel(uint index) {
    return (maps[index >> 1] >> (16u * (index & 1u))) & 0xffffu;
}

float texel_distance(uint index) {
    return float(texel(index) >> 1) / DISTANCE_STEPS * DISTANCE_RANGE;
}

// Whether cell-local p of grey cell g lies past the surface along its projection line (trace.rs's
// inside_cell): the face it leaves through, the map's distance there bilinear between texel
// centres, the nearest texel's inside-at-face bit.
bool inside_grey(GreyCell g, vec3 p) {
    vec3 d = projection_direction(g, p);
    float len = length(d);
    if (!(len > 0.0)) {
        return false;
    }
    d /= len;
    float best = 1.0e30;
    uint face = 0u;
    for (uint k = 0u; k < 3u; ++k) {
        if (d[k] == 0.0) {
            continue;
        }
        bool positive = d[k] > 0.0;
        float t = max(((positive ? 1.0 : 0.0) - p[k]) / d[k], 0.0);
        if (t < best) {
            best = t;
            face = 2u * k + (positive ? 1u : 0u);
        }
    }
    int layer = g.layers[face];
    if (layer < 0) {
        return false;
    }
    uint axis = face >> 1u;
    vec3 q = p + best * d;
    vec2 uv = axis == 0u ? q.yz : (axis == 1u ? q.xz : q.xy);
    float r = float(params.resolution);
    float last = r - 1.0;
    vec2 at = clamp(uv * r - 0.5, vec2(0.0), vec2(last));
    uvec2 a0 = uvec2(floor(at));
    uvec2 a1 = min(a0 + 1u, uvec2(params.resolution - 1u));
    vec2 f = at - vec2(a0);
    uint base = uint(layer) * params.resolution * params.resolution;
    uint row0 = base + a0.y * params.resolution;
    uint row1 = base + a1.y * params.resolution;
    float top = mix(texel_distance(row0 + a0.x), texel_distance(row0 + a1.x), f.x);
    float bottom = mix(texel_distance(row1 + a0.x), texel_distance(row1 + a1.x), f.x);
    float surface = mix(top, bottom, f.y);
    uvec2 near = uvec2(round(at));
    bool face_inside = (texel(base + near.y * params.resolution + near.x) & 1u) != 0u;
    return face_inside != (best > surface);
}

bool inside_cell(ivec3 cell, vec3 p) {
    uint word = cell_word(cell);
    uint colour = word & 3u;
    if (colour == WHITE) {
        return false;
    }
    if (colour == BLACK) {
        return true;
    }
    float size = params.origin_size.w;
    vec3 local = clamp((p - params.origin_size.xyz) / size - vec3(cell), vec3(0.0), vec3(1.0));
    return inside_grey(grey[word >> 2], local);
}

bool inside(vec3 p) {
    float size = params.origin_size.w;
    vec3 g = (p - params.origin_size.xyz) / size;
    ivec3 cell = ivec3(floor(g));
    int n = int(params.n);
    for (int k = 0; k < 3; ++k) {
        // A point on the grid's far side belongs to the last cell.
        if (cell[k] == n && g[k] <= float(n)) {
            cell[k] = n - 1;
        }
        if (cell[k] < 0 || cell[k] >= n) {
            return false;
        }
    }
    return inside_cell(cell, p);
}

float bisect(vec3 origin, vec3 dir, float t_out, float t_in) {
    for (uint i = 0u; i < params.refinements; ++i) {
        float mid = 0.5 * (t_out + t_in);
        if (inside(origin + mid * dir)) {
            t_in = mid;
        } else {
            t_out = mid;
        }
    }
    return 0.5 * (t_out + t_in);
}

// trace.rs's march: the cells along the ray, white ones crossed at once, grey ones sampled, the
// first inside sample (or a black cell's entry) refined against the last outside point.
vec2 march(vec3 origin, vec3 dir) {
    float size = params.origin_size.w;
    vec3 lo = params.origin_size.xyz;
    int n = int(params.n);
    vec3 hi = lo + size * float(n);
    float t_enter = 0.0;
    float t_leave = 1.0e30;
    for (int k = 0; k < 3; ++k) {
        if (dir[k] == 0.0) {
            if (origin[k] < lo[k] || origin[k] > hi[k]) {
                return vec2(-1.0, 0.0);
            }
            continue;
        }
        float a = (lo[k] - origin[k]) / dir[k];
        float b = (hi[k] - origin[k]) / dir[k];
        t_enter = max(t_enter, min(a, b));
        t_leave = min(t_leave, max(a, b));
    }
    if (!(t_enter <= t_leave)) {
        return vec2(-1.0, 0.0);
    }
    float step_t = size / (float(params.resolution) * params.samples_per_texel) / length(dir);
    vec3 start = origin + t_enter * dir;
    ivec3 cell = clamp(ivec3(floor((start - lo) / size)), ivec3(0), ivec3(n - 1));
    ivec3 step = ivec3(sign(dir));
    vec3 next = vec3(1.0e30);
    vec3 delta = vec3(1.0e30);
    for (int k = 0; k < 3; ++k) {
        if (dir[k] != 0.0) {
            float boundary = lo[k] + size * float(cell[k] + (dir[k] > 0.0 ? 1 : 0));
            next[k] = (boundary - origin[k]) / dir[k];
            delta[k] = size / abs(dir[k]);
        }
    }
    float outside_t = t_enter;
    float entered = t_enter;
    float samples = 0.0;
    // At most every cell once: the walk visits at most 3n cells.
    for (int walk = 0; walk < 3 * n + 3; ++walk) {
        int axis = next.x <= next.y ? (next.x <= next.z ? 0 : 2) : (next.y <= next.z ? 1 : 2);
        float left = min(next[axis], t_leave);
        uint colour = cell_word(cell) & 3u;
        if (colour == WHITE) {
            outside_t = left;
        } else if (colour == BLACK) {
            return vec2(bisect(origin, dir, outside_t, entered), samples);
        } else {
            uint count = uint(max(ceil((left - entered) / step_t), 1.0));
            for (uint i = 1u; i <= count; ++i) {
                float t = entered + (left - entered) * float(i) / float(count);
                samples += 1.0;
                if (inside_cell(cell, origin + t * dir)) {
                    return vec2(bisect(origin, dir, outside_t, t), samples);
                }
                outside_t = t;
            }
        }
        if (left >= t_leave) {
            break;
        }
        entered = left;
        cell[axis] += step[axis];
        if (cell[axis] < 0 || cell[axis] >= n) {
            break;
        }
        next[axis] += delta[axis];
    }
    return vec2(-1.0, samples);
}

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= params.ray_count) {
        return;
    }
    hits[i] = march(rays[i].origin.xyz, rays[i].dir.xyz);
}
