#version 460
// The surface pass: glTF metallic-roughness shading of a mesh, displaced per pixel. Relief
// variants (build.rs maps "method.glsl" to shaders/methods/<id>.glsl) build the view ray in the
// height map's texture space, trace it, move every texture lookup to the hit, shade with the
// height field's normal (or the normal map) and write the displaced point's depth; with a
// SHADOW_MODE (shadows.glsl) they also shadow each shadow-casting light by the height field;
// TERRAIN_LAYERS variants shade a layered material (terrain_layers.glsl); CURVED variants trace
// under the mesh's curvature (curved.glsl), SHELLS variants walk the prism this fragment's face
// bounds (shells.glsl, drawn from shell.vert). The plain variant
// (PLAIN_SURFACE) does none of that; relief variants first skip fragments the occluder pass
// shows hidden (occluders.glsl), and declare depth_greater, so a driver may keep early depth
// tests despite their depth writes. Every variant reads the scene's shadow maps
// (scene_shadows.glsl); with the frame's shadow probe on it writes one light's visibility
// terms instead of a colour.
#extension GL_GOOGLE_include_directive : require
#include "conventions.glsl"
#include "numeric.glsl"
#include "bindings.glsl"
#include "draw.glsl"
#include "lighting.glsl"
#include "material_sample.glsl"
#include "punctual.glsl"
#include "scene_shadows.glsl"
#include "environment_light.glsl"
#include "direct_light.glsl"
#include "octahedral.glsl"
#ifndef PLAIN_SURFACE
#include "heightfield.glsl"
#include "relief_frame.glsl"
#ifdef RELIEF_LOD
#include "lod.glsl"
#endif
#include "method.glsl"
#include "shadows.glsl"
#include "occluders.glsl"
#ifdef TERRAIN_LAYERS
#include "terrain_layers.glsl"
#endif
#ifdef CURVED
#include "curved.glsl"
#endif
#ifdef SHELLS
#include "curved.glsl"
#include "shells.glsl"
#endif
#endif

layout(location = 0) in vec3 in_world;
layout(location = 1) in vec3 in_normal;
layout(location = 2) in vec2 in_uv0;
layout(location = 3) in vec2 in_uv1;
layout(location = 4) in vec4 in_tangent;
layout(location = 5) in vec4 in_color;

layout(location = 0) out vec4 out_color;
// The G-buffer (src/render/frame/gbuffer.rs): written always, kept only where the frame has the
// attachments (a write without one is dropped).
layout(location = 1) out vec4 out_gbuffer_normal;
layout(location = 2) out uvec4 out_gbuffer_surface;
layout(location = 3) out vec4 out_gbuffer_material;
layout(location = 4) out vec4 out_gbuffer_motion;
// The deferred frame's shading inputs (src/render/lighting/): what the lighting pass needs
// beyond the G-buffer, written only by deferred variants.
layout(location = 5) out vec4 out_shading_point;
layout(location = 6) out uvec4 out_shading_frame;
layout(location = 7) out vec4 out_shading_self_shadow;
// 1: the fragment writes its shading inputs and its emission, and the lighting pass
// (lighting.comp) lights it once the scene is drawn; 0: it is lit here.
layout(constant_id = SPEC_DEFERRED) const uint DEFERRED = 0u;
#ifndef PLAIN_SURFACE
// The written depth is only ever behind the polygon's (see main), so the rasterizer may still
// reject fragments early against the polygon's depth.
layout(depth_greater) out float gl_FragDepth;
// Whether the displaced hit's depth is written (`Relief::write_depth`), else the polygon's.
layout(constant_id = SPEC_WRITE_DEPTH) const uint WRITE_DEPTH = 1u;
#endif

// Traces and shades the fragment (main decides whether it is worth it).
void shade() {
    vec3 n = normalize(gl_FrontFacing ? in_normal : -in_normal);
    // The triangle's own plane, on n's side: the shadow maps hold the triangles' depths, so a
    // receiver's plane must be the triangle's, not the one the smooth shading normal spans
    // (on a curved mesh the two part by the mesh's curvature across a triangle).
    vec3 face = cross(dFdx(in_world), dFdy(in_world));
    face = dot(face, face) > 0.0 ? normalize(face) : n;
    face = dot(face, n) < 0.0 ? -face : face;
    vec2 uv0 = in_uv0;
    vec2 uv1 = in_uv1;
    vec3 world = in_world;
    vec3 view = view_ray_dir(in_world);
    vec3 normal = n;
    bool relief_normal = false;
    uint traced_steps = 0u;

#ifndef PLAIN_SURFACE
    float depth_scale = material.relief.x;
#ifdef SHELLS
    // Prism shells: the ray walked through the prism this face bounds; where it leaves without
    // meeting the relief, a nearer or farther prism answers for the pixel, or none does.
    ShellPrism prism = shell_prism();
    ShellHit shell_hit;
    if (!trace_shell(prism, in_world, view, in_prism.xyz, shell_entry_face(in_prism.z), shell_hit)) {
        discard;
    }
    ReliefFrame f = shell_frame(prism, shell_hit.coords.xy, in_tangent);
    vec2 curvature = shell_curvature(prism, f);
    n = f.n;
    face = shell_face(prism, n);
    float z = shell_hit.coords.z * depth_scale;
    vec2 uv_hit = prism_blend2(prism.uv, shell_hit.coords.xy);
    uv0 = prism_blend2(prism.uv0, shell_hit.coords.xy);
    uv1 = prism_blend2(prism.uv1, shell_hit.coords.xy);
    world = in_world + view * shell_hit.t;
#else
    ReliefFrame f = relief_frame(in_world, n, in_tangent, in_uv0, in_uv1);
    vec2 uv_h = slot_uv(SLOT_HEIGHT, in_uv0, in_uv1);
    Ray ray = Ray(uv_h, height_space_ray_dir(f, view), depth_scale);
#ifdef RELIEF_LOD
    // Level of detail (lod.glsl): past the fade's end nothing is traced (normal mapping at the
    // entry point); inside it the hit slides back along the ray to the entry.
    lod_begin(uv_h, distance(in_world, frame.eye.xyz));
    Hit hit = Hit(0.0, 0u, false);
    if (lod_fade < 1.0) {
        hit = METHOD_TRACE(ray, lod_budget(ray_budget(ray), ray));
    }
    hit.z *= 1.0 - lod_fade;
#elif defined(CURVED)
    vec2 curvature = surface_curvature(in_world, n, f);
    Hit hit = trace_curved(ray, ray_budget(ray), f, curvature);
    if (hit.z < 0.0) {
        // The ray left the curved shell without meeting the surface: outside the silhouette.
        discard;
    }
#else
    Hit hit = METHOD_TRACE(ray, ray_budget(ray));
#endif
    traced_steps = hit.steps;
    count_traced_steps(traced_steps);
#ifdef CURVED
    // Below the tangent plane the curved shell reaches deeper than depth_scale.
    float z = max(hit.z, 0.0);
#else
    float z = clamp(hit.z, 0.0, depth_scale);
#endif
    vec2 uv_hit = ray_uv(ray, z);
    // A clamp-addressed height map ends at its uv bounds.
    if (frame.height_info.w < 0.5 && leaves_clamped_map(uv_h, uv_hit)) {
        discard;
    }
    vec2 d0 = f.from_height * (uv_hit - uv_h);
    uv0 += d0;
    uv1 += f.uv1_per_uv0 * d0;
    world = relief_hit_world(f, in_world, uv_h, uv_hit, z);
#endif
    // The surface stands depth_scale * h above the bottom plane; its slope per uv0 unit is the
    // height gradient carried back through the uv map.
    vec2 g0 = transpose(f.to_height) * (depth_scale * height_gradient(uv_hit));
    vec3 base_normal = n;
#ifdef CURVED
    // The curved top's normal at the hit: turned by the curvature over the distance travelled.
    vec3 along = height_offset_to_world(f, uv_hit - uv_h);
    base_normal = normalize(n + f.t * (curvature.x * dot(along, f.t))
                              + f.b * (curvature.y * dot(along, f.b)));
#endif
    normal = normalize(base_normal - f.t * (f.depth_len * g0.x / f.scale.x)
                                   - f.b * (f.depth_len * g0.y / f.scale.y));
    relief_normal = true;
    vec4 clip = frame.view_proj * vec4(world, 1.0);
    // Never nearer than the polygon (relief_fragment_depth); a material that keeps its
    // polygon's depth writes that instead.
    gl_FragDepth = WRITE_DEPTH != 0u ? relief_fragment_depth(clip, gl_FragCoord.z) : gl_FragCoord.z;
#endif

#ifdef TERRAIN_LAYERS
    MaterialSample m = sample_material(uv0, uv1, layer_vertex_tint(in_color));
#else
    MaterialSample m = sample_material(uv0, uv1, in_color);
#endif
    if (material_cut(m)) {
        discard;
    }
    if (has_texture(SLOT_NORMAL)) {
        // The normal map is the surface's finer detail; without one, the height field's own.
        normal = tangent_frame_normal(relief_normal ? normal : n, in_tangent, uv0, uv1);
    }
#ifdef TERRAIN_LAYERS
    // A layered material: its layers' look, mixed at the hit by the blend's shading weights.
    LayerMix layers = mix_layers(uv_hit, normal, f.t, f.b, n);
    m.base.rgb *= layers.albedo;
    m.roughness *= layers.roughness;
    normal = layers.normal;
#endif
    float occlusion = m.occlusion;
#ifndef PLAIN_SURFACE
    if (has_texture(SLOT_RELIEF_AO)) {
        // The field's own occlusion at the hit; the glTF occlusion texture multiplies it.
        occlusion *= texture(tex_relief_ao, uv_hit).r;
    }
#endif
    vec4 base = m.base;
    vec3 emissive = m.emissive;
    float roughness = m.roughness;
    float metallic = m.metallic;

    vec3 v = -view;
    // The light from above the polygon is answered by the maps from where the ray toward it
    // leaves the relief's top plane: the hit's depth below that plane, in world units.
#ifndef PLAIN_SURFACE
    float lift = z * f.depth_len;
#else
    float lift = 0.0;
#endif
    vec4 self_shadow = vec4(1.0);
    DirectSum direct = DirectSum(vec3(0.0), 0.0, 0.0);
    vec3 color = emissive;
    vec4 probe = vec4(0.0, 0.0, 0.0, 1.0);
    if (DEFERRED == 0u) {
        color += ambient_light(base.rgb, roughness, metallic, normal, v, occlusion);
    }
    for (int i = 0; i < min(frame.counts.x, MAX_LIGHTS); ++i) {
        float attenuation;
        vec3 l = light_toward(i, world, attenuation);
        bool facing = dot(normal, l) > 0.0 && attenuation > 0.0;
        bool probed = frame.counts.y == i + 1;
        if (DEFERRED != 0u && i >= DEFERRED_SELF_SHADOW_LIGHTS) {
            break;
        }
        if (!facing && !probed) {
            continue;
        }
        float lit_self = 1.0;
#ifndef PLAIN_SURFACE
        if (SHADOW_MODE != SHADOW_MODE_NONE && frame.lights[i].color.w > 0.5) {
            float radius = light_angular_radius(i, world);
#ifdef CURVED
            // The light's path hangs from the curved top too, so a shadow ray leaves the shell
            // where the silhouette does.
            vec3 l_height = to_height_space(f, l);
            vec2 bend = curved_bend(f, curvature, uv_hit - uv_h, l_height.xy);
            lit_self = facing ? light_visible_bent(uv_hit, z, l_height, radius, depth_scale, bend)
                              : 0.0;
#elif defined(SHELLS)
            // The shell follows the mesh's curvature: the light's path hangs from a curved top
            // through the hit, as curved relief's does, so the shadow falls where the prisms'.
            vec3 l_height = to_height_space(f, l);
            vec2 bend = curved_bend(f, curvature, vec2(0.0), l_height.xy);
            lit_self = facing ? light_visible_bent(uv_hit, z, l_height, radius, depth_scale, bend)
                              : 0.0;
#else
            lit_self = facing ? light_visible(uv_hit, z, to_height_space(f, l), radius, depth_scale)
                              : 0.0;
#endif
        }
#endif
        if (DEFERRED != 0u) {
            // The maps are looked up by the lighting pass, once per pixel.
            self_shadow[i] = lit_self;
            continue;
        }
        // The rule that keeps a blocker from darkening twice: the maps answer for the light's
        // path above the polygon, the height field's own shadows for the path below it; the
        // two multiply.
        float lit_map = scene_shadow(i, map_shadow_point(world, n, l, lift), face, l);
        if (probed) {
            // Alpha 0 flags a term that is not a number, which 8 bits could not show.
            bool finite = !(isnan(lit_map) || isinf(lit_map) || isnan(lit_self) || isinf(lit_self));
            probe = vec4(lit_map, lit_self, facing ? 1.0 : 0.0, finite ? 1.0 : 0.0);
        }
        if (!facing) {
            continue;
        }
        add_direct_light(direct, i, attenuation, lit_map * lit_self, base.rgb, roughness,
                         metallic, normal, v, l);
    }
    color += direct.radiance;
    out_gbuffer_normal = vec4(normal, 1.0);
    uint surface_ids = (draw.extra.y & 0xffffu) | (min(traced_steps, 0xffffu) << 16);
    // The depth and motion of the point the depth buffer holds: the hit, or with the
    // material's depth off, its polygon.
#ifndef PLAIN_SURFACE
    vec3 depth_point = WRITE_DEPTH != 0u ? world : in_world;
#else
    vec3 depth_point = world;
#endif
    float view_depth = dot(frame.view_depth.xyz, depth_point) + frame.view_depth.w;
    out_gbuffer_surface = uvec4(floatBitsToUint(uv0), floatBitsToUint(view_depth), surface_ids);
    out_gbuffer_material = vec4(base.rgb, occlusion);
    // Screen motion of that point, in pixels.
    vec4 now = frame.view_proj * vec4(depth_point, 1.0);
    vec4 before = frame.previous_view_proj * vec4(depth_point, 1.0);
    vec2 motion = (now.xy / now.w - before.xy / before.w) * 0.5 * frame.viewport.xy;
    out_gbuffer_motion = vec4(motion, direct_lit_share(direct), 0.0);
    if (DEFERRED != 0u) {
        // w: 1 + lift, so a cleared texel (0) reads as "nothing deferred here".
        out_shading_point = vec4(world, 1.0 + lift);
        out_shading_frame = uvec4(pack_direction(normal), pack_direction(face), pack_direction(n),
                                  packUnorm2x16(vec2(roughness, metallic)));
        out_shading_self_shadow = self_shadow;
    }
    if (frame.counts.y > 0) {
        out_color = probe;
        return;
    }
    out_color = vec4(color, material.relief.y > 0.5 ? base.a : 1.0);
}

void main() {
#ifndef PLAIN_SURFACE
    // Hidden behind the occluder pass's bounds: nothing this fragment traces could show. The
    // shading sits in the other branch, not after the discard: lavapipe runs straight-line code
    // after a discard with its lanes masked off, but skips a branch no lane takes.
    if (behind_occluders()) {
        discard;
    } else {
        count_traced_fragment();
        shade();
    }
#else
    shade();
#endif
}
