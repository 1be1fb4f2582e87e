// A ray answered by the buffers (lhb/lookup.rs on the CPU): its direction snapped to the
// nearest buffer direction by the directional map, its origin projected into that buffer and
// moved by the cone jitter, and the first layer of the texel beyond the origin's depth whose
// triangle faces the ray (surfaces are one-sided: a back the ray would meet, such as the
// origin's own surface seen from a neighbouring direction, is skipped). The hit lies on the
// texel's centre line at the layer's depth. Needs lhb/lhb.glsl, common/sampling.glsl.

// The map's texel of unit d (directional_map.rs: texel): theta from +z, phi about z from +x.
uint lhb_nearest(vec3 d) {
    uvec2 size = lhb_map_size();
    float theta = acos(clamp(d.z, -1.0, 1.0));
    float phi = atan(d.y, d.x);
    if (phi < 0.0) phi += 2.0 * PI;
    uint column = min(uint(phi / (2.0 * PI) * float(size.x)), size.x - 1u);
    uint row = min(uint(theta / PI * float(size.y)), size.y - 1u);
    uint at = lhb_ranges_at() + 2u * (row * size.x + column);
    uint first = lhb_candidates_at() + LHB_TABLES.v[at], count = LHB_TABLES.v[at + 1u];
    // The largest dot product, a tie to the lowest index (candidates ascend).
    float best = -2.0;
    uint nearest = 0u;
    for (uint k = 0u; k < count; ++k) {
        uint i = LHB_TABLES.v[first + k];
        float c = dot(lhb_view(i).forward, d);
        if (c > best) {
            best = c;
            nearest = i;
        }
    }
    return nearest;
}

// Texel t's layers: [begin, end) of LHB_LAYERS.
uvec2 lhb_list(uint t) {
#ifdef LHB_EXACT
    return uvec2(t == 0u ? 0u : LHB_WORK.v[t - 1u], LHB_WORK.v[t]);
#else
    uint capacity = lhb_capacity();
    return uvec2(t * capacity, t * capacity + min(LHB_WORK.v[t], capacity));
#endif
}

// Attempts at a layer facing the ray before the lookup gives up (a miss).
const uint LHB_ATTEMPTS = 8u;

// The point of the last lookup's hit (on the texel's centre line; a probe reports it).
vec3 lhb_point;

// The lookup of ray (origin, unit dir) with cone jitter `u` (two uniform numbers): the hit as
// trace() reports one; false where the texel lists nothing beyond the origin (the ray leaves).
bool lhb_lookup(vec3 origin, vec3 dir, vec2 u, out Hit hit) {
    hit = Hit(INF, 0.0, 0.0, 0u, 0u);
    uint d = lhb_nearest(dir);
    LhbView view = lhb_view(d);
    vec3 q = lhb_project(view, origin);
    vec2 uv = q.xy + lhb_cone() * sample_disk_concentric(u);
    float r = float(lhb_resolution());
    if (!(uv.x >= 0.0 && uv.y >= 0.0 && uv.x < r && uv.y < r)) return false;
    uvec2 texel = min(uvec2(uv), uvec2(lhb_resolution() - 1u));
    uvec2 list = lhb_list(d * lhb_resolution() * lhb_resolution() + texel.y * lhb_resolution() + texel.x);
    // Layers after (depth, id) in the order (depth, then placed triangle): the first beyond the
    // origin, then past each one that faces away.
    float after_depth = q.z + 1e-5 * lhb_radius();
    uint after_id = ~0u;
    for (uint attempt = 0u; attempt < LHB_ATTEMPTS; ++attempt) {
        float best = INF;
        uint best_id = ~0u;
        for (uint k = list.x; k < list.y; ++k) {
            uvec2 layer = LHB_LAYERS.v[k];
            float depth = uintBitsToFloat(layer.x);
            bool later = depth > after_depth || (depth == after_depth && after_id != ~0u && layer.y > after_id);
            if (later && (depth < best || (depth == best && layer.y < best_id))) {
                best = depth;
                best_id = layer.y;
            }
        }
        if (best_id == ~0u) return false;
        uvec2 placed = lhb_placed_at_index(best_id);
        vec3 p0, p1, p2;
        lhb_corners(placed, p0, p1, p2);
        vec3 e1 = p1 - p0, e2 = p2 - p0;
        if (dot(cross(e1, e2), dir) < 0.0) {
            // The texel centre's line at the layer's depth, and its barycentrics on the
            // triangle (clamped: the centre lies on the triangle up to rounding).
            float size = 2.0 * lhb_radius() / r;
            vec2 centre = (vec2(texel) + 0.5) * size - lhb_radius();
            vec3 p = lhb_centre() + view.right * centre.x + view.up * centre.y + view.forward * (best - lhb_radius());
            vec3 pv = cross(view.forward, e2);
            float det = dot(e1, pv);
            vec3 tv = p - p0;
            float b1 = det != 0.0 ? dot(tv, pv) / det : 0.0;
            float b2 = det != 0.0 ? dot(view.forward, cross(tv, e1)) / det : 0.0;
            b1 = clamp(b1, 0.0, 1.0);
            b2 = clamp(b2, 0.0, 1.0);
            if (b1 + b2 > 1.0) {
                float s = b1 + b2;
                b1 /= s;
                b2 /= s;
            }
            hit = Hit(distance(origin, p), b1, b2, placed.x, placed.y);
            lhb_point = p;
            return true;
        }
        after_depth = best;
        after_id = best_id;
    }
    return false;
}
