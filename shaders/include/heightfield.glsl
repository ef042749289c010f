// Texel maths and height fetches over the two samplers (docs/conventions.md).
#ifndef HEIGHTFIELD_GLSL
#define HEIGHTFIELD_GLSL

// The height map's size, mip levels and addressing (x, y, z, w as the frame block's height_info):
// the frame block's, unless a pass that binds a height map beside another frame names its own
// (lighting.comp's ray-traced shadows).
#ifndef HEIGHT_INFO
#define HEIGHT_INFO frame.height_info
#endif

// Texel fetches counted (docs/profiling.md): every read of the height map, its pyramids or the
// method's map goes through counted_texel or one of the helpers below, which add one to
// height_fetches per texture instruction (a gather of four corners is one) when the pipeline sets
// COUNT_FETCHES. Production pipelines leave it 0, and the count is dead code the compiler drops.
layout(constant_id = SPEC_COUNT_FETCHES) const uint COUNT_FETCHES = 0u;
uint height_fetches = 0u;

void count_fetch() {
    if (COUNT_FETCHES != 0u) {
        height_fetches += 1u;
    }
}

// texelFetch, counted.
vec4 counted_texel(sampler2D map, ivec2 texel, int level) {
    count_fetch();
    return texelFetch(map, texel, level);
}

vec2 height_size() {
    return HEIGHT_INFO.xy;
}

// The budget for `ray`: the fixed cap, or (BUDGET_EXTENT_LIMIT set: the accurate methods'
// default) the cap plus one step per texel boundary the ray crosses between the top and bottom
// planes, up to the limit. A grazing ray over a deep field crosses thousands of texels, and a
// tree walk that finds a spike in every coarse node pays a step for every few of them.
Budget ray_budget(Ray ray) {
    Budget b = default_budget();
    if (BUDGET_EXTENT_LIMIT > b.max_steps) {
        vec2 crossed = abs(ray_delta(ray)) * height_size();
        float grown = float(b.max_steps) + ceil(crossed.x + crossed.y);
        // Also catches inf and NaN from a ray that barely descends.
        b.max_steps = grown < float(BUDGET_EXTENT_LIMIT) ? uint(grown) : BUDGET_EXTENT_LIMIT;
    }
    return b;
}

// The texel of a level holding cell `cell` (which may lie outside the map), by the addressing.
ivec2 address_cell(vec2 cell, vec2 size) {
    vec2 t = HEIGHT_INFO.w > 0.5 ? cell - size * floor(cell / size) : clamp(cell, vec2(0.0), size - 1.0);
    return ivec2(t);
}

// The four texel heights at the corners of bilinear cell `cell` (texel centres (i, j) to
// (i+1, j+1)), by the addressing: x = h00, y = h10, z = h01, w = h11. One gather instead of four
// fetches: it is taken at the cell's centre, half a texel from every texel line, so the sampler's
// sub-texel rounding cannot pick another cell; the point sampler's own addressing (repeat or
// clamp to edge, as the map's) wraps or clamps, and a gather reads the view's base level.
vec4 bilinear_corners(vec2 cell) {
    count_fetch();
    vec4 h = textureGather(height_point, (cell + 1.0) / height_size(), 0);
    // A gather returns (i, j+1), (i+1, j+1), (i+1, j), (i, j).
    return h.wzxy;
}

// Bilinear height at uv computed from the four texels around it in full float precision,
// unlike the filtering hardware, which weighs with a few bits of sub-texel precision.
float height_bilinear_exact(vec2 uv) {
    vec2 g = uv * height_size() - 0.5;
    vec2 cell = floor(g);
    vec2 f = g - cell;
    vec4 h = bilinear_corners(cell);
    return mix(mix(h.x, h.y, f.x), mix(h.z, h.w, f.x), f.y);
}

// Bilinear height at uv (level 0): the true surface.
float height_bilinear(vec2 uv) {
    count_fetch();
    return textureLod(height_linear, uv, 0.0).r;
}

// Height of the texel containing uv at pyramid level `level` (level 0: the box surface).
float height_max(vec2 uv, float level) {
    count_fetch();
    return textureLod(height_point, uv, level).r;
}

// Depth below the top plane of the bilinear surface, in uv units.
float depth_bilinear(vec2 uv, float depth_scale) {
    return depth_scale * (1.0 - height_bilinear(uv));
}

// Surface gradient (dh/du, dh/dv) by central differences one texel apart.
vec2 height_gradient(vec2 uv) {
    vec2 texel = 1.0 / height_size();
    float hx = height_bilinear(uv + vec2(texel.x, 0.0)) - height_bilinear(uv - vec2(texel.x, 0.0));
    float hy = height_bilinear(uv + vec2(0.0, texel.y)) - height_bilinear(uv - vec2(0.0, texel.y));
    return vec2(hx, hy) / (2.0 * texel);
}

#endif
