#version 460
// Layered hit buffers, the rasterizer (Yu's thesis, ch. 4): an invocation per (placed triangle,
// direction). A front face whose box fits LHB_SMALL texels a side is rasterized here (each
// texel centre of its box tested); a larger one is split into blocks of LHB_BLOCK texels on the
// queue, which blocks.comp rasterizes an invocation a texel (a whole-buffer triangle in one
// invocation would pass llvmpipe's 65535 loop iterations an invocation, silently). The filling
// pass of the exact variant queues nothing: it replays the counting pass's queue.

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "common/scene.glsl"
#include "common/textures.glsl"
#include "common/intersect.glsl"
#include "common/surface.glsl"
#include "lhb/lhb.glsl"
#include "lhb/raster.glsl"

void main() {
    uint placed = lhb_placed_begin() + gl_GlobalInvocationID.x;
    uint d = lhb_first() + gl_WorkGroupID.y;
    if (placed >= min(lhb_placed_end(), lhb_placed()) || d >= lhb_directions()) return;
    vec3 a, b, c;
    if (!lhb_projected(placed, d, a, b, c)) return;
    uvec4 box = lhb_box(a, b, c);
    if (box.z <= box.x || box.w <= box.y) return;
    uint r = lhb_resolution();
    if (box.z - box.x > LHB_SMALL || box.w - box.y > LHB_SMALL) {
        if (lhb_pass() == LHB_FILL) return;
        uvec2 blocks = (box.zw - box.xy + LHB_BLOCK - 1u) / LHB_BLOCK;
        uint n = blocks.x * blocks.y;
        uint first = atomicAdd(pc.g.stats.v[STAT_LHB_QUEUED], n);
        uint capacity = lhb_queue_capacity();
        for (uint k = 0u; k < n && first + k < capacity; ++k) {
            uint e = lhb_queue_at() + 4u * (first + k);
            LHB_WORK.v[e] = placed;
            LHB_WORK.v[e + 1u] = d;
            LHB_WORK.v[e + 2u] = box.x + (k % blocks.x) * LHB_BLOCK;
            LHB_WORK.v[e + 3u] = box.y + (k / blocks.x) * LHB_BLOCK;
        }
        return;
    }
    uint base = d * r * r;
    for (uint j = box.y; j < box.w; ++j) {
        for (uint i = box.x; i < box.z; ++i) {
            float depth;
            if (lhb_covers(a, b, c, i, j, depth)) lhb_emit(base + j * r + i, depth, placed);
        }
    }
}
