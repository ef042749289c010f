// Unit vectors as two signed-normalised 16-bit numbers on the octahedron (Meyer et al. 2010):
// the deferred shading inputs keep three directions per pixel in one 32-bit word each, with an
// error under 1e-4 radians, well below what an 8-bit frame can show.
#ifndef OCTAHEDRAL_GLSL
#define OCTAHEDRAL_GLSL

uint pack_direction(vec3 d) {
    vec2 p = d.xy / max(abs(d.x) + abs(d.y) + abs(d.z), 1e-20);
    if (d.z < 0.0) {
        // The lower half folds over the diagonals onto the outer triangles.
        vec2 away = vec2(p.x >= 0.0 ? 1.0 : -1.0, p.y >= 0.0 ? 1.0 : -1.0);
        p = (1.0 - abs(p.yx)) * away;
    }
    return packSnorm2x16(p);
}

vec3 unpack_direction(uint bits) {
    vec2 p = unpackSnorm2x16(bits);
    vec3 d = vec3(p, 1.0 - abs(p.x) - abs(p.y));
    if (d.z < 0.0) {
        vec2 away = vec2(d.x >= 0.0 ? 1.0 : -1.0, d.y >= 0.0 ? 1.0 : -1.0);
        d.xy = (1.0 - abs(d.yx)) * away;
    }
    return normalize(d);
}

#endif
