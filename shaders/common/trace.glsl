// What a ray hits: trace(), the one entry point of every kernel. platoon's own traversal is the
// top level of the two-level BVH here, instances' boxes, then each instance's bottom level in
// object space (traverse_blas in intersect.glsl, or what a kernel defines VISIT_BLAS as before
// including this: IGI's imperfect visibility, igi/visibility.glsl). With TRAVERSAL_RAY_QUERY
// (a tracer of `--traversal ray-query`), the device's ray queries traverse its acceleration
// structures instead (crates/platoon-tracer/src/structures.rs), but where a kernel visits the
// bottom levels its own way, which a query cannot.

#if defined(TRAVERSAL_RAY_QUERY) && !defined(VISIT_BLAS)
#define TRACE_BY_RAY_QUERY
#endif
#ifndef VISIT_BLAS
#define VISIT_BLAS traverse_blas
#endif

bool trace_levels(Ray ray, bool any_hit, out Hit hit) {
    hit = Hit(ray.tmax, 0.0, 0.0, 0u, 0u);
    if (instance_count() == 0u) return false;
    RayTri world = ray_tri_setup(ray.origin, ray.dir);
    uint stack[32 + 1];
    int sp = 0;
    uint item = tlas_root();  // the root: inner node 0, or the one instance's leaf
    bool found = false;
    while (true) {
        uint count = item & ITEM_COUNT_MASK, index = item >> ITEM_INDEX_SHIFT;
        if (count > 0u) {
            for (uint i = index; i < index + count; ++i) {
                Instance inst = instance_at(i);
                vec3 o = vec3(dot(inst.w2o[0], vec4(ray.origin, 1.0)), dot(inst.w2o[1], vec4(ray.origin, 1.0)), dot(inst.w2o[2], vec4(ray.origin, 1.0)));
                vec3 d = vec3(dot(inst.w2o[0].xyz, ray.dir), dot(inst.w2o[1].xyz, ray.dir), dot(inst.w2o[2].xyz, ray.dir));
                if (VISIT_BLAS(ray_tri_setup(o, d), inst.blas_root, i, any_hit, hit)) {
                    found = true;
#ifdef HAS_ALPHA_TEST
                    // An alpha-tested candidate ends nothing yet: the nearest is tested.
                    if (any_hit && !alpha_tested_hit(hit)) return true;
#else
                    if (any_hit) return true;
#endif
                }
            }
        }
        uint near = 0u, far = 0u;
        int hits = 0;
        if (count == 0u) hits = order_children(world, tlas_at(index), hit.t, near, far);
        // Outside that branch, so that the push's store is guarded by the loop's mask alone
        // (STACK_PUSH).
        STACK_PUSH(stack, sp, 32, far, hits == 2);
        if (hits > 0) {
            item = near;
            continue;
        }
        if (sp == 0) break;
        item = stack[--sp];
    }
    return found;
}

#ifdef HAS_ALPHA_TEST
// The world-space ray as instance `i`'s bottom level traverses it (what alpha_rejects hashes).
RayTri instance_ray(Ray ray, uint i) {
    Instance inst = instance_at(i);
    vec3 o = vec3(dot(inst.w2o[0], vec4(ray.origin, 1.0)), dot(inst.w2o[1], vec4(ray.origin, 1.0)), dot(inst.w2o[2], vec4(ray.origin, 1.0)));
    vec3 d = vec3(dot(inst.w2o[0].xyz, ray.dir), dot(inst.w2o[1].xyz, ray.dir), dot(inst.w2o[2].xyz, ray.dir));
    return ray_tri_setup(o, d);
}

#endif

#ifdef TRACE_BY_RAY_QUERY
#extension GL_EXT_ray_query : require
// STRUCTURE_BINDING of crates/platoon-tracer/src/memory.rs.
layout(set = 0, binding = 17) uniform accelerationStructureEXT scene_structures;

// The nearest hit whose surface covers the ray there, by a ray query: opaque triangles are hits
// outright; alpha-tested ones (a scene that has them builds no geometry opaque) come back as
// candidates, each confirmed where its coverage lets the ray stop, as trace() below tests it at
// the nearest. A hit's triangle is its mesh's first (the instance's custom index) plus the
// primitive's index, its instance the query's instance id: what the own traversal reports.
bool trace(Ray ray, bool any_hit, out Hit hit) {
    hit = Hit(ray.tmax, 0.0, 0.0, 0u, 0u);
    if (instance_count() == 0u) return false;
    rayQueryEXT q;
    uint flags = any_hit ? gl_RayFlagsTerminateOnFirstHitEXT : gl_RayFlagsNoneEXT;
    rayQueryInitializeEXT(q, scene_structures, flags, 0xffu, ray.origin, 0.0, ray.dir, ray.tmax);
    while (rayQueryProceedEXT(q)) {
#ifdef HAS_ALPHA_TEST
        uint instance = uint(rayQueryGetIntersectionInstanceIdEXT(q, false));
        uint tri = uint(rayQueryGetIntersectionInstanceCustomIndexEXT(q, false)
            + rayQueryGetIntersectionPrimitiveIndexEXT(q, false));
        vec2 b = rayQueryGetIntersectionBarycentricsEXT(q, false);
        bool tested = tri_pos_at(3u * tri).w == CORNER_ALPHA_TESTED;
        if (!tested || !alpha_rejects(instance_ray(ray, instance), tri, b.x, b.y))
            rayQueryConfirmIntersectionEXT(q);
#endif
    }
    if (rayQueryGetIntersectionTypeEXT(q, true) == gl_RayQueryCommittedIntersectionNoneEXT)
        return false;
    vec2 b = rayQueryGetIntersectionBarycentricsEXT(q, true);
    hit = Hit(rayQueryGetIntersectionTEXT(q, true), b.x, b.y,
        uint(rayQueryGetIntersectionInstanceIdEXT(q, true)),
        uint(rayQueryGetIntersectionInstanceCustomIndexEXT(q, true)
            + rayQueryGetIntersectionPrimitiveIndexEXT(q, true)));
    return true;
}
#elif defined(HAS_ALPHA_TEST)
// The nearest hit whose surface covers the ray there (an any-hit search ends at the first
// opaque triangle, or at an alpha-tested one that covers). The traversal takes alpha-tested
// triangles as hits; when the nearest is one that lets this ray through, the search starts
// again beyond it. The same hit as testing coverage at every candidate, but the texture is read
// once per alpha-tested surface the ray meets, not at every step of the traversal.
bool trace(Ray ray, bool any_hit, out Hit hit) {
    g_tmin = 0.0;
    while (true) {
        bool found = trace_levels(ray, any_hit, hit);
        if (!found || !alpha_tested_hit(hit)) return found;
        if (!alpha_rejects(instance_ray(ray, hit.instance), hit.triangle, hit.b1, hit.b2)) return true;
        g_tmin = hit.t;
    }
    return false;
}
#else
bool trace(Ray ray, bool any_hit, out Hit hit) {
    return trace_levels(ray, any_hit, hit);
}
#endif
