// The top level of the two-level traversal: instances' boxes, then each instance's bottom level
// in object space (traverse_blas in intersect.glsl, or what a kernel defines VISIT_BLAS as before
// including this: IGI's imperfect visibility, igi/visibility.glsl).

#ifndef VISIT_BLAS
#define VISIT_BLAS traverse_blas
#endif

bool trace(Ray ray, bool any_hit, out Hit hit) {
    hit = Hit(ray.tmax, 0.0, 0.0, 0u, 0u);
    if (instance_count() == 0u) return false;
    RayTri world = ray_tri_setup(ray.origin, ray.dir);
    uint stack[32];
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
                    if (any_hit) return true;
                }
            }
        } else {
            uint near, far;
            int hits = order_children(world, tlas_at(index), hit.t, near, far);
            if (hits > 0) {
                if (hits == 2 && sp < 32) stack[sp++] = far;
                item = near;
                continue;
            }
        }
        if (sp == 0) break;
        item = stack[--sp];
    }
    return found;
}
