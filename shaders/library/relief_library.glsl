// relief's displacement methods as a shader library: include this file, then the method files
// you want. It declares no descriptor, uniform block or push constant of its own; the includer
// names its own resources with the macros below (docs/shader-library.md has the whole contract).
//
// Before including, define:
//   RELIEF_HEIGHT_POINT   a sampler2D over the height image: level 0 the heights in [0, 1]
//                         (1 = the top plane), levels 1.. the max pyramid that
//                         heightfield::MaxPyramid::build_bilinear_bound makes; nearest filtering,
//                         nearest mip, the map's addressing (repeat or clamp to edge)
//   RELIEF_HEIGHT_LINEAR  a sampler2D over the same image: linear filtering, the same addressing
//   RELIEF_HEIGHT_INFO    a vec4 expression: (width, height, mip levels, 1 for repeat else 0)
// and, for the methods that read a method map (csm.glsl, rcsm.glsl: a cone map; quadric.glsl:
// a quadric map), one texel per height texel, read by integer texel:
//   RELIEF_METHOD_MAP     a sampler2D over that map
// Optionally:
//   RELIEF_SPEC_ID_BASE   the first specialization id the library's constants take (default
//                         100); each constant's offset from it is in relief_ids.glsl and in
//                         relief::shader_library::SPEC_CONSTANTS
//   RELIEF_HEIGHT_UV_MAP(uv1_per_uv0)  the 2x2 map from uv0 to height uv, for relief_frame.glsl
//                         (default: height uv is uv0)
//   RELIEF_REVERSE_Z      depth is reversed (1 near, 0 far): relief_fragment_depth keeps the
//                         hit's depth from coming nearer by min, not max; declare
//                         gl_FragDepth depth_less, not depth_greater
//
// Then, for example:
//   #include "relief_library.glsl"
//   #include "qdm.glsl"            // Hit trace_qdm(Ray ray, Budget budget)
//   Hit hit = trace_qdm(ray, ray_budget(ray));
//   vec2 uv_hit = ray_uv(ray, hit.z);
//
// Files: the methods (parallax, steep, relief, pom, csm, rcsm, qrm, pdm, qdm, maxmip, quadric:
// one `Hit trace_<name>(Ray, Budget)` each); shadows.glsl (self-shadows toward a disk light,
// `light_visible`; define METHOD_TRACE as the method's trace function first, for the hard mode);
// relief_frame.glsl (the tangent frame, view ray in height space, the hit's world position;
// fragment shaders only: it takes screen derivatives); curved.glsl (curved relief,
// `trace_curved`, after relief_frame.glsl).
#ifndef RELIEF_LIBRARY_GLSL
#define RELIEF_LIBRARY_GLSL

#if !defined(RELIEF_HEIGHT_POINT) || !defined(RELIEF_HEIGHT_LINEAR) || !defined(RELIEF_HEIGHT_INFO)
#error "relief_library.glsl: define RELIEF_HEIGHT_POINT, RELIEF_HEIGHT_LINEAR and RELIEF_HEIGHT_INFO first"
#endif

#ifndef RELIEF_SPEC_ID_BASE
#define RELIEF_SPEC_ID_BASE 100
#endif

#ifndef RELIEF_HEIGHT_UV_MAP
#define RELIEF_HEIGHT_UV_MAP(uv1_per_uv0) mat2(1.0)
#endif

#define RELIEF_SHADER_LIBRARY
// The names relief's own shaders give these resources.
#define height_point RELIEF_HEIGHT_POINT
#define height_linear RELIEF_HEIGHT_LINEAR
#define HEIGHT_INFO RELIEF_HEIGHT_INFO
#ifdef RELIEF_METHOD_MAP
#define method_map RELIEF_METHOD_MAP
#endif

#include "relief_ids.glsl"
#include "conventions.glsl"
#include "numeric.glsl"
#include "heightfield.glsl"

#endif
