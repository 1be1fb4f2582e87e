// The rasterizer's coverage and what a covered texel appends (lhb/raster.rs on the CPU: the same
// edge functions, top-left rule and plane depth). Shared by raster.comp (a small triangle in one
// invocation) and blocks.comp (a large one's block, an invocation a texel).

// Push words while building: the pass (LHB_APPEND, LHB_COUNT, LHB_FILL), the dispatch's first
// direction (raster.comp) or queue entry (blocks.comp), the queue's capacity in entries, and
// the placed triangles [begin, end) raster.comp takes.
const uint LHB_APPEND = 0u;
const uint LHB_COUNT = 1u;
const uint LHB_FILL = 2u;
uint lhb_pass() { return pc.method_words[0]; }
uint lhb_first() { return pc.method_words[1]; }
uint lhb_queue_capacity() { return pc.method_words[2]; }
uint lhb_placed_begin() { return pc.method_words[3]; }
uint lhb_placed_end() { return pc.method_words[4]; }

// A triangle's bounding box wider or taller than this (texels) is split into blocks.
const uint LHB_SMALL = 32u;
const uint LHB_BLOCK = 16u;

// The triangle projected into direction d's buffer; false for a back face or an edge-on one.
bool lhb_projected(uint placed, uint d, out vec3 a, out vec3 b, out vec3 c) {
    vec3 p0, p1, p2;
    lhb_corners(lhb_placed_at_index(placed), p0, p1, p2);
    LhbView view = lhb_view(d);
    a = lhb_project(view, p0);
    b = lhb_project(view, p1);
    c = lhb_project(view, p2);
    // Twice the signed area in (u, v): negative for a front face (clockwise).
    float area = (b.x - a.x) * (c.y - a.y) - (b.y - a.y) * (c.x - a.x);
    return area < 0.0;
}

// Its texel box [x0, x1) x [y0, y1), clamped to the buffer.
uvec4 lhb_box(vec3 a, vec3 b, vec3 c) {
    int r = int(lhb_resolution());
    uint x0 = uint(max(floor(min(a.x, min(b.x, c.x))), 0.0));
    uint y0 = uint(max(floor(min(a.y, min(b.y, c.y))), 0.0));
    uint x1 = uint(clamp(int(ceil(max(a.x, max(b.x, c.x)))), 0, r));
    uint y1 = uint(clamp(int(ceil(max(a.y, max(b.y, c.y)))), 0, r));
    return uvec4(min(x0, uint(r)), min(y0, uint(r)), x1, y1);
}

bool lhb_top_left(vec2 e0, vec2 e1) {
    vec2 d = e1 - e0;
    return (d.y == 0.0 && d.x > 0.0) || d.y < 0.0;
}

// Whether texel (i, j)'s centre is covered, and its depth there.
bool lhb_covers(vec3 a, vec3 b, vec3 c, uint i, uint j, out float depth) {
    vec2 p = vec2(float(i) + 0.5, float(j) + 0.5);
    vec3 e[4] = vec3[4](a, b, c, a);
    float w[3];
    bool inside = true;
    for (int k = 0; k < 3; ++k) {
        vec2 e0 = e[k].xy, e1 = e[k + 1].xy;
        // Positive inside a clockwise triangle.
        float f = (p.x - e0.x) * (e1.y - e0.y) - (p.y - e0.y) * (e1.x - e0.x);
        inside = inside && (f > 0.0 || (f == 0.0 && lhb_top_left(e0, e1)));
        w[k] = f;
    }
    // Barycentrics from the edge functions: w[1] is a's weight (the edge bc), w[2] b's, w[0] c's.
    depth = (w[1] * a.z + w[2] * b.z + w[0] * c.z) / (w[0] + w[1] + w[2]);
    return inside;
}

// Appends layer (depth, placed) to texel t of every direction's texels, as the pass does.
void lhb_emit(uint t, float depth, uint placed) {
    uint pass = lhb_pass();
    if (pass == LHB_COUNT) {
        atomicAdd(LHB_WORK.v[t], 1u);
        return;
    }
    uint n = atomicAdd(LHB_WORK.v[t], 1u);
    uvec2 layer = uvec2(floatBitsToUint(depth), placed);
    if (pass == LHB_FILL) {
        LHB_LAYERS.v[n] = layer;
        return;
    }
    uint capacity = lhb_capacity();
    if (n < capacity) LHB_LAYERS.v[t * capacity + n] = layer;
    else atomicAdd(pc.g.stats.v[STAT_LHB_LAYERS], 1u);
}
