// Scene shadows (src/render/shadows): the visible fraction of a light at a point, from the
// light's shadow map in the frame's depth atlas. Every tap compares the stored depth with the
// receiver's plane extended to that tap's texel centre (receiver-plane depth), so a flat
// receiver meets its own depth exactly at every texel whatever the light's angle; only a small
// bias along the light, a fraction of a texel, remains for rounding. Filters: one nearest tap
// (hard), bilinear percentage-closer taps over a fixed footprint (PCF), or percentage-closer
// soft shadows (PCSS: the mean depth of the blockers found near the point and the light's size
// give the penumbra's width, which the filter then covers).
#ifndef SCENE_SHADOWS_GLSL
#define SCENE_SHADOWS_GLSL

layout(set = 0, binding = BINDING_SHADOW_ATLAS) uniform sampler2D shadow_atlas;

// The most capable filter any light of the frame uses, 0 without maps: a software rasteriser
// runs every compiled path under a mask, so the filters no light uses are compiled out.
layout(constant_id = SPEC_SHADOW_FILTER) const uint SHADOW_FILTER_MAX = 0u;

// Widest filter and blocker search, in texels; a cascade is used only where the point keeps
// this far (and a little more) from its edge, and cube faces are rendered this much wider.
const float MAX_FILTER_TEXELS = 8.0;
// PCF's fixed footprint, in texels.
const float PCF_RADIUS_TEXELS = 1.5;
// Bias along the light, in texels of the view's world size at the receiver: covers float
// rounding of two depths computed by different passes, well under the peter-panning scale.
const float DEPTH_BIAS_TEXELS = 0.1;

// Where world point p falls in shadow view t: xy its continuous atlas texel coordinates, z its
// depth; w <= 0 when the point lies behind a perspective view. Views are passed by value, read
// from the uniform block once per lookup: a software rasteriser pays every indexed read.
vec4 shadow_project(ShadowTile t, vec3 p) {
    vec4 c = t.view_proj * vec4(p, 1.0);
    if (c.w <= 0.0) {
        return vec4(0.0, 0.0, 0.0, -1.0);
    }
    vec3 ndc = c.xyz / c.w;
    return vec4(t.rect.xy + (ndc.xy * 0.5 + 0.5) * t.rect.z, ndc.z, 1.0);
}

// Whether projected point q lies inside view t with `margin` texels to spare.
bool shadow_view_holds(ShadowTile t, vec4 q, float margin) {
    vec2 local = q.xy - t.rect.xy;
    return q.w > 0.0 && all(greaterThanEqual(local, vec2(margin)))
        && all(lessThanEqual(local, vec2(t.rect.z - margin))) && q.z >= 0.0 && q.z <= 1.0;
}

// The view of light i's map that holds p, or -1 (no map, or p outside it: lit).
int shadow_view_of(int i, vec3 p) {
    ivec4 s = frame.light_shadows[i];
    if (s.y <= 0) {
        return -1;
    }
    int kind = int(frame.lights[i].position.w);
    int k = s.x;
    if (kind == 1) {
        // A cube: the face of the dominant axis, in the order +x, -x, +y, -y, +z, -z.
        vec3 d = p - frame.lights[i].position.xyz;
        vec3 a = abs(d);
        int face = a.x >= a.y && a.x >= a.z ? (d.x >= 0.0 ? 0 : 1)
                 : a.y >= a.z               ? (d.y >= 0.0 ? 2 : 3)
                                            : (d.z >= 0.0 ? 4 : 5);
        k += face;
    }
    if (kind != 0) {
        ShadowTile t = frame.shadow_tiles[k];
        return shadow_view_holds(t, shadow_project(t, p), 0.0) ? k : -1;
    }
    // Cascades, nearest first: the first that holds the point and its filter.
    for (int c = 0; c < s.y; ++c) {
        ShadowTile t = frame.shadow_tiles[s.x + c];
        if (shadow_view_holds(t, shadow_project(t, p), MAX_FILTER_TEXELS + 1.0)) {
            return s.x + c;
        }
    }
    return -1;
}

// A receiver in one view: where it falls, its depth (biased toward the light), how its plane's
// depth changes per texel, and the texel range its taps stay in.
struct ShadowReceiver {
    vec2 texel;
    float depth;
    vec2 slope;
    vec2 lo;
    vec2 hi;
    // World size of one texel at the receiver.
    float texel_world;
};

// Where p + v falls, given q = shadow_project(t, p). An orthographic view maps offsets linearly,
// so its offset needs a 3x3 product and no division; a perspective one projects the point anew.
vec4 shadow_project_offset(ShadowTile t, vec3 p, vec4 q, vec3 v) {
    if (t.rect.w > 0.5) {
        return shadow_project(t, p + v);
    }
    vec3 d = mat3(t.view_proj) * v;
    return vec4(q.xy + d.xy * (0.5 * t.rect.z), q.z + d.z, q.w);
}

ShadowReceiver shadow_receiver(ShadowTile t, vec3 p, vec3 n, vec3 l) {
    ShadowReceiver r;
    r.texel_world = t.rect.w > 0.5 ? t.depth.z * distance(p, t.origin.xyz) : t.depth.z;
    vec4 q = shadow_project(t, p);
    r.texel = q.xy;
    r.depth = shadow_project_offset(t, p, q, l * (DEPTH_BIAS_TEXELS * r.texel_world)).z;
    // Two directions in the receiver's plane, one texel long, and where they land in the view.
    vec3 a = normalize(cross(n, abs(n.x) < 0.9 ? vec3(1.0, 0.0, 0.0) : vec3(0.0, 1.0, 0.0)));
    vec3 b = cross(n, a);
    vec4 qa = shadow_project_offset(t, p, q, a * r.texel_world);
    vec4 qb = shadow_project_offset(t, p, q, b * r.texel_world);
    mat2 j = mat2(qa.xy - q.xy, qb.xy - q.xy);
    vec2 dz = vec2(qa.z - q.z, qb.z - q.z);
    // slope . j[c] = dz[c]: the plane's depth gradient in texels (zero when seen edge-on).
    float det = determinant(j);
    r.slope = abs(det) > 1e-6 ? vec2(dz.x * j[1].y - dz.y * j[0].y, dz.y * j[0].x - dz.x * j[1].x) / det
                              : vec2(0.0);
    r.lo = t.rect.xy + 0.5;
    r.hi = t.rect.xy + t.rect.z - 0.5;
    return r;
}

// The depth a stored texel at centre c must be nearer than to block the receiver: nearer than
// the receiver's plane there (so the plane never shadows itself) and nearer than the receiver
// itself (a blocker lies between it and the light; without this, the floor at a wall's foot,
// nearer than the wall's plane continued under it, would darken the wall's lit foot).
float receiver_depth_at(ShadowReceiver r, vec2 c) {
    return min(r.depth + dot(r.slope, c - r.texel), r.depth);
}

// The stored depth at texel centre c, kept inside the receiver's view.
float stored_depth(ShadowReceiver r, vec2 c) {
    return texelFetch(shadow_atlas, ivec2(clamp(c, r.lo, r.hi)), 0).r;
}

// 1 where the texel centred at c does not hide the receiver's plane, else 0.
float shadow_tap(ShadowReceiver r, vec2 c) {
    return stored_depth(r, c) >= receiver_depth_at(r, c) ? 1.0 : 0.0;
}

// The four stored depths whose centres surround corner `corner` (a texel corner), in
// textureGather's order: (-,+), (+,+), (+,-), (-,-) from the corner; one fetch, where four
// texelFetch calls would each pay a software rasteriser's full texel path. With the depths a
// blocker must be nearer than at those centres (receiver_depth_at).
vec4 gather_depths(ShadowReceiver r, vec2 corner, out vec4 plane) {
    corner = clamp(corner, r.lo + 0.5, r.hi - 0.5);
    vec2 atlas = vec2(textureSize(shadow_atlas, 0));
    vec2 c00 = corner - 0.5;
    float base = r.depth + dot(r.slope, c00 - r.texel);
    plane = min(base + vec4(r.slope.y, r.slope.x + r.slope.y, r.slope.x, 0.0), vec4(r.depth));
    return textureGather(shadow_atlas, corner / atlas, 0);
}

// Four taps around continuous texel position x, weighted bilinearly.
float shadow_bilinear(ShadowReceiver r, vec2 x) {
    vec2 g = x - 0.5;
    vec2 w = g - floor(g);
    vec4 plane;
    vec4 stored = gather_depths(r, floor(g) + 1.0, plane);
    vec4 lit = vec4(greaterThanEqual(stored, plane));
    // lit.w (-,-), lit.z (+,-), lit.x (-,+), lit.y (+,+).
    return mix(mix(lit.w, lit.z, w.x), mix(lit.x, lit.y, w.x), w.y);
}

// The lit share of a square of half-width `radius` texels around the receiver: bilinear taps
// on a grid fine enough that their footprints overlap.
float shadow_filter(ShadowReceiver r, float radius) {
    radius = clamp(radius, 0.5, MAX_FILTER_TEXELS);
    int n = clamp(int(ceil(radius)) + 1, 2, 4);
    float sum = 0.0;
    for (int y = 0; y < n; ++y) {
        for (int x = 0; x < n; ++x) {
            vec2 o = ((vec2(x, y) + 0.5) / float(n)) * 2.0 - 1.0;
            sum += shadow_bilinear(r, r.texel + o * radius);
        }
    }
    return sum / float(n * n);
}

// World distance from the light (perspective views) or along it (orthographic) of depth d.
float shadow_distance(ShadowTile t, float d) {
    if (t.rect.w > 0.5) {
        float near = t.depth.x;
        float far = t.depth.y;
        return near * far / max(far - d * (far - near), 1e-12);
    }
    return d * t.depth.y;
}

// Percentage-closer soft shadows for light i (size `size`: an angular radius for directional
// lights, a sphere's radius otherwise).
float shadow_pcss(ShadowTile t, ShadowReceiver r, float size) {
    bool perspective = t.rect.w > 0.5;
    float receiver = shadow_distance(t, r.depth);
    // Blockers up to the light shade the point from within this reach (capped at the filter's
    // widest): the penumbra a blocker at the map's near end would throw.
    float reach = perspective ? size * (receiver - t.depth.x) / max(t.depth.x, 1e-6)
                              : tan(size) * receiver;
    float search = clamp(reach / r.texel_world, 1.0, MAX_FILTER_TEXELS);
    float blockers = 0.0;
    float found = 0.0;
    // 2 x 2 gathers: 16 texels spread over the search square.
    for (int y = 0; y < 2; ++y) {
        for (int x = 0; x < 2; ++x) {
            vec2 corner = floor(r.texel + (vec2(x, y) - 0.5) * search) + 0.5;
            vec4 plane;
            vec4 stored = gather_depths(r, corner + 0.5, plane);
            vec4 blocking = vec4(lessThan(stored, plane));
            found += dot(blocking, vec4(1.0));
            if (perspective) {
                for (int c = 0; c < 4; ++c) {
                    blockers += blocking[c] * shadow_distance(t, stored[c]);
                }
            } else {
                // Distance is linear in an orthographic view's depth: convert the mean once.
                blockers += dot(blocking, stored);
            }
        }
    }
    if (found == 0.0) {
        return 1.0;
    }
    float blocker = perspective ? blockers / found : shadow_distance(t, blockers / found);
    float gap = max(receiver - blocker, 0.0);
    float penumbra = perspective ? size * gap / max(blocker, 1e-6) : tan(size) * gap;
    return shadow_filter(r, penumbra / r.texel_world);
}

// The visible fraction of light i at world point p, on a receiver plane of normal n, the light
// toward l, from the light's shadow map; 1 when it has none or p lies outside it.
float scene_shadow(int i, vec3 p, vec3 n, vec3 l) {
    if (SHADOW_FILTER_MAX == 0u) {
        return 1.0;
    }
    int k = shadow_view_of(i, p);
    if (k < 0) {
        return 1.0;
    }
    ShadowTile t = frame.shadow_tiles[k];
    ShadowReceiver r = shadow_receiver(t, p, n, l);
    int filter_kind = frame.light_shadows[i].z;
    if (SHADOW_FILTER_MAX == SHADOW_FILTER_HARD || filter_kind == SHADOW_FILTER_HARD) {
        return shadow_tap(r, floor(r.texel) + 0.5);
    }
    if (SHADOW_FILTER_MAX == SHADOW_FILTER_PCF || filter_kind == SHADOW_FILTER_PCF) {
        return shadow_filter(r, PCF_RADIUS_TEXELS);
    }
    return shadow_pcss(t, r, frame.lights[i].cone.z);
}

#endif
