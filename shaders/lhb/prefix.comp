#version 460
// Layered hit buffers, the exact variant's prefix sum: each texel's count (the counting pass)
// becomes the offset of its first layer among every direction's, in four stages (push word 0),
// each of loops short enough for llvmpipe's 65535 iterations an invocation:
//   0: an invocation per row scans its texels, leaving the row's sum;
//   1: an invocation per direction scans its rows' sums, leaving the direction's;
//   2: one invocation scans the directions' sums; the total goes to stats[STAT_LHB_LAYERS];
//   3: an invocation per row adds its direction's and its row's offsets to its texels.
// The filling pass then advances each texel's word past its layers: afterwards texel t's layers
// run from word t - 1 (0 for the first) to word t.

layout(local_size_x = 64, local_size_y = 1, local_size_z = 1) in;

#include "common/scene.glsl"
#include "common/textures.glsl"
#include "common/intersect.glsl"
#include "common/surface.glsl"
#include "lhb/lhb.glsl"

void main() {
    uint stage = pc.method_words[0];
    uint i = gl_GlobalInvocationID.x;
    uint r = lhb_resolution(), dirs = lhb_directions();
    if (stage == 0u || stage == 3u) {
        if (i >= dirs * r) return;
        uint row = i * r;
        if (stage == 0u) {
            uint sum = 0u;
            for (uint k = 0u; k < r; ++k) {
                uint c = LHB_WORK.v[row + k];
                LHB_WORK.v[row + k] = sum;
                sum += c;
            }
            LHB_WORK.v[lhb_row_sums_at() + i] = sum;
        } else {
            uint add = LHB_WORK.v[lhb_direction_sums_at() + i / r] + LHB_WORK.v[lhb_row_sums_at() + i];
            for (uint k = 0u; k < r; ++k) LHB_WORK.v[row + k] += add;
        }
    } else if (stage == 1u) {
        if (i >= dirs) return;
        uint sum = 0u;
        for (uint k = 0u; k < r; ++k) {
            uint at = lhb_row_sums_at() + i * r + k;
            uint c = LHB_WORK.v[at];
            LHB_WORK.v[at] = sum;
            sum += c;
        }
        LHB_WORK.v[lhb_direction_sums_at() + i] = sum;
    } else if (i == 0u) {
        uint sum = 0u;
        for (uint k = 0u; k < dirs; ++k) {
            uint at = lhb_direction_sums_at() + k;
            uint c = LHB_WORK.v[at];
            LHB_WORK.v[at] = sum;
            sum += c;
        }
        pc.g.stats.v[STAT_LHB_LAYERS] = sum;
    }
}
