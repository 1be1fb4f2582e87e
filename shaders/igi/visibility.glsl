// Visibility between a shading point and a VPL. Exact: any hit on a triangle, as NEE's shadow
// rays. With IGI_IMPERFECT_VISIBILITY (Marques and Santos' first acceleration) the bottom levels
// are not descended to their triangles: a segment is blocked by a leaf's box it passes through
// whole, and boxes holding either end (the surfaces the segment joins) are ignored. Cheaper, and
// wrong both ways: boxes block light that passes beside their triangles, and small occluders
// next to either end are missed.

#ifdef IGI_IMPERFECT_VISIBILITY
// The segment [0, tmax] enters the box after its start and leaves it before its end.
bool passes_through(RayTri r, vec3 lo, vec3 hi, float tmax) {
    vec3 t0 = (lo - r.org) * r.inv_dir;
    vec3 t1 = (hi - r.org) * r.inv_dir;
    float tn = max3(min(t0, t1));
    float tf = min3(max(t0, t1));
    return tn > 0.0 && tn <= tf && tf < tmax;
}

bool leaf_boxes_block(RayTri r, uint root, uint instance, float tmax) {
    if ((root & ITEM_COUNT_MASK) != 0u) {
        // A bottom level that is one leaf has no box of its own in the tree: its triangles.
        Hit h = Hit(tmax, 0.0, 0.0, 0u, 0u);
        return traverse_blas(r, root, instance, true, h);
    }
    uint stack[64];
    int sp = 0;
    uint index = root >> ITEM_INDEX_SHIFT;
    while (true) {
        BvhNode n = blas_at(index);
        uint items[2] = uint[2](n.item0, n.item1);
        vec3 lo[2] = vec3[2](n.min0, n.min1);
        vec3 hi[2] = vec3[2](n.max0, n.max1);
        for (int c = 0; c < 2; ++c) {
            if ((items[c] & ITEM_COUNT_MASK) != 0u) {
                if (passes_through(r, lo[c], hi[c], tmax)) return true;
            } else if (intersect_aabb(r, lo[c], hi[c], tmax) != INF && sp < 64) {
                stack[sp++] = items[c] >> ITEM_INDEX_SHIFT;
            }
        }
        if (sp == 0) return false;
        index = stack[--sp];
    }
    return false;
}

bool boxes_block(Ray ray) {
    if (F.counts.y == 0u) return false;
    RayTri world = ray_tri_setup(ray.origin, ray.dir);
    uint stack[32];
    int sp = 0;
    uint item = F.counts.z;
    while (true) {
        uint count = item & ITEM_COUNT_MASK, index = item >> ITEM_INDEX_SHIFT;
        if (count > 0u) {
            for (uint i = index; i < index + count; ++i) {
                Instance inst = instance_at(i);
                vec3 o = vec3(dot(inst.w2o[0], vec4(ray.origin, 1.0)), dot(inst.w2o[1], vec4(ray.origin, 1.0)), dot(inst.w2o[2], vec4(ray.origin, 1.0)));
                vec3 d = vec3(dot(inst.w2o[0].xyz, ray.dir), dot(inst.w2o[1].xyz, ray.dir), dot(inst.w2o[2].xyz, ray.dir));
                if (leaf_boxes_block(ray_tri_setup(o, d), inst.blas_root, i, ray.tmax)) return true;
            }
        } else {
            uint near, far;
            int hits = order_children(world, tlas_at(index), ray.tmax, near, far);
            if (hits > 0) {
                if (hits == 2 && sp < 32) stack[sp++] = far;
                item = near;
                continue;
            }
        }
        if (sp == 0) break;
        item = stack[--sp];
    }
    return false;
}
#endif

// Whether the segment from `origin` to `target` is blocked.
bool vpl_blocked(vec3 origin, vec3 target) {
    Ray shadow = Ray(origin, target - origin, 1.0);
#ifdef IGI_IMPERFECT_VISIBILITY
    return boxes_block(shadow);
#else
    Hit h;
    return trace(shadow, true, h);
#endif
}
