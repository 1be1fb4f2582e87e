// What layered hit buffers' kernels share (crates/platoon-core/src/method/lhb,
// crates/platoon-tracer/src/method/lhb.rs): the tables (lhb/tables.rs: header, views,
// directional map, placed triangles), the work words (per texel a count, or with LHB_EXACT an
// offset; the prefix sum's partial sums; the queue of large triangles' blocks) and the layers.
// Included after common/surface.glsl.

layout(buffer_reference, std430, buffer_reference_align = 16) buffer LhbWords { uint v[]; };
layout(buffer_reference, std430, buffer_reference_align = 16) buffer LhbLayers { uvec2 v[]; };

#define LHB_TABLES Uints(pc.g.method_buffer0)
#define LHB_WORK LhbWords(pc.g.method_buffer1)
#define LHB_LAYERS LhbLayers(pc.g.method_buffer2)

// The header's words (tables.rs: pack).
uint lhb_directions() { return LHB_TABLES.v[0]; }
uint lhb_resolution() { return LHB_TABLES.v[1]; }
uint lhb_capacity() { return LHB_TABLES.v[2]; }
uint lhb_placed() { return LHB_TABLES.v[3]; }
uvec2 lhb_map_size() { return uvec2(LHB_TABLES.v[4], LHB_TABLES.v[5]); }
uint lhb_views_at() { return LHB_TABLES.v[6]; }
uint lhb_ranges_at() { return LHB_TABLES.v[7]; }
uint lhb_candidates_at() { return LHB_TABLES.v[8]; }
uint lhb_placed_at() { return LHB_TABLES.v[9]; }
vec3 lhb_centre() { return vec3(uintBitsToFloat(LHB_TABLES.v[10]), uintBitsToFloat(LHB_TABLES.v[11]), uintBitsToFloat(LHB_TABLES.v[12])); }
float lhb_radius() { return uintBitsToFloat(LHB_TABLES.v[13]); }
float lhb_cone() { return uintBitsToFloat(LHB_TABLES.v[14]); }
// A probe's queries (tables.rs: with_queries): their count, then 8 words each; 0 in a render.
uint lhb_queries_at() { return LHB_TABLES.v[15]; }

// Texels of every direction: the work words' first region.
uint lhb_texels() { uint r = lhb_resolution(); return lhb_directions() * r * r; }
// The prefix sum's partial sums: one a row, then one a direction.
uint lhb_row_sums_at() { return lhb_texels(); }
uint lhb_direction_sums_at() { return lhb_texels() + lhb_directions() * lhb_resolution(); }
// The queue of blocks, uvec4 entries (placed triangle, direction, block x, block y).
uint lhb_queue_at() { return (lhb_direction_sums_at() + lhb_directions() + 3u) & ~3u; }

// stats[2] and [3] (scene.glsl's Stats) while the buffers are built: blocks queued, and layers
// lost past the capacity (or, after the exact variant's prefix sum, the layers in all).
const uint STAT_LHB_QUEUED = 2u;
const uint STAT_LHB_LAYERS = 3u;

struct LhbView { vec3 right; vec3 up; vec3 forward; };

LhbView lhb_view(uint d) {
    uint a = lhb_views_at() + 9u * d;
    vec3 axis[3];
    for (uint k = 0u; k < 3u; ++k)
        axis[k] = vec3(uintBitsToFloat(LHB_TABLES.v[a + 3u * k]), uintBitsToFloat(LHB_TABLES.v[a + 3u * k + 1u]), uintBitsToFloat(LHB_TABLES.v[a + 3u * k + 2u]));
    return LhbView(axis[0], axis[1], axis[2]);
}

// Point p in the buffer of `view`: texel coordinates (texel (i, j) spans [i, i + 1) x [j, j + 1))
// and depth from the sphere's entry plane (frame.rs: BufferFrame::project, the same operations).
vec3 lhb_project(LhbView view, vec3 p) {
    vec3 q = p - lhb_centre();
    float radius = lhb_radius();
    float scale = float(lhb_resolution()) / (2.0 * radius);
    return vec3((dot(q, view.right) + radius) * scale, (dot(q, view.up) + radius) * scale, dot(q, view.forward) + radius);
}

// Placed triangle i: its instance and scene triangle.
uvec2 lhb_placed_at_index(uint i) {
    uint a = lhb_placed_at() + 2u * i;
    return uvec2(LHB_TABLES.v[a], LHB_TABLES.v[a + 1u]);
}

// Its corners in render space.
void lhb_corners(uvec2 placed, out vec3 p0, out vec3 p1, out vec3 p2) {
    Instance inst = instance_at(placed.x);
    p0 = instance_point(inst, tri_pos_at(3u * placed.y).xyz);
    p1 = instance_point(inst, tri_pos_at(3u * placed.y + 1u).xyz);
    p2 = instance_point(inst, tri_pos_at(3u * placed.y + 2u).xyz);
}
