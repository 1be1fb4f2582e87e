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

// The bottom level with leaves as solid boxes; the signature of traverse_blas, whose place it
// takes in trace() (trace.glsl). A hit says only that the segment is blocked.
bool leaf_boxes_block(RayTri r, uint root, uint instance, bool any_hit, inout Hit hit) {
    float tmax = hit.t;
    if ((root & ITEM_COUNT_MASK) != 0u) {
        // A bottom level that is one leaf has no box of its own in the tree: its triangles.
        return traverse_blas(r, root, instance, any_hit, hit);
    }
    uint stack[64 + 1];
    int sp = 0;
    uint index = root >> ITEM_INDEX_SHIFT;
    while (true) {
        BvhNode n = blas_at(index);
        uint items[2] = uint[2](n.item0, n.item1);
        vec3 lo[2] = vec3[2](n.min0, n.min1);
        vec3 hi[2] = vec3[2](n.max0, n.max1);
        for (int c = 0; c < 2; ++c) {
            bool leaf = (items[c] & ITEM_COUNT_MASK) != 0u;
            if (leaf && passes_through(r, lo[c], hi[c], tmax)) {
#ifdef HAS_ALPHA_TEST
                hit.triangle = NO_TRIANGLE;  // a box, which no alpha lets light through
#endif
                return true;
            }
            STACK_PUSH(stack, sp, 64, items[c] >> ITEM_INDEX_SHIFT, !leaf && intersect_aabb(r, lo[c], hi[c], tmax) != INF);
        }
        if (sp == 0) return false;
        index = stack[--sp];
    }
    return false;
}

#define VISIT_BLAS leaf_boxes_block
#endif
