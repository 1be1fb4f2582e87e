// Two-level BVH traversal with a watertight ray/triangle test (Woop, Benthin, Wald 2013).

#extension GL_KHR_shader_subgroup_vote : require

struct Ray { vec3 origin; vec3 dir; float tmax; };
struct Hit { float t; float b1; float b2; uint instance; uint triangle; };

// Wachter & Binder, Ray Tracing Gems ch. 6: move p off the surface along the geometric normal
// by a few ULPs in integer space; where a coordinate is near zero, whose ULPs are finer than the
// error of p, by a small fraction of the coordinate magnitude of the triangle instead. The error
// of a computed hit point scales with that magnitude (pbrt-v4's bounds), not with p, so the
// offset does too: a scene scaled by 1e-4 gets offsets scaled by 1e-4 (a fixed 1/65536 would be
// a tenth of such a room).
vec3 offset_ray(vec3 p, vec3 n, float magnitude) {
    float origin = magnitude * (1.0 / 32.0);
    float float_scale = magnitude * (1.0 / 65536.0);
    const float int_scale = 256.0;
    ivec3 of_i = ivec3(int_scale * n);
    vec3 p_i = vec3(
        intBitsToFloat(floatBitsToInt(p.x) + (p.x < 0.0 ? -of_i.x : of_i.x)),
        intBitsToFloat(floatBitsToInt(p.y) + (p.y < 0.0 ? -of_i.y : of_i.y)),
        intBitsToFloat(floatBitsToInt(p.z) + (p.z < 0.0 ? -of_i.z : of_i.z)));
    return vec3(
        abs(p.x) < origin ? p.x + float_scale * n.x : p_i.x,
        abs(p.y) < origin ? p.y + float_scale * n.y : p_i.y,
        abs(p.z) < origin ? p.z + float_scale * n.z : p_i.z);
}

// Largest coordinate magnitude of the triangle (v0, v1, v2) in world space.
float coordinate_magnitude(vec3 v0, vec3 v1, vec3 v2) {
    return max3(max(abs(v0), max(abs(v1), abs(v2))));
}

// Per-ray constants of the watertight test, in the space the ray is traversed in. The axis
// permutation is applied with swizzles and selects rather than dynamic vector indexing (which
// compilers may spill to memory); on lavapipe the two measured the same.
struct RayTri { vec3 org; vec3 inv_dir; int kz; bool swap_xy; vec3 shear; };

// Permutes v so that the ray's dominant axis becomes z (Woop et al.: kx, ky, kz), swapping x and y
// when the ray points down that axis, to keep the winding.
vec3 permute(RayTri r, vec3 v) {
    vec3 p = r.kz == 0 ? v.yzx : (r.kz == 1 ? v.zxy : v);
    return r.swap_xy ? p.yxz : p;
}

RayTri ray_tri_setup(vec3 org, vec3 dir) {
    RayTri r;
    r.org = org;
    vec3 ad = abs(dir);
    r.kz = ad.x > ad.y ? (ad.x > ad.z ? 0 : 2) : (ad.y > ad.z ? 1 : 2);
    r.swap_xy = false;
    vec3 d = permute(r, dir);
    r.swap_xy = d.z < 0.0;
    d = r.swap_xy ? d.yxz : d;
    r.shear = vec3(d.x / d.z, d.y / d.z, 1.0 / d.z);
    // Zero components would give 0 * inf = NaN in the slab test.
    vec3 safe = mix(dir, mix(vec3(1e-30), vec3(-1e-30), lessThan(dir, vec3(0.0))), lessThan(ad, vec3(1e-30)));
    r.inv_dir = 1.0 / safe;
    return r;
}

// Returns t and barycentrics (b1, b2) of v1 and v2 when hit in (0, tmax).
bool intersect_triangle(RayTri r, vec3 v0, vec3 v1, vec3 v2, float tmax, out float t, out float b1, out float b2) {
    vec3 A = permute(r, v0 - r.org), B = permute(r, v1 - r.org), C = permute(r, v2 - r.org);
    float Ax = A.x - r.shear.x * A.z, Ay = A.y - r.shear.y * A.z;
    float Bx = B.x - r.shear.x * B.z, By = B.y - r.shear.y * B.z;
    float Cx = C.x - r.shear.x * C.z, Cy = C.y - r.shear.y * C.z;
    float U = Cx * By - Cy * Bx;
    float V = Ax * Cy - Ay * Cx;
    float W = Bx * Ay - By * Ax;
    if ((U < 0.0 || V < 0.0 || W < 0.0) && (U > 0.0 || V > 0.0 || W > 0.0)) return false;
    float det = U + V + W;
    if (det == 0.0) return false;
    float T = r.shear.z * (U * A.z + V * B.z + W * C.z);
    float inv = 1.0 / det;
    t = T * inv;
    if (!(t > 0.0 && t < tmax)) return false;
    b1 = V * inv;
    b2 = W * inv;
    return true;
}

#if defined(HAS_ALPHA_MASK) || defined(HAS_ALPHA_BLEND)
#define HAS_ALPHA_TEST
// Hits at or before this distance are not taken (trace() moves it past an alpha-tested
// triangle that let the ray through, and traverses again), but for opaque triangles at it
// within TMIN_SLACK: a surface coplanar with the one let through, whose distance rounds apart
// in its own instance's space (found against the ray queries, tests/kernel/traversal.rs).
float g_tmin = 0.0;
const float TMIN_SLACK = 0.999999;
#endif

// Slab test, conservative by 2*gamma(3) (Ize 2013) so that rounding never culls a real hit.
// With alpha-tested geometry, a box that ends before g_tmin holds no hit the traversal may take
// and is culled: the traversal that resumes beyond a leaf the ray passed through skips what lies
// before it. The entry distance returned (the children's order) is the unclamped one, so the
// boxes visited are visited in the order they were, and the hit is the same bits.
float intersect_aabb(RayTri r, vec3 bmin, vec3 bmax, float tmax) {
    vec3 t0 = (bmin - r.org) * r.inv_dir;
    vec3 t1 = (bmax - r.org) * r.inv_dir;
    float tn = max(max3(min(t0, t1)), 0.0);
    float tf = min3(max(t0, t1)) * 1.0000003577;
#ifdef HAS_ALPHA_TEST
    return (max(tn, g_tmin * TMIN_SLACK) <= tf && tn < tmax) ? tn : INF;
#else
    return (tn <= tf && tn < tmax) ? tn : INF;
#endif
}

// Items (see BvhNode): a leaf's primitive count in the low bits, the index above them.
const uint ITEM_COUNT_MASK = 15u;
const uint ITEM_INDEX_SHIFT = 4u;

// Traversal stacks push by writing the top slot whatever the lane does, and count the entry
// only when it is one: `stack[sp] = item; sp += push ? 1 : 0;`. llvmpipe stores to a per-lane
// index under the lanes' mask one lane at a time, as a load, a branch on the lane's bit and a
// store; under `if (push)` that branch is taken at random and mispredicted, a quarter of the
// conference room's time (docs/PERFORMANCE.md). Outside it only the loop's mask guards the
// store, whose bits change less often (traverse_blas keeps even that one steady). So a stack
// holds one slot past its capacity, which a push onto a full stack writes and does not count.
#define STACK_PUSH(stack, sp, capacity, value, push) \
    { stack[sp] = (value); sp += ((push) && sp < (capacity)) ? 1 : 0; }

// Tests both children of n; returns how many are hit before tmax, with the nearer one's item in
// `near`.
int order_children(RayTri r, BvhNode n, float tmax, out uint near, out uint far) {
    float ta = intersect_aabb(r, n.min0, n.max0, tmax);
    float tb = intersect_aabb(r, n.min1, n.max1, tmax);
    near = n.item0;
    far = n.item1;
    if (tb < ta) { float t = ta; ta = tb; tb = t; near = n.item1; far = n.item0; }
    return ta == INF ? 0 : (tb == INF ? 1 : 2);
}

#ifdef HAS_ALPHA_TEST
// Whether a ray passes through triangle `tri` at (b1, b2): alphaMode MASK below its cutoff, and
// BLEND with probability 1 - alpha (stochastic transparency: unbiased for coverage, for shadow
// rays too). The blend's number is a hash of the ray and the hit, so it is a pure function of
// the pixel's sample like every other random number.
bool alpha_rejects(RayTri r, uint tri, float b1, float b2) {
    Triangle T = triangle_at(tri);
    Material m = material_at(T.material);
    if ((m.textures1.w & (MATERIAL_ALPHA_MASK | MATERIAL_ALPHA_BLEND)) == 0) return false;
    float coverage = material_coverage(m, vertex_attributes(T, m, vec3(1.0 - b1 - b2, b1, b2)));
    if (coverage >= 1.0) return false;
    if (coverage <= 0.0) return true;
    uint h = pcg_hash(tri ^ pcg_hash(floatBitsToUint(b1) ^ pcg_hash(floatBitsToUint(b2)
        ^ pcg_hash(floatBitsToUint(r.org.x) ^ pcg_hash(floatBitsToUint(r.org.y) ^ pcg_hash(floatBitsToUint(r.inv_dir.z)))))));
    return float(h >> 8) * (1.0 / 16777216.0) >= coverage;
}

// The triangle of a hit that is a leaf's box, not a triangle (igi/visibility.glsl).
const uint NO_TRIANGLE = 0xffffffffu;

// Whether `hit` is on an alpha-tested triangle (whose coverage trace() has yet to test).
bool alpha_tested_hit(Hit hit) {
    return hit.triangle != NO_TRIANGLE && tri_pos_at(3u * hit.triangle).w == CORNER_ALPHA_TESTED;
}
#endif

// Bottom level from the `root` item: returns true on a hit closer than hit.t; with any_hit,
// at the first one. Aila and Laine's while-while traversal: inner nodes are descended in one
// loop until the lane holds a leaf, whose triangles are tested one at a time in a second loop.
// On llvmpipe every step of a loop runs all of its body for all 8 lanes of a SIMD group, so a
// single loop that took a node or a triangle per step paid both tests at every step; apart, a
// step pays one (about 20% fewer instructions and 9-19% less time, docs/PERFORMANCE.md). A lane
// in a leaf does not hold the others at its triangle count: it goes on to the next leaf.
// Alpha-tested triangles (CORNER_ALPHA_TESTED) are taken as hits here, and do not end an any-hit
// search: their coverage is tested once, at the nearest, by trace(). Testing it at every hit
// candidate put the texture fetch in this loop, where llvmpipe runs it at every step for all
// lanes: twice the time of the atrium with its leaves (docs/PERFORMANCE.md).
bool traverse_blas(RayTri r, uint root, uint instance, bool any_hit, inout Hit hit) {
    uint stack[64 + 1];
    int sp = 0;
    uint item = root;
    bool found = false;
    bool done = false;
    // The group loops while any lane traverses, and descends while any lane descends; a lane
    // that does not keeps its state by `done` and `descending` rather than by the loops' masks,
    // and an any-hit search ends by `done`, not a return: so the push's store is guarded by the
    // mask the group entered with, which llvmpipe's branches predict (STACK_PUSH). A lane not
    // descending tests node 0, which exists where any lane descends.
    while (subgroupAny(!done)) {
        while (subgroupAny(!done && (item & ITEM_COUNT_MASK) == 0u)) {
            bool descending = !done && (item & ITEM_COUNT_MASK) == 0u;
            uint near, far;
            int hits = order_children(r, blas_at(descending ? item >> ITEM_INDEX_SHIFT : 0u), hit.t, near, far);
            STACK_PUSH(stack, sp, 64, far, descending && hits == 2);
            if (descending) {
                if (hits > 0) {
                    item = near;
                } else if (sp > 0) {
                    item = stack[--sp];
                } else {
                    done = true;
                }
            }
        }
        while (!done && (item & ITEM_COUNT_MASK) != 0u) {
            uint count = item & ITEM_COUNT_MASK, index = item >> ITEM_INDEX_SHIFT;
            float t, b1, b2;
            vec4 p0 = tri_pos_at(3u * index);
            vec3 v1 = tri_pos_at(3u * index + 1u).xyz, v2 = tri_pos_at(3u * index + 2u).xyz;
            if (intersect_triangle(r, p0.xyz, v1, v2, hit.t, t, b1, b2)
#ifdef HAS_ALPHA_TEST
                // Past the alpha-tested triangle trace() let the ray through; an opaque one
                // at its distance, within rounding, is still a hit (coplanar with it: a decal's
                // wall), which the first traversal may have culled by its box's rounding.
                && (t > g_tmin || (p0.w != CORNER_ALPHA_TESTED && t >= g_tmin * TMIN_SLACK))
#endif
            ) {
                hit = Hit(t, b1, b2, instance, index);
                found = true;
#ifdef HAS_ALPHA_TEST
                if (any_hit && p0.w != CORNER_ALPHA_TESTED) done = true;
#else
                if (any_hit) done = true;
#endif
            }
            if (count > 1u) {
                item = ((index + 1u) << ITEM_INDEX_SHIFT) | (count - 1u);
            } else if (sp > 0) {
                item = stack[--sp];
            } else {
                done = true;
            }
        }
    }
    return found;
}
