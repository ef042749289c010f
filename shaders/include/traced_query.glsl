// One occlusion query through the scene's acceleration structure (src/render/traced): triangles
// are opaque and commit themselves; a relief prism's box is a candidate resolved by the exact
// height-field walk of relief_prism.glsl. Any hit ends the query. Needs `scene` (the top level)
// and `prisms` (the prism records) declared, and relief_prism.glsl included, first.
#ifndef TRACED_QUERY_GLSL
#define TRACED_QUERY_GLSL

// Whether anything lies on origin + t dir for t in [t0, t1]; counts the prisms tested, their walk
// steps, and whether a walk ran out of budget.
bool segment_blocked(vec3 origin, float t0, vec3 dir, float t1, inout uint tested,
                     inout uint steps, inout bool capped) {
    rayQueryEXT query;
    rayQueryInitializeEXT(query, scene, gl_RayFlagsTerminateOnFirstHitEXT, 0xffu, origin, t0, dir,
                          t1);
    while (rayQueryProceedEXT(query)) {
        if (rayQueryGetIntersectionTypeEXT(query, false)
            != gl_RayQueryCandidateIntersectionAABBEXT) {
            continue;
        }
        uint prism = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(query, false)
                          + rayQueryGetIntersectionPrimitiveIndexEXT(query, false));
        vec3 o = rayQueryGetIntersectionObjectRayOriginEXT(query, false);
        vec3 d = rayQueryGetIntersectionObjectRayDirectionEXT(query, false);
        tested += 1u;
        float t;
        if (prism_blocks(prisms[prism], o, d, t0, t1, steps, capped, t)) {
            rayQueryGenerateIntersectionEXT(query, t);
        }
    }
    return rayQueryGetIntersectionTypeEXT(query, true) != gl_RayQueryCommittedIntersectionNoneEXT;
}

#endif
