#version 460
// Layered hit buffers, a large triangle's blocks (raster.comp queued them): a workgroup per
// block of LHB_BLOCK x LHB_BLOCK texels from its first entry (push word 1), an invocation per
// texel, each testing its centre as raster.comp does.

layout(local_size_x = 16, local_size_y = 16, local_size_z = 1) in;

#include "common/scene.glsl"
#include "common/textures.glsl"
#include "common/intersect.glsl"
#include "common/surface.glsl"
#include "lhb/lhb.glsl"
#include "lhb/raster.glsl"

void main() {
    // Entries past 65535 continue on the dispatch's next row of workgroups.
    uint entry = lhb_first() + gl_WorkGroupID.y * gl_NumWorkGroups.x + gl_WorkGroupID.x;
    if (entry >= min(pc.g.stats.v[STAT_LHB_QUEUED], lhb_queue_capacity())) return;
    uint e = lhb_queue_at() + 4u * entry;
    uint placed = LHB_WORK.v[e], d = LHB_WORK.v[e + 1u];
    uvec2 texel = uvec2(LHB_WORK.v[e + 2u], LHB_WORK.v[e + 3u]) + gl_LocalInvocationID.xy;
    vec3 a, b, c;
    if (!lhb_projected(placed, d, a, b, c)) return;
    uvec4 box = lhb_box(a, b, c);
    if (texel.x >= box.z || texel.y >= box.w) return;
    float depth;
    uint r = lhb_resolution();
    if (lhb_covers(a, b, c, texel.x, texel.y, depth)) lhb_emit(d * r * r + texel.y * r + texel.x, depth, placed);
}
