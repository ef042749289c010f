#version 460
// The cells pass (Apaza and Andujar): a mesh drawn through its cell complex. Each fragment of a grey
// cell's outer face marches the view ray through the complex from that face (cells_march.glsl);
// a ray that leaves without a hit is discarded, a hit writes its depth and is shaded like the
// mesh: the attribute maps give the normal, tangent, vertex colour and uvs at the hit, and the
// mesh's material (set 1) is read there and lit as the surface pass lights it.
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

// Mirrors `CellsUniform` in src/render/cells/cells_pass.rs.
layout(set = 2, binding = BINDING_CELLS_PARAMS, std140) uniform CellsParams {
    vec4 origin_size;
    uint n;
    uint resolution;
    uint refinements;
    float samples_per_texel;
} cells_params;

#define CELLS_SET 2
#define CELLS_GRID cells_params
#include "cells_march.glsl"

// AttributeTexel in src/cells/attributes.rs.
struct CellAttributes {
    vec2 uv0;
    vec2 uv1;
    uint normal;
    uint tangent;
    uint colour;
    float tangent_sign;
};

layout(set = 2, binding = BINDING_CELLS_ATTRIBUTES, std430) readonly buffer Attributes {
    CellAttributes attributes[];
};

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

// A texel's uvs differ from its quad's nearest by more than this across a texture seam, where
// blending them would read the texture between the charts.
const float UV_SEAM = 0.25;

// uv with whole turns taken off so that it lies within half a turn of `near`: across a seam
// where the texture wraps (a sphere's, u from 1 back to 0) the texels' uvs blend continuously.
vec2 unwrapped(vec2 uv, vec2 near) {
    return uv - round(uv - near);
}

// The four texels whose attributes blend at face point fp, as cells_quad, but within half a texel
// of the face's edge the weights extrapolate from the edge texels instead of clamping to them: the
// neighbouring face's map continues the surface there, and a clamped band would make the uvs jump
// at every cell and face boundary (the jump picks a coarser mip along those lines).
uvec4 attribute_quad(CellFacePoint fp, out vec2 f) {
    uint r = CELLS_GRID.resolution;
    if (r < 2u) {
        f = vec2(0.0);
        uint only = uint(fp.layer);
        return uvec4(only);
    }
    vec2 at = fp.uv * float(r) - 0.5;
    vec2 a0 = clamp(floor(at), vec2(0.0), vec2(float(r) - 2.0));
    f = at - a0;
    uvec2 a = uvec2(a0);
    uint base = uint(fp.layer) * r * r;
    return uvec4(base + a.y * r + a.x, base + a.y * r + a.x + 1u, base + (a.y + 1u) * r + a.x,
                 base + (a.y + 1u) * r + a.x + 1u);
}

struct SurfaceAt {
    vec2 uv0;
    vec2 uv1;
    vec3 normal;
    vec4 tangent;
    vec4 colour;
};

// The attributes at world point p of the surface: bilinear over the four texels around the
// point's projection onto its grey cell's domain face.
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
        vec2 f;
        uvec4 q = attribute_quad(fp, f);
        vec4 w = vec4((1.0 - f.x) * (1.0 - f.y), f.x * (1.0 - f.y), (1.0 - f.x) * f.y, f.x * f.y);
        CellAttributes a[4] = CellAttributes[4](attributes[q.x], attributes[q.y],
                                                attributes[q.z], attributes[q.w]);
        int nearest = (f.x < 0.5 ? 0 : 1) + (f.y < 0.5 ? 0 : 2);
        s.uv0 = vec2(0.0);
        s.uv1 = vec2(0.0);
        s.normal = vec3(0.0);
        vec3 tangent = vec3(0.0);
        s.colour = vec4(0.0);
        bool seam = false;
        for (int i = 0; i < 4; ++i) {
            vec2 uv0 = unwrapped(a[i].uv0, a[nearest].uv0);
            vec2 uv1 = unwrapped(a[i].uv1, a[nearest].uv1);
            seam = seam || any(greaterThan(abs(uv0 - a[nearest].uv0), vec2(UV_SEAM)))
                        || any(greaterThan(abs(uv1 - a[nearest].uv1), vec2(UV_SEAM)));
            s.uv0 += w[i] * uv0;
            s.uv1 += w[i] * uv1;
            s.normal += w[i] * decode_octahedral(a[i].normal);
            tangent += w[i] * decode_octahedral(a[i].tangent);
            s.colour += w[i] * unpackUnorm4x8(a[i].colour);
        }
        if (seam) {
            s.uv0 = a[nearest].uv0;
            s.uv1 = a[nearest].uv1;
        }
        s.normal = normalize(s.normal);
        s.tangent = vec4(normalize(tangent), a[nearest].tangent_sign);
        return true;
    }
    return false;
}

// The pixel's uv footprint from ray differentials: the rays through the next pixels across and
// down (derivatives of the interpolated view direction) met with the surface's tangent plane at
// the hit, and the attribute maps read there. Not dFdx of the uvs themselves: those need the
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
    vec3 eye = frame.eye.xyz;
    vec3 dir = normalize(in_world - eye);
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
        s = SurfaceAt(vec2(0.0), vec2(0.0), -dir, vec4(1.0, 0.0, 0.0, 1.0), vec4(1.0));
    }
    uv_footprint(eye, ray_dx, ray_dy, world, s);
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
    vec3 color = frame.ambient.rgb * m.base.rgb * m.occlusion + m.emissive;
    for (int i = 0; i < min(frame.counts.x, MAX_LIGHTS); ++i) {
        float attenuation;
        vec3 l = light_toward(i, world, attenuation);
        if (dot(normal, l) <= 0.0 || attenuation <= 0.0) {
            continue;
        }
        vec3 radiance = frame.lights[i].color.rgb * attenuation;
        color += shade_ggx(m.base.rgb, m.roughness, m.metallic, normal, v, l, radiance);
    }
    out_color = vec4(color, 1.0);
}
