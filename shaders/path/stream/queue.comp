#version 460
// Streaming path tracer (path/stream/stream.glsl): a queue's counter becomes the next kernels'
// indirect dispatch size and length, and is reset for the next iteration. Step 0 after
// compaction (the live queue), 1 after shading (the shadow rays and the ended slots).

layout(local_size_x = 1) in;

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
    if (queue_step() == 0u) {
        // After compaction: this iteration's live queue is complete.
        uint n = ctl.live_appended;
        ctl.live_appended = 0u;
        ctl.live_count = n;
        ctl.extend_args = uvec4((n + STREAM_GROUP - 1u) / STREAM_GROUP, 1u, 1u, 0u);
        if (n > 0u) ctl.iterations++;
    } else {
        // After shading: its shadow rays and ended slots.
        uint n = ctl.shadow_appended;
        ctl.shadow_appended = 0u;
        ctl.shadow_count = n;
        ctl.connect_args = uvec4((n + STREAM_GROUP - 1u) / STREAM_GROUP, 1u, 1u, 0u);
        n = ctl.ended_appended;
        ctl.ended_appended = 0u;
        ctl.ended_count = n;
        ctl.regenerate_args = uvec4((n + STREAM_GROUP - 1u) / STREAM_GROUP, 1u, 1u, 0u);
    }
}
