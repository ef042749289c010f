// Parallax mapping with offset limiting (Welsh 2004, cited in papers 000 and 001): one height
// fetch at the entry point; the texture is shifted by that depth along the view direction, with
// the 1/dir.z factor dropped so the shift never exceeds the depth (the "offset limit"). The
// answer is the point of the ray at that shift: z = d(entry) * dir.z.

Hit trace_parallax(Ray ray, Budget budget) {
    float d0 = depth_bilinear(ray.origin, ray.depth_scale);
    vec3 dir = normalize(ray.dir);
    return Hit(d0 * dir.z, 1u, false);
}
