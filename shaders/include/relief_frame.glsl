// The map between a mesh's surface and a height map's texture space (docs/conventions.md): the
// interpolated tangent frame gives directions, screen derivatives give world lengths per uv unit,
// and the height slot's uv transform (KHR_texture_transform, maybe on texCoord 1) is folded in as
// one 2x2 linear map from uv0 to height uv.
#ifndef RELIEF_FRAME_GLSL
#define RELIEF_FRAME_GLSL

// d(height uv) / d(uv0), given d(uv1) / d(uv0): for relief's materials the height slot's
// KHR_texture_transform, on texCoord 0 or 1. A shader-library includer that maps uv0 to height uv
// some other way defines it before including this file; relief.glsl makes it the identity.
#ifndef RELIEF_HEIGHT_UV_MAP
#define RELIEF_HEIGHT_UV_MAP(uv1_per_uv0) \
    (slot_linear(SLOT_HEIGHT) * (slot_set(SLOT_HEIGHT) == 1 ? (uv1_per_uv0) : mat2(1.0)))
#endif

struct ReliefFrame {
    vec3 t, b, n;        // world unit vectors along +u0, +v0 and out of the surface
    vec2 scale;          // world length of one uv0 unit along t and b
    mat2 to_height;      // d(height uv) = to_height * d(uv0)
    mat2 from_height;    // its inverse (zero when singular)
    mat2 uv1_per_uv0;    // d(uv1) = uv1_per_uv0 * d(uv0)
    float depth_len;     // world length of one unit of depth, in height-uv units
};

// World lengths of one uv0 unit along u and v, from screen-space derivatives.
vec2 world_per_uv(vec3 world, vec2 uv) {
    vec3 dpx = dFdx(world), dpy = dFdy(world);
    vec2 dux = dFdx(uv), duy = dFdy(uv);
    float det = dux.x * duy.y - dux.y * duy.x;
    if (abs(det) < 1e-20) {
        return vec2(1.0);
    }
    vec3 dpdu = (dpx * duy.y - dpy * dux.y) / det;
    vec3 dpdv = (dpy * dux.x - dpx * duy.x) / det;
    return max(vec2(length(dpdu), length(dpdv)), vec2(1e-12));
}

mat2 safe_inverse(mat2 m) {
    float det = determinant(m);
    return abs(det) < 1e-20 ? mat2(0.0) : inverse(m);
}

// The frame's maps to and from height uv and its depth length, from its scale and uv1_per_uv0.
void relief_frame_height_maps(inout ReliefFrame f) {
    f.to_height = RELIEF_HEIGHT_UV_MAP(f.uv1_per_uv0);
    f.from_height = safe_inverse(f.to_height);
    // One height-uv unit spans the mean world length of the two height-uv axes.
    float area = abs(determinant(f.to_height));
    f.depth_len = sqrt(f.scale.x * f.scale.y / max(area, 1e-20));
}

ReliefFrame relief_frame(vec3 world, vec3 n, vec4 tangent, vec2 uv0, vec2 uv1) {
    ReliefFrame f;
    f.n = n;
    f.t = normalize(tangent.xyz - n * dot(n, tangent.xyz));
    f.b = cross(n, f.t) * (tangent.w < 0.0 ? -1.0 : 1.0);
    f.scale = world_per_uv(world, uv0);
    // Chain rule through the screen: J1 = D1 * inverse(D0), D = [d/dx d/dy] of each set.
    mat2 d0 = mat2(dFdx(uv0), dFdy(uv0));
    mat2 d1 = mat2(dFdx(uv1), dFdy(uv1));
    f.uv1_per_uv0 = d1 * safe_inverse(d0);
    relief_frame_height_maps(f);
    return f;
}

// A world direction in height texture space (xy per height uv, z per unit of depth, +z out of
// the surface), not normalised.
vec3 to_height_space(ReliefFrame f, vec3 w) {
    vec2 uv0 = vec2(dot(w, f.t) / f.scale.x, dot(w, f.b) / f.scale.y);
    return vec3(f.to_height * uv0, dot(w, f.n) / f.depth_len);
}

// A height-uv offset in world space along the surface.
vec3 height_offset_to_world(ReliefFrame f, vec2 d_height) {
    vec2 d0 = f.from_height * d_height;
    return f.t * (d0.x * f.scale.x) + f.b * (d0.y * f.scale.y);
}

// Smallest dir.z of a ray per unit of its xy length (about 0.06 degrees): grazing rays stay
// finite instead of producing inf offsets.
const float MIN_DIR_Z = 1e-3;

// A world direction looking into the surface (toward -n), as a height-space ray direction
// (+z down into the field), unit length.
vec3 height_space_ray_dir(ReliefFrame f, vec3 world_dir) {
    vec3 d = to_height_space(f, world_dir) * vec3(1.0, 1.0, -1.0);
    d.z = max(d.z, MIN_DIR_Z * length(d.xy));
    return normalize(d);
}

// Whether a ray that entered a clamp-addressed map inside its uv bounds (at uv_entry) has left
// them at its hit: it passes beside the object, which cuts the silhouette.
bool leaves_clamped_map(vec2 uv_entry, vec2 uv_hit) {
    bool inside = all(greaterThanEqual(uv_entry, vec2(0.0))) && all(lessThanEqual(uv_entry, vec2(1.0)));
    bool left = any(lessThan(uv_hit, vec2(0.0))) || any(greaterThan(uv_hit, vec2(1.0)));
    return inside && left;
}

// The window depth to write for a hit projected to `clip_hit`, never nearer than the polygon's
// own (`polygon`, gl_FragCoord.z): the hit lies beyond the polygon along the view ray, and
// rounding must not break the promise that lets early depth tests run: layout(depth_greater)
// for standard depth, layout(depth_less) where RELIEF_REVERSE_Z says nearer is larger.
float relief_fragment_depth(vec4 clip_hit, float polygon) {
    float d = clamp(clip_hit.z / clip_hit.w, 0.0, 1.0);
#ifdef RELIEF_REVERSE_Z
    return min(polygon, d);
#else
    return max(polygon, d);
#endif
}

// World position of the hit at (uv_hit, depth z) of a ray that entered the polygon at `entry`
// (world) and uv_entry.
vec3 relief_hit_world(ReliefFrame f, vec3 entry, vec2 uv_entry, vec2 uv_hit, float z) {
    return entry + height_offset_to_world(f, uv_hit - uv_entry) - f.n * (z * f.depth_len);
}

#endif
