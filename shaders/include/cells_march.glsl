// Rays through a cubic cell complex (Apaza and Andujar), in f32, over the arrays of src/cells/packed.rs:
// the march of src/cells/trace.rs, whose module docs say what white and black cells mean, how grey
// cells are sampled and where a ray stops; this file follows them step for step. Shared by the
// ray pass (cells_trace.comp) and the render pass (cells.frag).
//
// The includer defines CELLS_GRID, an expression with the fields origin_size (the grid's low corner
// and cell side), n, resolution, refinements and samples_per_texel, and may set CELLS_SET (the
// descriptor set of bindings 0-2, default 0).
#ifndef CELLS_MARCH_GLSL
#define CELLS_MARCH_GLSL

#include "interface.glsl"

#ifndef CELLS_SET
#define CELLS_SET 0
#endif

// Per grid cell (x fastest): colour in bits 0-1 (0 white, 1 grey, 2 black), grey slot above.
layout(set = CELLS_SET, binding = BINDING_CELLS_CELLS, std430) readonly buffer Cells {
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

layout(set = CELLS_SET, binding = BINDING_CELLS_GREY, std430) readonly buffer Grey {
    GreyCell grey[];
};

// 16-bit texels, two per word: distance (top 15 bits, over sqrt 3) and inside-at-face (bit 0).
layout(set = CELLS_SET, binding = BINDING_CELLS_MAPS, std430) readonly buffer Maps {
    uint maps[];
};

const uint CELL_WHITE = 0u;
const uint CELL_BLACK = 2u;
const uint CELL_PERSPECTIVE = 0u;
const uint CELL_AXIAL = 1u;
const uint CELL_PLANAR = 2u;
const float CELL_DISTANCE_RANGE = 1.7320508;
const float CELL_DISTANCE_STEPS = 32767.0;

uint cells_word(ivec3 c) {
    int n = int(CELLS_GRID.n);
    return cells[(c.z * n + c.y) * n + c.x];
}

// The projection's direction at cell-local p (not normalized), zero where it has none.
vec3 cells_projection_direction(GreyCell g, vec3 p) {
    vec3 d = vec3(0.0);
    if (g.kind == CELL_PERSPECTIVE) {
        d = p - g.param.xyz;
    } else if (g.kind == CELL_AXIAL) {
        d = p - g.param.xyz;
        d[g.axis] = 0.0;
    } else if (g.kind == CELL_PLANAR) {
        d[g.axis] = p[g.axis] >= g.param.w ? 1.0 : -1.0;
    } else {
        d[g.axis] = g.positive != 0u ? 1.0 : -1.0;
    }
    return d;
}

// The 16-bit texel `index` of the maps.
uint cells_texel(uint index) {
    return (maps[index >> 1] >> (16u * (index & 1u))) & 0xffffu;
}

float cells_texel_distance(uint index) {
    return float(cells_texel(index) >> 1) / CELL_DISTANCE_STEPS * CELL_DISTANCE_RANGE;
}

// Where cell-local p of grey cell g projects: the domain face its projection line leaves through
// (its map layer, -1 where the face carries none), the face point in the face's coordinates (0 to
// 1) and in texel coordinates clamped to the texel centres (centres at whole numbers), and how far
// along the line p lies from the face.
struct CellFacePoint {
    int layer;
    vec2 uv;
    vec2 at;
    float along;
};

CellFacePoint cells_face_point(GreyCell g, vec3 p) {
    vec3 d = cells_projection_direction(g, p);
    float len = length(d);
    if (!(len > 0.0)) {
        return CellFacePoint(-1, vec2(0.0), vec2(0.0), 0.0);
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
    uint axis = face >> 1u;
    vec3 q = p + best * d;
    vec2 uv = axis == 0u ? q.yz : (axis == 1u ? q.xz : q.xy);
    float last = float(CELLS_GRID.resolution) - 1.0;
    vec2 at = clamp(uv * float(CELLS_GRID.resolution) - 0.5, vec2(0.0), vec2(last));
    return CellFacePoint(g.layers[face], uv, at, best);
}

// The four texels around `at` in layer `layer` (index order: (a0, b0), (a1, b0), (a0, b1),
// (a1, b1)) and the bilinear weights between them.
uvec4 cells_quad(int layer, vec2 at, out vec2 f) {
    uint r = CELLS_GRID.resolution;
    uvec2 a0 = uvec2(floor(at));
    uvec2 a1 = min(a0 + 1u, uvec2(r - 1u));
    f = at - vec2(a0);
    uint base = uint(layer) * r * r;
    return uvec4(base + a0.y * r + a0.x, base + a0.y * r + a1.x, base + a1.y * r + a0.x,
                 base + a1.y * r + a1.x);
}

// Whether cell-local p of grey cell g lies past the surface along its projection line (trace.rs's
// inside_cell): the face it leaves through, the map's distance there bilinear between texel
// centres, the nearest texel's inside-at-face bit.
bool cells_inside_grey(GreyCell g, vec3 p) {
    CellFacePoint fp = cells_face_point(g, p);
    if (fp.layer < 0) {
        return false;
    }
    vec2 f;
    uvec4 q = cells_quad(fp.layer, fp.at, f);
    float top = mix(cells_texel_distance(q.x), cells_texel_distance(q.y), f.x);
    float bottom = mix(cells_texel_distance(q.z), cells_texel_distance(q.w), f.x);
    float surface = mix(top, bottom, f.y);
    uint r = CELLS_GRID.resolution;
    uvec2 near = uvec2(round(fp.at));
    bool face_inside = (cells_texel(uint(fp.layer) * r * r + near.y * r + near.x) & 1u) != 0u;
    return face_inside != (fp.along > surface);
}

bool cells_inside_cell(ivec3 cell, vec3 p) {
    uint word = cells_word(cell);
    uint colour = word & 3u;
    if (colour == CELL_WHITE) {
        return false;
    }
    if (colour == CELL_BLACK) {
        return true;
    }
    float size = CELLS_GRID.origin_size.w;
    vec3 local = clamp((p - CELLS_GRID.origin_size.xyz) / size - vec3(cell), vec3(0.0), vec3(1.0));
    return cells_inside_grey(grey[word >> 2], local);
}

bool cells_inside(vec3 p) {
    float size = CELLS_GRID.origin_size.w;
    vec3 g = (p - CELLS_GRID.origin_size.xyz) / size;
    ivec3 cell = ivec3(floor(g));
    int n = int(CELLS_GRID.n);
    for (int k = 0; k < 3; ++k) {
        // A point on the grid's far side belongs to the last cell.
        if (cell[k] == n && g[k] <= float(n)) {
            cell[k] = n - 1;
        }
        if (cell[k] < 0 || cell[k] >= n) {
            return false;
        }
    }
    return cells_inside_cell(cell, p);
}

float cells_bisect(vec3 origin, vec3 dir, float t_out, float t_in) {
    for (uint i = 0u; i < CELLS_GRID.refinements; ++i) {
        float mid = 0.5 * (t_out + t_in);
        if (cells_inside(origin + mid * dir)) {
            t_in = mid;
        } else {
            t_out = mid;
        }
    }
    return 0.5 * (t_out + t_in);
}

// trace.rs's march from t_start on (the point there counts as outside): the cells along the ray,
// white ones crossed at once, grey ones sampled, the first inside sample (or a black cell's
// entry) refined against the last outside point. Returns the hit's t (-1: none) and the samples.
vec2 cells_march(vec3 origin, vec3 dir, float t_start) {
    float size = CELLS_GRID.origin_size.w;
    vec3 lo = CELLS_GRID.origin_size.xyz;
    int n = int(CELLS_GRID.n);
    vec3 hi = lo + size * float(n);
    float t_enter = t_start;
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
    float step_t = size / (float(CELLS_GRID.resolution) * CELLS_GRID.samples_per_texel) / length(dir);
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
        uint colour = cells_word(cell) & 3u;
        if (colour == CELL_WHITE) {
            outside_t = left;
        } else if (colour == CELL_BLACK) {
            return vec2(cells_bisect(origin, dir, outside_t, entered), samples);
        } else {
            uint count = uint(max(ceil((left - entered) / step_t), 1.0));
            for (uint i = 1u; i <= count; ++i) {
                float t = entered + (left - entered) * float(i) / float(count);
                samples += 1.0;
                if (cells_inside_cell(cell, origin + t * dir)) {
                    return vec2(cells_bisect(origin, dir, outside_t, t), samples);
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

#endif
