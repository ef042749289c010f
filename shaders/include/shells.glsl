// Prism shells: each triangle extruded down its vertices' normals into a prism as deep as the
// relief (src/shells/shell_mesh.rs builds them). A fragment lies on a face through which the
// view (or light) ray enters its prism; the ray is walked inside that prism alone, in the
// prism's coordinates (barycentric b of corners 1 and 2, depth fraction w), until it passes from
// above the relief to under it, or leaves. Every prism the ray crosses is drawn, so the depth
// test keeps the nearest hit over all of them, and a ray that leaves the shell without a hit
// writes nothing: the outline is the displaced surface's, on open meshes too. The CPU's march
// (src/shells/march.rs, f64) is the definition; this one walks each prism on its own, as a
// fragment must: a stretch of the ray runs from the face it enters by to the face it leaves by,
// both the rasterized (flat) faces, so neighbours split the ray where the draw does.
// Needs heightfield.glsl, draw.glsl, relief_frame.glsl and curved.glsl.
#ifndef SHELLS_GLSL
#define SHELLS_GLSL

// The prism as every one of its corners carries it (ShellVertex, shell.vert).
// xyz: this fragment's prism coordinates, interpolated; w: open sides (the same at every corner)
layout(location = 6) in vec4 in_prism;
layout(location = 7) flat in vec4 in_top[3];      // xyz: top corners, w: world depth
layout(location = 10) flat in vec4 in_corner_normal[3];  // w: side k's split, 1 from corner k
layout(location = 13) flat in vec4 in_corner_uv[3];  // uv0 of 0, 1 | uv0 of 2, uv1 of 0 | uv1 of 1, 2

struct ShellPrism {
    vec3 top[3];
    vec3 normal[3];
    vec3 depth;
    vec2 uv0[3];
    vec2 uv1[3];
    vec2 uv[3];  // height uv
    bool side_split[3];  // side k (corners k, k + 1): split from corner k's top
    uint open_sides;     // bit k: side k is the shell's open boundary
};

ShellPrism shell_prism() {
    ShellPrism p;
    for (int k = 0; k < 3; ++k) {
        p.top[k] = in_top[k].xyz;
        p.normal[k] = in_corner_normal[k].xyz;
    }
    p.depth = vec3(in_top[0].w, in_top[1].w, in_top[2].w);
    for (int k = 0; k < 3; ++k) {
        p.side_split[k] = in_corner_normal[k].w > 0.5;
    }
    p.open_sides = uint(in_prism.w + 0.5);
    p.uv0[0] = in_corner_uv[0].xy;
    p.uv0[1] = in_corner_uv[0].zw;
    p.uv0[2] = in_corner_uv[1].xy;
    p.uv1[0] = in_corner_uv[1].zw;
    p.uv1[1] = in_corner_uv[2].xy;
    p.uv1[2] = in_corner_uv[2].zw;
    for (int k = 0; k < 3; ++k) {
        p.uv[k] = slot_uv(SLOT_HEIGHT, p.uv0[k], p.uv1[k]);
    }
    return p;
}

vec3 prism_weights(vec2 b) {
    return vec3(1.0 - b.x - b.y, b.x, b.y);
}

vec3 prism_blend3(vec3 v[3], vec2 b) {
    vec3 k = prism_weights(b);
    return v[0] * k.x + v[1] * k.y + v[2] * k.z;
}

vec2 prism_blend2(vec2 v[3], vec2 b) {
    vec3 k = prism_weights(b);
    return v[0] * k.x + v[1] * k.y + v[2] * k.z;
}

// The world point at (b, w): down the renormalised interpolated normal by the interpolated
// depth times w, as the displaced reference moves a finely split triangle's vertices.
vec3 prism_point(ShellPrism p, vec3 c) {
    vec3 m = prism_blend3(p.normal, c.xy);
    float len = length(m);
    vec3 n = len > 0.0 ? m / len : vec3(0.0);
    return prism_blend3(p.top, c.xy) - n * (dot(prism_weights(c.xy), p.depth) * c.z);
}

// Columns: d(point)/d(b.x), d(point)/d(b.y), d(point)/dw.
mat3 prism_jacobian(ShellPrism p, vec3 c) {
    vec3 m = prism_blend3(p.normal, c.xy);
    float len = max(length(m), 1e-20);
    vec3 n = m / len;
    float depth = dot(prism_weights(c.xy), p.depth);
    mat3 j;
    for (int k = 1; k < 3; ++k) {
        vec3 dm = p.normal[k] - p.normal[0];
        vec3 dn = (dm - n * dot(n, dm)) / len;
        j[k - 1] = (p.top[k] - p.top[0]) - (n * (p.depth[k] - p.depth[0]) + dn * depth) * c.z;
    }
    j[2] = -n * depth;
    return j;
}

// Newton's method on point(c) = x from `c`, `iterations` times; where the Jacobian is singular
// or a step leaves the finite numbers, the last finite coordinates stand.
vec3 prism_newton(ShellPrism p, vec3 x, vec3 c, int iterations) {
    for (int i = 0; i < iterations; ++i) {
        mat3 j = prism_jacobian(p, c);
        if (abs(determinant(j)) < 1e-30) {
            break;
        }
        vec3 next = c - inverse(j) * (prism_point(p, c) - x);
        if (any(isnan(next)) || any(isinf(next))) {
            break;
        }
        c = next;
    }
    return c;
}

// Coordinates of a point on or in the prism, clamped into it (the rasterized faces are flat,
// the prism's own sides are ruled: a point between the two is the prism's).
vec3 prism_clamp(vec3 c) {
    vec2 b = max(c.xy, vec2(0.0));
    float s = b.x + b.y;
    b = s > 1.0 ? b / s : b;
    return vec3(b, clamp(c.z, 0.0, 1.0));
}

// Whether coordinates `c` lie under the relief: deeper than the field's 1 - h there.
bool prism_under(ShellPrism p, vec3 c) {
    return c.z >= depth_bilinear(prism_blend2(p.uv, c.xy), 1.0);
}

// Where the ray `entry + t dir` leaves the prism's rasterized faces (the triangles the draw
// rasterizes, so that each prism's stretch of a ray ends where its neighbour's begins): the
// farthest crossing, since a prism is all but convex and the ray enters it at t = 0 (the entry
// face's own crossing, at t near 0, cannot be told from others by t alone at grazing angles);
// t <= 0 where there is none. `bottom` says whether it leaves through the bottom.
float prism_exit(ShellPrism p, vec3 entry, vec3 dir, out bool bottom) {
    vec3 d[3];
    for (int k = 0; k < 3; ++k) {
        d[k] = p.top[k] - p.normal[k] * p.depth[k];
    }
    vec3 tri[24];
    tri[0] = p.top[0]; tri[1] = p.top[1]; tri[2] = p.top[2];
    tri[3] = d[0]; tri[4] = d[1]; tri[5] = d[2];
    for (int k = 0; k < 3; ++k) {
        int i = k, j = (k + 1) % 3;
        // The split the mesh chose (shell_mesh.rs): from the top of the lower-identity corner.
        bool first_low = p.side_split[k];
        int lo = first_low ? i : j, hi = first_low ? j : i;
        tri[6 + 6 * k] = p.top[lo]; tri[7 + 6 * k] = p.top[hi]; tri[8 + 6 * k] = d[hi];
        tri[9 + 6 * k] = p.top[lo]; tri[10 + 6 * k] = d[hi]; tri[11 + 6 * k] = d[lo];
    }
    float best = -1.0;
    bottom = false;
    for (int f = 0; f < 8; ++f) {
        vec3 a = tri[3 * f], b = tri[3 * f + 1], c = tri[3 * f + 2];
        vec3 e1 = b - a, e2 = c - a;
        vec3 q = cross(dir, e2);
        float det = dot(e1, q);
        if (abs(det) < 1e-30) {
            continue;
        }
        vec3 s = entry - a;
        float u = dot(s, q) / det;
        vec3 r = cross(s, e1);
        float v = dot(dir, r) / det;
        float t = dot(e2, r) / det;
        const float slack = 1e-3;
        if (u >= -slack && v >= -slack && u + v <= 1.0 + slack && t > best) {
            best = t;
            bottom = f == 1;
        }
    }
    return best;
}

// Steps per height texel the ray's height uv crosses and per full relief depth it descends (the
// CPU march's), bounds on a stretch's steps, and the halvings of the step that went under.
const float SHELL_STEPS_PER_TEXEL = 4.0;
const float SHELL_STEPS_PER_DEPTH = 32.0;
const float SHELL_MIN_STEPS = 4.0;
const float SHELL_MAX_STEPS = 512.0;
const int SHELL_BISECTIONS = 10;
const int SHELL_NEWTON_STEP = 1;
const int SHELL_NEWTON_ENTRY = 3;
const int SHELL_NEWTON_EXIT = 4;

struct ShellHit {
    vec3 coords;  // b.x, b.y, w
    float t;      // along the ray from the entry, world units
};

// The entry face from the interpolated depth fraction: 0 top (from outside the shell), 1 bottom
// (from under the relief), 2 a side (from the neighbour, in the state the field says).
int shell_entry_face(float w) {
    return w <= 1e-4 ? 0 : (w >= 1.0 - 1e-4 ? 1 : 2);
}

// Whether a ray entering through a side at coordinates `c`, under the relief, meets it there. On
// a side shared with a neighbour it does: either the neighbour saw the ray go under (its hit is
// nearer and wins the depth test), or the two reliefs part at the side and the side is the wall
// between them (the neighbour's rasterized face is flat where the shared side is ruled, and a
// pole or a uv seam gives the two prisms different heights along it). At the shell's open
// boundary the ray passes under the sheet, as under the one-sided displaced mesh.
bool shell_meets_at_side(ShellPrism p, vec3 c) {
    vec3 k = prism_weights(c.xy);
    // Side 0 lies opposite corner 2, side 1 opposite corner 0, side 2 opposite corner 1.
    int side = k.z <= min(k.x, k.y) ? 0 : (k.x <= k.y ? 1 : 2);
    return (p.open_sides & (1u << uint(side))) == 0u;
}

// Prism coordinates at t along the ray, Newton warm-started from `c`, clamped into the prism.
vec3 shell_at(ShellPrism p, vec3 x, vec3 c, int iterations) {
    return prism_clamp(prism_newton(p, x, c, iterations));
}

// The first passage of the ray `entry + t dir` (t >= 0, dir unit) from above the relief to under
// it inside prism `p`, entered through face `face` at coordinates near `guess`: walked from the
// entry to where the ray leaves the prism's faces, in steps of a quarter texel of height uv and
// a 32nd of the depth (at least 4, at most 512), the step that goes under halved 10 times; or
// the entry itself, for a ray that comes through a shared side already under the relief. A ray
// entering through the bottom meets nothing.
bool trace_shell(ShellPrism p, vec3 entry, vec3 dir, vec3 guess, int face, out ShellHit hit) {
    hit = ShellHit(vec3(0.0), 0.0);
    if (face == 1) {
        // From under the relief, through the mesh: on a closed mesh behind the relief its near
        // side shows, under an open sheet where the one-sided displaced mesh shows nothing.
        return false;
    }
    vec3 c = shell_at(p, entry, guess, SHELL_NEWTON_ENTRY);
    if (face == 0) {
        c.z = 0.0;
    }
    bool was_under = face == 2 && prism_under(p, c);
    if (was_under && shell_meets_at_side(p, c)) {
        hit = ShellHit(c, 0.0);
        return true;
    }
    bool bottom;
    float t_exit = prism_exit(p, entry, dir, bottom);
    if (t_exit <= 0.0) {
        return false;
    }
    vec3 leave = shell_at(p, entry + dir * t_exit, c, SHELL_NEWTON_EXIT);
    if (bottom) {
        leave.z = 1.0;
    }
    vec2 texels = (prism_blend2(p.uv, leave.xy) - prism_blend2(p.uv, c.xy)) * height_size();
    float steps = clamp(ceil(length(texels) * SHELL_STEPS_PER_TEXEL
                             + abs(leave.z - c.z) * SHELL_STEPS_PER_DEPTH),
                        SHELL_MIN_STEPS, SHELL_MAX_STEPS);
    float t_prev = 0.0;
    vec3 c_prev = c;
    int n = int(steps);
    for (int k = 0; k <= n; ++k) {
        float t = t_exit * float(k) / steps;
        // Each step starts from the straight line between the ends' coordinates, so no error
        // carries from one step to the next.
        vec3 ck = k == 0 ? c : (k == n ? leave
                                       : shell_at(p, entry + dir * t, mix(c, leave, float(k) / steps),
                                                  SHELL_NEWTON_STEP));
        bool now_under = prism_under(p, ck);
        if (now_under && !was_under) {
            float above = t_prev, below = t;
            vec3 c_below = ck;
            // Within one step the coordinates move along the ray all but linearly (the prism
            // bends over its whole depth, not over a quarter texel), so the halvings interpolate
            // them instead of solving again.
            vec3 c_above = c_prev;
            for (int i = 0; k > 0 && i < SHELL_BISECTIONS; ++i) {
                float mid = 0.5 * (above + below);
                vec3 cm = 0.5 * (c_above + c_below);
                if (prism_under(p, cm)) {
                    below = mid;
                    c_below = cm;
                } else {
                    above = mid;
                    c_above = cm;
                }
            }
            hit = ShellHit(c_below, below);
            return true;
        }
        was_under = now_under;
        t_prev = t;
        c_prev = ck;
    }
    return false;
}

// The hit's shading frame, from the mesh triangle the prism stands on: the interpolated normal
// at b, the tangent `tangent` turned into its plane, and the triangle's own world lengths per uv
// unit (as the surface pass's screen derivatives give them on the triangle).
ReliefFrame shell_frame(ShellPrism p, vec2 b, vec4 tangent) {
    ReliefFrame f;
    f.n = normalize(prism_blend3(p.normal, b));
    f.t = normalize(tangent.xyz - f.n * dot(f.n, tangent.xyz));
    f.b = cross(f.n, f.t) * (tangent.w < 0.0 ? -1.0 : 1.0);
    vec3 e1 = p.top[1] - p.top[0], e2 = p.top[2] - p.top[0];
    vec2 d1 = p.uv0[1] - p.uv0[0], d2 = p.uv0[2] - p.uv0[0];
    float det = d1.x * d2.y - d1.y * d2.x;
    if (abs(det) < 1e-20) {
        f.scale = vec2(1.0);
    } else {
        vec3 dpdu = (e1 * d2.y - e2 * d1.y) / det;
        vec3 dpdv = (e2 * d1.x - e1 * d2.x) / det;
        f.scale = max(vec2(length(dpdu), length(dpdv)), vec2(1e-12));
    }
    mat2 d0 = mat2(d1, d2);
    mat2 d_1 = mat2(p.uv1[1] - p.uv1[0], p.uv1[2] - p.uv1[0]);
    f.uv1_per_uv0 = d_1 * safe_inverse(d0);
    relief_frame_height_maps(f);
    return f;
}

// Normal curvatures along f.t and f.b across the prism's triangle: how the corner normals change
// along its edges (where curved relief reads them across a pixel).
vec2 shell_curvature(ShellPrism p, ReliefFrame f) {
    return curvature_along(p.top[1] - p.top[0], p.top[2] - p.top[0], p.normal[1] - p.normal[0],
                           p.normal[2] - p.normal[0], f);
}

// The triangle's own plane, on n's side (what the shadow maps hold of it).
vec3 shell_face(ShellPrism p, vec3 n) {
    vec3 face = cross(p.top[1] - p.top[0], p.top[2] - p.top[0]);
    face = dot(face, face) > 0.0 ? normalize(face) : n;
    return dot(face, n) < 0.0 ? -face : face;
}

#endif
