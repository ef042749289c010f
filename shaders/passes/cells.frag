#version 460
// The cells pass (Apaza and Andujar): a mesh drawn through its cell complex. Each fragment of a grey
// cell's outer face marches the view ray through the complex from that face (cells_march.glsl);
// a ray that leaves without a hit is discarded, a hit writes its depth and is shaded like the
// mesh: the triangle the hit lies on gives the normal, tangent, vertex colour and uvs there, and
// the mesh's material (set 1) is read there and lit as the surface pass lights it, scene shadow
// maps included (the mesh casts into them with its own triangles).
#extension GL_GOOGLE_include_directive : require
#define PLAIN_SURFACE
#include "bindings.glsl"
#include "draw.glsl"
#include "lighting.glsl"

// The uv footprint of both coordinate sets across the pixel (see uv_footprint), which picks the
// material textures' mips.
vec2 uv_dx[2];
vec2 uv_dy[2];
#define MATERIAL_TEXTURE(slot, tex, uv)                                  \
    textureGrad(tex, uv, slot_linear(slot) * uv_dx[slot_set(slot)],      \
                slot_linear(slot) * uv_dy[slot_set(slot)])
#include "material_sample.glsl"
#include "punctual.glsl"
#include "scene_shadows.glsl"
#include "environment_light.glsl"

// The grid: `CellsUniform` in interface.glsl.
layout(set = 2, binding = BINDING_CELLS_PARAMS, std140) uniform CellsParams {
    CELLS_PARAMS_FIELDS
} cells_params;

#define CELLS_SET 2
#define CELLS_GRID cells_params
#include "cells_march.glsl"

// CornerAttributes in src/cells/attributes.rs: three per mesh triangle, in world space.
struct CellCorner {
    vec3 position;
    uint normal;
    vec2 uv0;
    vec2 uv1;
    uint tangent;
    uint colour;
    float tangent_sign;
    uint opposite;  // the triangle across the edge opposite this corner
};

// Per map texel, the mesh triangle its line meets (surface_triangles.rs).
layout(set = 2, binding = BINDING_CELLS_SURFACE_TRIANGLES, std430) readonly buffer SurfaceTriangles {
    uint surface_triangle[];
};

layout(set = 2, binding = BINDING_CELLS_CORNERS, std430) readonly buffer Corners {
    CellCorner corners[];
};

// A texel of a face whose lines all miss the surface.
const uint NO_TRIANGLE = 0xffffffffu;

layout(location = 0) in vec3 in_world;

layout(location = 0) out vec4 out_color;
// The hit lies on the ray beyond the face the fragment belongs to.
layout(depth_greater) out float gl_FragDepth;

// Octahedral unit vector from two snorm16 (encode_octahedral in attributes.rs).
vec3 decode_octahedral(uint word) {
    vec2 e = unpackSnorm2x16(word);
    vec3 v = vec3(e, 1.0 - abs(e.x) - abs(e.y));
    if (v.z < 0.0) {
        v.xy = (1.0 - abs(v.yx)) * vec2(v.x >= 0.0 ? 1.0 : -1.0, v.y >= 0.0 ? 1.0 : -1.0);
    }
    return normalize(v);
}

// A texel's uvs differ from the next pixel's by more than this across a texture seam, where
// the two belong to different charts of the texture.
const float UV_SEAM = 0.25;

// uv with whole turns taken off so that it lies within half a turn of `near`: across a seam
// where the texture wraps (a sphere's, u from 1 back to 0) the pixels' uvs differ continuously.
vec2 unwrapped(vec2 uv, vec2 near) {
    return uv - round(uv - near);
}

// The four texels around face point fp (the nearest first), whose triangles are the candidates
// for the surface at fp.
uvec4 candidate_texels(CellFacePoint fp) {
    uint r = CELLS_GRID.resolution;
    uint base = uint(fp.layer) * r * r;
    if (r < 2u) {
        return uvec4(base);
    }
    vec2 at = fp.uv * float(r) - 0.5;
    vec2 a0 = clamp(floor(at), vec2(0.0), vec2(float(r) - 2.0));
    vec2 f = at - a0;
    uvec2 a = uvec2(a0);
    uvec4 quad = uvec4(base + a.y * r + a.x, base + a.y * r + a.x + 1u, base + (a.y + 1u) * r + a.x,
                       base + (a.y + 1u) * r + a.x + 1u);
    uint nearest = (f.x < 0.5 ? 0u : 1u) + (f.y < 0.5 ? 0u : 2u);
    uint first = quad[nearest];
    quad[nearest] = quad.x;
    quad.x = first;
    return quad;
}

// Barycentric weights of p's projection onto triangle t's plane (negative outside the triangle);
// false for a degenerate triangle.
bool triangle_barycentric(uint t, vec3 p, out vec3 weights) {
    vec3 a = corners[3u * t].position;
    vec3 e0 = corners[3u * t + 1u].position - a;
    vec3 e1 = corners[3u * t + 2u].position - a;
    vec3 d = p - a;
    float d00 = dot(e0, e0);
    float d01 = dot(e0, e1);
    float d11 = dot(e1, e1);
    float area = d00 * d11 - d01 * d01;
    if (!(area > 1e-12 * d00 * d11)) {
        weights = vec3(1.0, 0.0, 0.0);
        return false;
    }
    float v = (d11 * dot(d, e0) - d01 * dot(d, e1)) / area;
    float w = (d00 * dot(d, e1) - d01 * dot(d, e0)) / area;
    weights = vec3(1.0 - v - w, v, w);
    return true;
}

// Weights clamped onto triangle t, and how far p lies from the point they give (infinite for a
// degenerate triangle).
vec3 triangle_weights(uint t, vec3 p, out float miss) {
    vec3 weights;
    if (!triangle_barycentric(t, p, weights)) {
        miss = 1e30;
        return weights;
    }
    weights = max(weights, vec3(0.0));
    weights /= weights.x + weights.y + weights.z;
    miss = distance(p, weights.x * corners[3u * t].position + weights.y * corners[3u * t + 1u].position
                           + weights.z * corners[3u * t + 2u].position);
    return weights;
}

// From triangle t toward the one p lies on, across the edge p lies beyond, a few triangles at
// most: a texel's triangle is the one its line meets at the texel's centre, and where triangles
// are smaller than texels (a fan at a pole) the hit lies on a neighbour of it.
const int WALK_STEPS = 8;

uint walk_to(uint t, vec3 p) {
    for (int step = 0; step < WALK_STEPS; ++step) {
        vec3 w;
        if (!triangle_barycentric(t, p, w)) {
            break;
        }
        float lowest = min(w.x, min(w.y, w.z));
        if (lowest >= -1e-4) {
            break;
        }
        uint k = w.x == lowest ? 0u : (w.y == lowest ? 1u : 2u);
        uint next = corners[3u * t + k].opposite;
        if (next == NO_TRIANGLE) {
            break;
        }
        t = next;
    }
    return t;
}

struct SurfaceAt {
    vec2 uv0;
    vec2 uv1;
    vec3 normal;
    // The hit triangle's own plane, facing like `normal`: the shadow maps' receiver plane.
    vec3 face;
    // The hit moved onto that triangle: the march finds the surface to within its bisection,
    // a hair off the triangles the shadow maps hold, enough to shadow a lit surface by itself.
    vec3 on_face;
    vec4 tangent;
    vec4 colour;
};

// The attributes at world point p of the surface: of the triangles the four texels around p's
// projection onto its grey cell's domain face meet, the nearest to p, walked to the one p lies
// on, its corners interpolated at p as the rasteriser interpolates them. Not a blend of the texels: a texel
// quad can straddle a crease or two sheets of the surface, and a blend there shades the hit
// with normals from parts of the mesh it is not on.
bool surface_at(vec3 p, vec3 dir, out SurfaceAt s) {
    float size = cells_params.origin_size.w;
    vec3 g = (p - cells_params.origin_size.xyz) / size;
    ivec3 last = ivec3(int(cells_params.n) - 1);
    // A hit found by bisection lies within rounding of a grey cell; it may round into a
    // neighbour, so the cells just before and after it along the ray are tried too.
    float nudge[3] = float[3](0.0, -1e-3, 1e-3);
    for (int k = 0; k < 3; ++k) {
        vec3 at = g + dir * nudge[k];
        ivec3 cell = clamp(ivec3(floor(at)), ivec3(0), last);
        uint word = cells_word(cell);
        if ((word & 3u) != 1u) {
            continue;
        }
        CellFacePoint fp = cells_face_point(grey[word >> 2], clamp(at - vec3(cell), 0.0, 1.0));
        if (fp.layer < 0) {
            continue;
        }
        uvec4 texels = candidate_texels(fp);
        uint best = NO_TRIANGLE;
        float best_miss = 1e30;
        vec3 w = vec3(1.0, 0.0, 0.0);
        for (int i = 0; i < 4; ++i) {
            uint t = surface_triangle[texels[i]];
            if (t == NO_TRIANGLE || t == best) {
                continue;
            }
            float miss;
            vec3 weights = triangle_weights(t, p, miss);
            if (miss < best_miss) {
                best = t;
                best_miss = miss;
                w = weights;
            }
        }
        if (best == NO_TRIANGLE) {
            continue;
        }
        uint walked = walk_to(best, p);
        float walked_miss;
        vec3 walked_w = triangle_weights(walked, p, walked_miss);
        if (walked_miss < best_miss) {
            best = walked;
            w = walked_w;
        }
        CellCorner c[3] = CellCorner[3](corners[3u * best], corners[3u * best + 1u],
                                        corners[3u * best + 2u]);
        s.uv0 = w.x * c[0].uv0 + w.y * c[1].uv0 + w.z * c[2].uv0;
        s.uv1 = w.x * c[0].uv1 + w.y * c[1].uv1 + w.z * c[2].uv1;
        s.normal = normalize(w.x * decode_octahedral(c[0].normal)
                             + w.y * decode_octahedral(c[1].normal)
                             + w.z * decode_octahedral(c[2].normal));
        vec3 face = cross(c[1].position - c[0].position, c[2].position - c[0].position);
        face = dot(face, face) > 0.0 ? normalize(face) : s.normal;
        s.face = dot(face, s.normal) < 0.0 ? -face : face;
        s.on_face = p - s.face * dot(p - c[0].position, s.face);
        vec3 tangent = w.x * decode_octahedral(c[0].tangent) + w.y * decode_octahedral(c[1].tangent)
                     + w.z * decode_octahedral(c[2].tangent);
        s.tangent = vec4(normalize(tangent), c[0].tangent_sign);
        s.colour = w.x * unpackUnorm4x8(c[0].colour) + w.y * unpackUnorm4x8(c[1].colour)
                 + w.z * unpackUnorm4x8(c[2].colour);
        return true;
    }
    return false;
}

// The pixel's uv footprint from ray differentials: the rays through the next pixels across and
// down (derivatives of the interpolated view direction) met with the surface's tangent plane at
// the hit, and the surface's attributes found there as at the hit. Not dFdx of the uvs themselves: those need the
// quad's helper invocations to march and find the same surface (llvmpipe's helpers read zeros
// from storage buffers), and a quad straddling a face's edge would pick the coarsest mip.
void uv_footprint(vec3 eye, vec3 ray_dx, vec3 ray_dy, vec3 world, SurfaceAt s) {
    vec3 rays[2] = vec3[2](ray_dx, ray_dy);
    for (int k = 0; k < 2; ++k) {
        vec2 d0 = vec2(0.0);
        vec2 d1 = vec2(0.0);
        float facing = dot(rays[k], s.normal);
        SurfaceAt next;
        if (abs(facing) > 1e-4) {
            float t = dot(world - eye, s.normal) / facing;
            if (t > 0.0 && surface_at(eye + t * rays[k], normalize(rays[k]), next)) {
                d0 = unwrapped(next.uv0, s.uv0) - s.uv0;
                d1 = unwrapped(next.uv1, s.uv1) - s.uv1;
            }
        }
        // Across a chart seam the next pixel's uvs belong to another part of the texture.
        d0 = any(greaterThan(abs(d0), vec2(UV_SEAM))) ? vec2(0.0) : d0;
        d1 = any(greaterThan(abs(d1), vec2(UV_SEAM))) ? vec2(0.0) : d1;
        if (k == 0) {
            uv_dx[0] = d0;
            uv_dx[1] = d1;
        } else {
            uv_dy[0] = d0;
            uv_dy[1] = d1;
        }
    }
}

void main() {
    vec3 dir = view_ray_dir(in_world);
    // The ray's origin in the camera's plane: the eye itself for a perspective camera.
    vec3 eye = in_world - dir * dot(in_world - frame.eye.xyz, dir);
    // Derivatives of an interpolated input: valid in every invocation of the quad.
    vec3 ray_dx = dir + dFdx(dir);
    vec3 ray_dy = dir + dFdy(dir);
    // From a little before the face, which the march takes as outside.
    float t_face = max(dot(in_world - eye, dir) - 1e-4 * cells_params.origin_size.w, 0.0);
    vec2 hit = cells_march(eye, dir, t_face);
    if (hit.x < 0.0) {
        discard;
    }
    vec3 world = eye + hit.x * dir;
    SurfaceAt s;
    if (!surface_at(world, dir, s)) {
        s = SurfaceAt(vec2(0.0), vec2(0.0), -dir, -dir, world, vec4(1.0, 0.0, 0.0, 1.0), vec4(1.0));
    }
    // Two more surface lookups a pixel, a fifth of the pass on an untextured sphere: only when
    // some texture's mip depends on them.
    bool textured = has_texture(SLOT_BASE_COLOR) || has_texture(SLOT_METALLIC_ROUGHNESS)
        || has_texture(SLOT_NORMAL) || has_texture(SLOT_OCCLUSION) || has_texture(SLOT_EMISSIVE);
    uv_dx = vec2[2](vec2(0.0), vec2(0.0));
    uv_dy = vec2[2](vec2(0.0), vec2(0.0));
    if (textured) {
        uv_footprint(eye, ray_dx, ray_dy, world, s);
    }
    vec4 clip = frame.view_proj * vec4(world, 1.0);
    gl_FragDepth = max(gl_FragCoord.z, clamp(clip.z / clip.w, 0.0, 1.0));

    MaterialSample m = sample_material(s.uv0, s.uv1, s.colour);
    if (material_cut(m)) {
        discard;
    }
    vec3 normal = s.normal;
    if (has_texture(SLOT_NORMAL)) {
        normal = tangent_frame_normal(normal, s.tangent, s.uv0, s.uv1);
    }
    vec3 v = -dir;
    vec3 color = ambient_light(m.base.rgb, m.roughness, m.metallic, normal, v, m.occlusion) + m.emissive;
    for (int i = 0; i < min(frame.counts.x, MAX_LIGHTS); ++i) {
        float attenuation;
        vec3 l = light_toward(i, world, attenuation);
        if (dot(normal, l) <= 0.0 || attenuation <= 0.0) {
            continue;
        }
        float lit = scene_shadow(i, s.on_face, s.face, l);
        vec3 radiance = frame.lights[i].color.rgb * (attenuation * lit);
        color += shade_ggx(m.base.rgb, m.roughness, m.metallic, normal, v, l, radiance);
    }
    out_color = vec4(color, 1.0);
}
