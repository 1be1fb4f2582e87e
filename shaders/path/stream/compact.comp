#version 460
// Streaming path tracer, compaction (path/stream/stream.glsl): every live slot into the live
// queue, in slot order within each subgroup, so that a SIMD group of extend.comp traces the
// rays of neighbouring slots (whose first paths were neighbouring pixels').

layout(local_size_x = 64) in;

#include "common/scene.glsl"
#include "common/rng.glsl"
#include "common/sampling.glsl"
#include "common/textures.glsl"
#include "common/intersect.glsl"
#include "common/trace.glsl"
#include "common/surface.glsl"
#include "common/environment.glsl"
#include "common/bsdf.glsl"
#include "common/lights.glsl"
#include "path/path.glsl"
#include "path/stream/stream.glsl"

void main() {
    uint i = gl_GlobalInvocationID.x;
    if (i >= slot_count()) return;
    bool live = (slots[i].info.x & 3u) == SLOT_LIVE;
    uint at;
    QUEUE_APPEND(ctl.live_appended, live, at);
    if (live) queue[live_queue() + at] = i;
}
